//! One glTF primitive to one [`MeshData`]: attributes read through the
//! checked accessor reader, strips and fans unrolled, normals and tangents
//! made where the file has none; joint influences and morph targets
//! beside it ([`Deform`]).

use glam::Vec3;
use gltf::Semantic;
use gltf::mesh::Mode;

use super::deform::Deform;
use super::{GltfError, Importer};
use spreadlight_render::mesh::{Aabb, MeshData, Shading};

/// A primitive's mesh and, when its vertices were unwelded, each output
/// vertex's vertex in the file.
type Unwelded = (MeshData, Option<Vec<u32>>);

/// Whether some texture of `material` reads TEXCOORD_1: its texture info's
/// `texCoord`, or the `KHR_texture_transform` override that replaces it.
fn uses_second_uv_set(material: &gltf::Material) -> bool {
    let pbr = material.pbr_metallic_roughness();
    let info = |t: gltf::texture::Info| {
        t.texture_transform()
            .and_then(|x| x.tex_coord())
            .unwrap_or(t.tex_coord())
    };
    let overridden = |v: Option<&gltf::json::Value>, set: u32| {
        v.map(super::material::parse_transform)
            .and_then(|(_, over)| over)
            .unwrap_or(set)
    };
    let normal = material.normal_texture();
    let occlusion = material.occlusion_texture();
    [
        pbr.base_color_texture().map(info),
        pbr.metallic_roughness_texture().map(info),
        normal
            .as_ref()
            .map(|t| overridden(t.extension_value("KHR_texture_transform"), t.tex_coord())),
        occlusion
            .as_ref()
            .map(|t| overridden(t.extension_value("KHR_texture_transform"), t.tex_coord())),
        material.emissive_texture().map(info),
    ]
    .contains(&Some(1))
}

/// `stream[indices[k]]` for every k (indices already checked against the stream).
fn unweld_by<T: Copy>(stream: &[T], indices: &[u32]) -> Vec<T> {
    indices.iter().map(|&i| stream[i as usize]).collect()
}

/// "mesh 2 `Wheel`, primitive 1": how messages name a primitive.
pub(super) fn primitive_name(mesh: &gltf::Mesh, primitive: usize) -> String {
    match mesh.name() {
        Some(name) => format!("mesh {} `{name}`, primitive {primitive}", mesh.index()),
        None => format!("mesh {}, primitive {primitive}", mesh.index()),
    }
}

impl Importer<'_> {
    /// One primitive as a mesh and what deforms it, or `None` (with a
    /// warning) for points and lines.
    pub(super) fn primitive(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
    ) -> Result<Option<(MeshData, Deform)>, GltfError> {
        let Some((data, origin)) = self.primitive_mesh(mesh, primitive)? else {
            return Ok(None);
        };
        let name = primitive_name(mesh, primitive.index());
        // Attributes are per vertex of the file (POSITION's count, which
        // `primitive_mesh` read); `origin` maps unwelded ones back.
        let file_vertices = primitive
            .get(&Semantic::Positions)
            .map_or(data.positions.len(), |a| a.count());
        let origin = origin.as_deref();
        let influences =
            self.influences(&name, primitive, file_vertices, origin, &data.positions)?;
        let targets = self.morph_targets(&name, primitive, file_vertices, origin)?;
        Ok(Some((
            data,
            Deform {
                influences,
                targets,
            },
        )))
    }

    /// The primitive's mesh and, when its vertices were unwelded (flat
    /// normals), each output vertex's vertex in the file.
    fn primitive_mesh(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
    ) -> Result<Option<Unwelded>, GltfError> {
        let name = primitive_name(mesh, primitive.index());
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.warnings
                .push(format!("{name}: {mode:?} are not drawn; skipped"));
            return Ok(None);
        }
        let read = |semantic: Semantic| primitive.get(&semantic).map(|a| (semantic, a));
        let Some(positions) = read(Semantic::Positions) else {
            return Err(GltfError::Primitive {
                path: self.path.to_owned(),
                primitive: name,
                reason: "it has no POSITION attribute".into(),
            });
        };
        let positions: Vec<[f32; 3]> = self.floats(&name, positions)?;
        let vertices = positions.len();
        let normals: Option<Vec<[f32; 3]>> = read(Semantic::Normals)
            .map(|a| self.floats(&name, a))
            .transpose()?;
        let uvs: Option<Vec<[f32; 2]>> = read(Semantic::TexCoords(0))
            .map(|a| self.floats(&name, a))
            .transpose()?;
        let tangents: Option<Vec<[f32; 4]>> = read(Semantic::Tangents)
            .map(|a| self.floats(&name, a))
            .transpose()?;
        let uvs1: Option<Vec<[f32; 2]>> = read(Semantic::TexCoords(1))
            .map(|a| self.floats(&name, a))
            .transpose()?;
        if uvs1.is_none() && uses_second_uv_set(&primitive.material()) {
            self.warn(format!(
                "{name}: its material maps a texture with TEXCOORD_1, which it lacks; TEXCOORD_0 stands in"
            ));
        }
        let colors = read(Semantic::Colors(0))
            .map(|a| self.colors(&name, a))
            .transpose()?;

        let indices = match primitive.indices() {
            Some(a) => self.indices(&name, a)?,
            None => (0..vertices as u32).collect(),
        };
        let indices = self.triangle_list(&name, mode, indices);
        if indices.is_empty() {
            // Accessors of count 0 are valid glTF: nothing to draw.
            self.warn(format!("{name}: it has no triangles; skipped"));
            return Ok(None);
        }

        let mesh_error = |source| GltfError::Mesh {
            path: self.path.to_owned(),
            primitive: name.clone(),
            source,
        };
        let Some(normals) = normals else {
            // glTF: flat normals, and tangents in the file are ignored.
            // Streams are checked against the positions before unwelding.
            let mut data = MeshData {
                normals: vec![[0.0, 1.0, 0.0]; positions.len()],
                positions,
                uvs: None,
                tangents: None,
                uvs1,
                colors,
                indices,
                bounds: Aabb::ZERO,
            };
            data.recompute_bounds();
            data.validate().map_err(&mesh_error)?;
            let flat = MeshData::from_triangles(
                std::mem::take(&mut data.positions),
                uvs,
                data.indices.clone(),
                Shading::Flat,
            )
            .map_err(&mesh_error)?;
            // from_triangles gave each triangle corner its own vertex, in index order.
            let mesh = MeshData {
                uvs1: data.uvs1.as_deref().map(|s| unweld_by(s, &data.indices)),
                colors: data.colors.as_deref().map(|s| unweld_by(s, &data.indices)),
                ..flat
            };
            return Ok(Some((mesh, Some(data.indices))));
        };
        let normals = normals
            .into_iter()
            .map(|n| Vec3::from(n).try_normalize().map_or(n, |n| n.to_array()))
            .collect();
        let tangents = tangents.map(|t| {
            t.into_iter()
                .map(|[x, y, z, w]| [x, y, z, if w < 0.0 { -1.0 } else { 1.0 }])
                .collect()
        });
        let mut data = MeshData {
            positions,
            normals,
            uvs,
            tangents,
            uvs1,
            colors,
            indices,
            bounds: Aabb::ZERO,
        };
        data.recompute_bounds();
        if data.tangents.is_none() && data.uvs.is_some() {
            data.generate_tangents().map_err(mesh_error)?;
        }
        data.validate().map_err(mesh_error)?;
        Ok(Some((data, None)))
    }

    /// Triangle strips and fans unrolled into a list (glTF's vertex order,
    /// which keeps every triangle's winding); a list cut short loses its
    /// last partial triangle, with a warning.
    fn triangle_list(&mut self, name: &str, mode: Mode, indices: Vec<u32>) -> Vec<u32> {
        let n = indices.len();
        match mode {
            Mode::TriangleStrip => (0..n.saturating_sub(2))
                .flat_map(|i| {
                    let (a, b, c) = if i % 2 == 0 {
                        (i, i + 1, i + 2)
                    } else {
                        (i, i + 2, i + 1)
                    };
                    [indices[a], indices[b], indices[c]]
                })
                .collect(),
            Mode::TriangleFan => (1..n.saturating_sub(1))
                .flat_map(|i| [indices[i], indices[i + 1], indices[0]])
                .collect(),
            _ => {
                let mut indices = indices;
                if !n.is_multiple_of(3) {
                    self.warnings.push(format!(
                        "{name}: {n} indices is not a whole number of triangles; the last {} are dropped",
                        n % 3
                    ));
                    indices.truncate(n - n % 3);
                }
                indices
            }
        }
    }

    fn floats<const N: usize>(
        &self,
        primitive: &str,
        (semantic, accessor): (Semantic, gltf::Accessor),
    ) -> Result<Vec<[f32; N]>, GltfError> {
        self.buffers.read_floats::<N>(&accessor).map_err(|reason| {
            self.accessor_error(&accessor, &semantic.to_string(), primitive, reason)
        })
    }

    /// COLOR_0 as linear RGBA: VEC3 gets alpha 1; unsigned byte and short
    /// components are normalised (glTF requires them to be).
    fn colors(
        &self,
        primitive: &str,
        (semantic, accessor): (Semantic, gltf::Accessor),
    ) -> Result<Vec<[f32; 4]>, GltfError> {
        let read = match accessor.dimensions() {
            gltf::accessor::Dimensions::Vec3 => self
                .buffers
                .read_floats::<3>(&accessor)
                .map(|v| v.into_iter().map(|[r, g, b]| [r, g, b, 1.0]).collect()),
            _ => self.buffers.read_floats::<4>(&accessor),
        };
        read.map_err(|reason| {
            self.accessor_error(&accessor, &semantic.to_string(), primitive, reason)
        })
    }

    fn indices(&self, primitive: &str, accessor: gltf::Accessor) -> Result<Vec<u32>, GltfError> {
        self.buffers
            .read_indices(&accessor)
            .map_err(|reason| self.accessor_error(&accessor, "indices", primitive, reason))
    }

    pub(super) fn accessor_error(
        &self,
        accessor: &gltf::Accessor,
        usage: &str,
        primitive: &str,
        reason: String,
    ) -> GltfError {
        GltfError::Accessor {
            path: self.path.to_owned(),
            index: accessor.index(),
            usage: format!("{usage} of {primitive}"),
            reason,
        }
    }
}

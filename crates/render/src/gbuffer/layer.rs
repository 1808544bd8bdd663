//! A layer: what one `DeferredBase` node draws — instanced meshes and the
//! feature switches its resolve permutation is compiled with.

use std::sync::Arc;

use glam::Mat4;
use thiserror::Error;

use super::resolve_key::{ResolveKey, SurfaceOut, SurfaceResolve, Uv, Written};
use super::surface_shader::SurfaceShader;
use crate::material::MaterialWorld;
use crate::mesh_arena::GpuMesh;
use crate::recipe::TextureRef;

/// Where velocity comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VelocitySource {
    /// From this and last frame's transforms (rigid motion).
    #[default]
    Transforms,
    /// From the mesh's previous-frame positions as well (deforming geometry).
    Geometry,
    /// None: velocity is zero.
    Off,
}

/// The DeferredBase switches (Emeshe's `#define`s), each a shader feature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct LayerFeatures {
    /// Write the mesh's texture coordinates (the UV target).
    pub texcoords: bool,
    /// Perturb normals with the layer's normal map (needs UVs and tangents, or triplanar, which needs neither).
    pub normal_map: bool,
    /// Texture coordinates projected from world position, for geometry without UVs.
    pub triplanar: bool,
    pub velocity: VelocitySource,
    /// Write object and material ids (otherwise 0).
    pub ids: bool,
    /// Emeshe's "Instance from GeomFX": add each triangle's geometry id (its
    /// first vertex's `previous_position.w`, written by GPU geometry and
    /// particles) to the object id, for per-virtual-instance parameters.
    pub geometry_ids: bool,
    /// Triplanar: the exponent of the normal's components that weights the
    /// three projections its Color and Normal Textures blend (1: wide
    /// blends; larger: narrower ones). A uniform, not a permutation.
    pub triplanar_sharpness: u32,
}

/// The default blend sharpness of triplanar mapping.
pub const TRIPLANAR_SHARPNESS: u32 = 4;

impl Default for LayerFeatures {
    fn default() -> Self {
        LayerFeatures {
            texcoords: false,
            normal_map: false,
            triplanar: false,
            velocity: VelocitySource::default(),
            ids: false,
            geometry_ids: false,
            triplanar_sharpness: TRIPLANAR_SHARPNESS,
        }
    }
}

impl LayerFeatures {
    /// The resolve adds each triangle's geometry id to the object id (a
    /// uniform flag, not a permutation: the runs of alike layers compare it).
    pub(crate) fn adds_geometry_ids(&self) -> bool {
        self.ids && self.geometry_ids
    }

    /// The resolve's permutation for the surface (color, normals) pass, from the switches alone.
    fn surface_key(&self) -> ResolveKey {
        ResolveKey {
            normal_map: self.normal_map,
            // A normal map needs coordinates even with both switches off:
            // the mesh's own UVs (`Layer::new` checked it has them), never
            // one texel for the whole surface.
            uv: match self.normal_map {
                true => self.uv().or(Uv::Mesh),
                false => Uv::None,
            },
            ..ResolveKey::surface(SurfaceResolve::default())
        }
    }

    /// The resolve's permutation for the motion (velocity, UV) pass.
    pub(crate) fn motion_key(&self) -> ResolveKey {
        ResolveKey {
            // The UVs the surface pass reads (a normal map reads the mesh's
            // even with both switches off), so one dispatch for both writes the same.
            uv: match self.normal_map {
                true => self.uv().or(Uv::Mesh),
                false => self.uv(),
            },
            velocity_from_geometry: self.velocity == VelocitySource::Geometry,
            ..ResolveKey::motion()
        }
    }

    /// The texture coordinates the switches ask for.
    pub(crate) fn uv(&self) -> Uv {
        if self.texcoords {
            Uv::Mesh
        } else if self.triplanar {
            Uv::Triplanar
        } else {
            Uv::None
        }
    }
}

/// One instance of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InstanceInput {
    pub transform: Mat4,
    /// Last frame's transform (for velocity); the same as `transform` when static.
    pub previous_transform: Mat4,
    pub color: [f32; 4],
    pub material_id: u32,
    pub object_id: u32,
}

/// A mesh drawn once per instance.
#[derive(Clone, Debug)]
pub struct DrawBatch {
    pub mesh: Arc<GpuMesh>,
    pub instances: Vec<InstanceInput>,
}

/// A switch the geometry cannot serve: an error on the DeferredBase node, not a broken image.
#[derive(Debug, Error, PartialEq)]
pub enum LayerError {
    #[error("Normal Mapping is on but no normal texture is connected")]
    NoNormalTexture,
    #[error(
        "{switch} needs texture coordinates, but mesh slice {mesh} has none (switch on Triplanar, or use a mesh with UVs)"
    )]
    NoTexcoords { switch: &'static str, mesh: usize },
    #[error(
        "a Color Texture needs texture coordinates: switch on Texture Coordinates or Triplanar"
    )]
    ColorMapWithoutUvs,
    #[error("Normal Mapping needs tangents, but mesh slice {mesh} has none")]
    NoTangents { mesh: usize },
    #[error(
        "Velocity from geometry needs previous-frame positions, but mesh slice {mesh} has none"
    )]
    NoPreviousPositions { mesh: usize },
}

/// What a DeferredBase node outputs.
#[derive(Clone, Debug)]
pub struct Layer {
    pub owner: Option<u32>,
    pub batches: Vec<DrawBatch>,
    pub features: LayerFeatures,
    pub normal_map: Option<TextureRef>,
    /// Multiplies the instances' colour (albedo) at the surface's UV.
    pub color_map: Option<TextureRef>,
    /// The material world the instances' material ids index, when the
    /// resolve must read it: glTF surface maps (MATERIAL_MAPS).
    pub materials: Option<Arc<MaterialWorld>>,
    /// A shader node material: its `surface` function shades the layer's
    /// pixels in the resolve (CUSTOM_SURFACE), in place of surface maps.
    pub surface: Option<Arc<SurfaceShader>>,
}

impl Layer {
    /// A layer, if its meshes can serve its switches.
    pub fn new(
        owner: Option<u32>,
        batches: Vec<DrawBatch>,
        features: LayerFeatures,
        normal_map: Option<TextureRef>,
    ) -> Result<Self, LayerError> {
        if features.normal_map && normal_map.is_none() {
            return Err(LayerError::NoNormalTexture);
        }
        for (mesh, batch) in batches.iter().enumerate() {
            if features.texcoords && !batch.mesh.has_uvs {
                return Err(LayerError::NoTexcoords {
                    switch: "Texture Coordinates",
                    mesh,
                });
            }
            if features.normal_map && !features.triplanar && !batch.mesh.has_uvs {
                return Err(LayerError::NoTexcoords {
                    switch: "Normal Mapping",
                    mesh,
                });
            }
            // Triplanar normal mapping needs no tangents: each projection's
            // axes are its frame (resolve.wgsl's whiteout blend).
            if features.normal_map && !features.triplanar && !batch.mesh.has_tangents {
                return Err(LayerError::NoTangents { mesh });
            }
            if features.velocity == VelocitySource::Geometry && !batch.mesh.has_previous_positions {
                return Err(LayerError::NoPreviousPositions { mesh });
            }
        }
        Ok(Layer {
            owner,
            features,
            normal_map,
            ..Layer::plain(batches)
        })
    }

    /// A layer with no feature switches and no owner: it asks nothing of
    /// its meshes, so unlike `new` it cannot fail.
    pub fn plain(batches: Vec<DrawBatch>) -> Self {
        Layer {
            owner: None,
            batches,
            features: LayerFeatures::default(),
            normal_map: None,
            color_map: None,
            materials: None,
            surface: None,
        }
    }

    /// The layer with the material world its ids index: with surface maps,
    /// the resolve samples them (albedo, normals, and the surface target).
    pub fn with_materials(mut self, materials: Option<Arc<MaterialWorld>>) -> Self {
        self.materials = materials;
        self
    }

    /// The layer shaded by a shader node material's `surface` function
    /// (which then replaces the world's surface maps).
    pub fn with_surface(mut self, surface: Option<Arc<SurfaceShader>>) -> Self {
        self.surface = surface;
        self
    }

    /// Whether the surface resolve shares a dispatch with alike layers
    /// beside it: not with maps, a material world or a shader material,
    /// which bind their own.
    pub(crate) fn resolves_with_others(&self) -> bool {
        self.surface.is_none() && self.maps().next().is_none() && self.map_world().is_none()
    }

    /// The world, when its surface maps are sampled by this layer (never
    /// under a shader node material, which shades the surface itself).
    pub(crate) fn map_world(&self) -> Option<&Arc<MaterialWorld>> {
        self.materials
            .as_ref()
            .filter(|w| w.has_maps() && self.surface.is_none())
    }

    /// Whether some instance's material is alpha-tested (MASK): the
    /// visibility pass discards its pixels below the cutoff.
    pub fn alpha_masked(&self) -> bool {
        let Some(world) = self.map_world() else {
            return false;
        };
        self.batches
            .iter()
            .flat_map(|b| &b.instances)
            .any(|i| world.alpha_masked(i.material_id))
    }

    /// Whether some instance's material is double-sided (drawn without back-face culling).
    pub fn double_sided(&self) -> bool {
        let Some(world) = self.map_world() else {
            return false;
        };
        self.batches
            .iter()
            .flat_map(|b| &b.instances)
            .any(|i| world.double_sided(i.material_id))
    }

    /// The layer with `map` scaling its colour at each pixel's texture
    /// coordinates (Texture Coordinates or Triplanar must be on).
    pub fn with_color_map(mut self, map: Option<TextureRef>) -> Result<Self, LayerError> {
        if map.is_some() && !self.features.texcoords && !self.features.triplanar {
            return Err(LayerError::ColorMapWithoutUvs);
        }
        self.color_map = map;
        Ok(self)
    }

    /// The resolve's permutation for the surface (color, normals) pass.
    pub(crate) fn surface_key(&self) -> ResolveKey {
        let mut key = self.features.surface_key();
        // A Color Texture, and a shader node material (its `uv` is the
        // layer's texture coordinates, docs/shader-nodes.md, maps or not),
        // read the switches' UVs where a normal map did not choose them.
        if self.color_map.is_some() || self.surface.is_some() {
            key.uv = key.uv.or(self.features.uv());
        }
        let surface = if self.surface.is_some() {
            Some(SurfaceOut::Custom)
        } else {
            // The extensions' maps (coat, specular) only where the world has one.
            self.map_world().map(|w| {
                if w.has_extension_maps() {
                    SurfaceOut::ExtendedMaps
                } else {
                    SurfaceOut::MaterialMaps
                }
            })
        };
        // The anisotropy target, where this layer's maps world has an
        // Anisotropy material (never under a shader node material).
        let anisotropy = self.map_world().is_some_and(|w| w.has_anisotropy());
        // The sheen and film target, where this layer's maps world has a
        // sheen or iridescence map.
        let sheen_film = self.map_world().is_some_and(|w| w.has_sheen_film_maps());
        key.written = Written::Surface(SurfaceResolve {
            color_map: self.color_map.is_some(),
            vertex_extras: self.vertex_extras(),
            velocity: false,
            surface,
            anisotropy,
            sheen_film,
        });
        key
    }

    /// The resolve's permutation for the surface and motion passes in one
    /// dispatch: the surface's, the motion pass's texture coordinates (which
    /// the surface's equal where the surface reads any) and velocity from
    /// geometry, writing velocity and UVs beside the surface (VELOCITY_OUT).
    pub(crate) fn fused_key(&self) -> ResolveKey {
        let mut key = self.surface_key();
        let motion = self.features.motion_key();
        key.uv = key.uv.or(motion.uv);
        key.velocity_from_geometry = motion.velocity_from_geometry;
        if let Written::Surface(s) = &mut key.written {
            s.velocity = true;
        }
        key
    }

    /// The textures its shader node material reads: its texture inputs,
    /// then the material world's texture array where it reads the world
    /// ([`Layer::library_textures`]).
    pub(crate) fn surface_textures(&self) -> impl Iterator<Item = &TextureRef> {
        self.surface
            .iter()
            .flat_map(|s| &s.textures)
            .chain(self.library_textures())
    }

    /// The world a shader node material reads through `spreadlight::materials`.
    pub(crate) fn library_world(&self) -> Option<&Arc<MaterialWorld>> {
        self.surface.as_ref().filter(|s| s.reads_materials)?;
        self.materials.as_ref()
    }

    /// That world's texture array, when some material of it reads one.
    pub(crate) fn library_textures(&self) -> Option<&TextureRef> {
        self.library_world()?.textures()
    }

    /// Whether the surface pass reads the arena's extra stream: some mesh
    /// has vertex colours, or a second UV set that surface maps may read.
    pub(crate) fn vertex_extras(&self) -> bool {
        let maps = self.map_world().is_some();
        self.batches
            .iter()
            .any(|b| b.mesh.has_colors || (maps && b.mesh.has_uvs1))
    }

    /// The textures its surface pass samples (a normal texture only while Normal Mapping is on).
    pub(crate) fn maps(&self) -> impl Iterator<Item = &TextureRef> {
        self.normal_map
            .iter()
            .filter(|_| self.features.normal_map)
            .chain(&self.color_map)
    }
}

#[cfg(test)]
mod tests {
    use super::super::resolve_key::{ResolveKey, SurfaceResolve, Uv};
    use super::LayerFeatures;

    #[test]
    fn a_normal_map_reads_the_meshes_uvs_even_with_the_uv_switches_off() {
        let features = LayerFeatures {
            normal_map: true,
            ..LayerFeatures::default()
        };
        let surface = |uv| ResolveKey {
            uv,
            normal_map: true,
            ..ResolveKey::surface(SurfaceResolve::default())
        };
        assert_eq!(features.surface_key(), surface(Uv::Mesh));
        let triplanar = LayerFeatures {
            triplanar: true,
            ..features
        };
        assert_eq!(triplanar.surface_key(), surface(Uv::Triplanar));
        // The motion pass writes the UVs the surface pass read, so the two in
        // one dispatch write what each writes alone.
        let motion = |uv| ResolveKey {
            uv,
            ..ResolveKey::motion()
        };
        assert_eq!(features.motion_key(), motion(Uv::Mesh));
        assert_eq!(triplanar.motion_key(), motion(Uv::Triplanar));
        assert_eq!(LayerFeatures::default().motion_key(), motion(Uv::None));
    }
}

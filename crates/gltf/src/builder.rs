//! glTF files written in code (tests, generated benchmark scenes: nothing
//! is downloaded): a gltf-json document builder with one binary buffer that
//! is finished as a `.gltf` with a data URI, a `.gltf` with an external
//! `.bin`, or a `.glb`.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use gltf::json;
use json::accessor::{ComponentType, GenericComponentType, Type};
use json::mesh::{Mode, Semantic};
use json::validation::Checked::Valid;
use json::validation::USize64;
use json::{Index, Root};

/// A glTF document under construction and the bytes of its one buffer.
pub struct Doc {
    pub root: Root,
    pub bin: Vec<u8>,
}

/// The raw little-endian bytes of `values`.
pub fn bytes<T: bytemuck::Pod>(values: &[T]) -> Vec<u8> {
    bytemuck::cast_slice(values).to_vec()
}

impl Doc {
    pub fn new() -> Doc {
        let mut root = Root::default();
        root.buffers.push(json::Buffer {
            byte_length: USize64(0),
            extensions: None,
            extras: Default::default(),
            name: None,
            uri: None,
        });
        Doc {
            root,
            bin: Vec::new(),
        }
    }

    /// Appends `data` (4-byte aligned) to the buffer as a new buffer view.
    pub fn view(&mut self, data: &[u8]) -> Index<json::buffer::View> {
        self.pad();
        let offset = self.bin.len();
        self.bin.extend_from_slice(data);
        self.root.push(json::buffer::View {
            buffer: Index::new(0),
            byte_length: USize64::from(data.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: None,
            extensions: None,
            extras: Default::default(),
            name: None,
            target: None,
        })
    }

    pub fn accessor(
        &mut self,
        view: Option<Index<json::buffer::View>>,
        count: usize,
        component: ComponentType,
        type_: Type,
    ) -> Index<json::Accessor> {
        self.root.push(json::Accessor {
            buffer_view: view,
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(GenericComponentType(component)),
            extensions: None,
            extras: Default::default(),
            type_: Valid(type_),
            min: None,
            max: None,
            name: None,
            normalized: false,
            sparse: None,
        })
    }

    /// A POSITION accessor, with the min and max glTF requires.
    pub fn positions(&mut self, p: &[[f32; 3]]) -> Index<json::Accessor> {
        let view = self.view(&bytes(p));
        let a = self.accessor(Some(view), p.len(), ComponentType::F32, Type::Vec3);
        let (mut min, mut max) = ([f32::MAX; 3], [f32::MIN; 3]);
        for v in p {
            for k in 0..3 {
                min[k] = min[k].min(v[k]);
                max[k] = max[k].max(v[k]);
            }
        }
        let acc = &mut self.root.accessors[a.value()];
        acc.min = Some(json::Value::from(min.to_vec()));
        acc.max = Some(json::Value::from(max.to_vec()));
        a
    }

    pub fn floats<const N: usize>(&mut self, v: &[[f32; N]]) -> Index<json::Accessor> {
        let type_ = match N {
            2 => Type::Vec2,
            3 => Type::Vec3,
            _ => Type::Vec4,
        };
        let view = self.view(&bytes(v.as_flattened()));
        self.accessor(Some(view), v.len(), ComponentType::F32, type_)
    }

    pub fn indices(&mut self, i: &[u16]) -> Index<json::Accessor> {
        let view = self.view(&bytes(i));
        self.accessor(Some(view), i.len(), ComponentType::U16, Type::Scalar)
    }

    pub fn mesh(
        &mut self,
        name: &str,
        primitives: Vec<json::mesh::Primitive>,
    ) -> Index<json::Mesh> {
        self.root.push(json::Mesh {
            extensions: None,
            extras: Default::default(),
            name: Some(name.into()),
            primitives,
            weights: None,
        })
    }

    pub fn node(&mut self, node: json::Node) -> Index<json::Node> {
        self.root.push(node)
    }

    pub fn scene(&mut self, nodes: Vec<Index<json::Node>>) -> Index<json::Scene> {
        self.root.push(json::Scene {
            extensions: None,
            extras: Default::default(),
            name: None,
            nodes,
        })
    }

    /// A mesh from a finished [`MeshData`](spreadlight_render::mesh::MeshData): positions,
    /// normals, UVs, a second UV set and vertex colours when it has them (no
    /// tangents) and u16 indices.
    pub fn mesh_data(
        &mut self,
        name: &str,
        m: &spreadlight_render::mesh::MeshData,
    ) -> Index<json::Mesh> {
        let mut attributes = vec![
            (Semantic::Positions, self.positions(&m.positions)),
            (Semantic::Normals, self.floats(&m.normals)),
        ];
        if let Some(uvs) = &m.uvs {
            attributes.push((Semantic::TexCoords(0), self.floats(uvs)));
        }
        if let Some(uvs) = &m.uvs1 {
            attributes.push((Semantic::TexCoords(1), self.floats(uvs)));
        }
        if let Some(colors) = &m.colors {
            attributes.push((Semantic::Colors(0), self.floats(colors)));
        }
        let indices: Vec<u16> = m.indices.iter().map(|&i| i as u16).collect();
        let indices = self.indices(&indices);
        self.mesh(
            name,
            vec![primitive(&attributes, Some(indices), Mode::Triangles)],
        )
    }

    fn pad(&mut self) {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
    }

    fn finish_buffer(&mut self, uri: Option<String>) {
        self.pad();
        let buffer = &mut self.root.buffers[0];
        buffer.byte_length = USize64::from(self.bin.len());
        buffer.uri = uri;
    }

    /// A `.gltf` whose buffer is a base64 data URI.
    pub fn gltf_data_uri(mut self) -> Vec<u8> {
        self.pad();
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
        self.finish_buffer(Some(uri));
        json::serialize::to_vec(&self.root).expect("a glTF document serializes")
    }

    /// `name` in `dir`, its buffer referred to by `uri`; the buffer is
    /// written to `bin_file` in `dir` when given.
    pub fn gltf_external(
        mut self,
        dir: &Path,
        name: &str,
        uri: &str,
        bin_file: Option<&str>,
    ) -> PathBuf {
        self.finish_buffer(Some(uri.into()));
        if let Some(bin_file) = bin_file {
            std::fs::write(dir.join(bin_file), &self.bin).expect("write bin");
        }
        let path = dir.join(name);
        std::fs::write(
            &path,
            json::serialize::to_vec_pretty(&self.root).expect("serialize"),
        )
        .expect("write gltf");
        path
    }

    /// A `.glb` with the buffer as its BIN chunk.
    pub fn glb(mut self) -> Vec<u8> {
        self.finish_buffer(None);
        let mut json = json::serialize::to_vec(&self.root).expect("serialize");
        json.resize(json.len().next_multiple_of(4), b' ');
        let total = 12 + 8 + json.len() + 8 + self.bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend(json);
        out.extend((self.bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend(&self.bin);
        out
    }
}

impl Default for Doc {
    fn default() -> Self {
        Self::new()
    }
}

impl Doc {
    /// An image stored in a buffer view (PNG bytes).
    pub fn png_image(&mut self, png: &[u8]) -> Index<json::Image> {
        let view = self.view(png);
        self.root.push(json::Image {
            buffer_view: Some(view),
            mime_type: Some(json::image::MimeType("image/png".into())),
            name: None,
            uri: None,
            extensions: None,
            extras: Default::default(),
        })
    }

    /// A texture of `image` with glTF's default sampler.
    pub fn texture(&mut self, image: Index<json::Image>) -> Index<json::Texture> {
        self.root.push(json::Texture {
            name: None,
            sampler: None,
            source: image,
            extensions: None,
            extras: Default::default(),
        })
    }

    pub fn material(&mut self, material: json::Material) -> Index<json::Material> {
        self.root.push(material)
    }

    /// A sampler that magnifies NEAREST (glTF's defaults otherwise), so a
    /// small test texture's regions stay sharp when magnified.
    pub fn nearest_sampler(&mut self) -> Index<json::texture::Sampler> {
        self.root.push(json::texture::Sampler {
            mag_filter: Some(Valid(json::texture::MagFilter::Nearest)),
            ..Default::default()
        })
    }

    /// A texture of `png` sampled by a [`Doc::nearest_sampler`] of its own.
    pub fn nearest_texture(&mut self, png: &[u8]) -> Index<json::Texture> {
        let image = self.png_image(png);
        let texture = self.texture(image);
        let sampler = self.nearest_sampler();
        self.root.textures[texture.value()].sampler = Some(sampler);
        texture
    }

    /// The document's scene: one node holding `mesh`, whose primitives
    /// take `material`.
    pub fn mesh_scene(&mut self, mesh: Index<json::Mesh>, material: Index<json::Material>) {
        for primitive in &mut self.root.meshes[mesh.value()].primitives {
            primitive.material = Some(material);
        }
        let node = self.node(json::Node {
            mesh: Some(mesh),
            ..Default::default()
        });
        self.scene(vec![node]);
    }

    /// The file's `KHR_lights_punctual` lights, which [`light_node`]s name by index.
    pub fn punctual_lights(
        &mut self,
        lights: Vec<json::extensions::scene::khr_lights_punctual::Light>,
    ) {
        self.root.extensions_used.push("KHR_lights_punctual".into());
        self.root.extensions = Some(json::extensions::root::Root {
            khr_lights_punctual: Some(json::extensions::root::KhrLightsPunctual { lights }),
            ..Default::default()
        });
    }
}

/// A node carrying light `index` of the file's [`Doc::punctual_lights`],
/// at the origin: set its translation and rotation over it.
pub fn light_node(index: u32) -> json::Node {
    json::Node {
        extensions: Some(json::extensions::scene::Node {
            khr_lights_punctual: Some(
                json::extensions::scene::khr_lights_punctual::KhrLightsPunctual {
                    light: json::Index::new(index),
                },
            ),
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// A texture reference on TEXCOORD_0.
pub fn info(texture: Index<json::Texture>) -> json::texture::Info {
    json::texture::Info {
        index: texture,
        tex_coord: 0,
        extensions: None,
        extras: Default::default(),
    }
}

/// `image` encoded as PNG.
pub fn png(image: &image::RgbaImage) -> Vec<u8> {
    use image::ImageEncoder;
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Best, FilterType::Adaptive)
        .write_image(
            image.as_raw(),
            image.width(),
            image.height(),
            image::ExtendedColorType::Rgba8,
        )
        .expect("PNG encoding to memory cannot fail");
    out
}

pub fn primitive(
    attributes: &[(Semantic, Index<json::Accessor>)],
    indices: Option<Index<json::Accessor>>,
    mode: Mode,
) -> json::mesh::Primitive {
    json::mesh::Primitive {
        attributes: attributes
            .iter()
            .map(|(s, a)| (Valid(s.clone()), *a))
            .collect::<BTreeMap<_, _>>(),
        extensions: None,
        extras: Default::default(),
        indices,
        material: None,
        mode: Valid(mode),
        targets: None,
    }
}

/// A node holding `mesh`, placed by translation and uniform scale.
pub fn mesh_node(mesh: Option<Index<json::Mesh>>, translation: [f32; 3], scale: f32) -> json::Node {
    json::Node {
        mesh,
        translation: Some(translation),
        scale: Some([scale; 3]),
        ..Default::default()
    }
}

/// The UVs of [`quad`]: spanning the texture, v down.
pub const QUAD_UVS: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];

/// The quad x, y in [-1, 1] at z = 0, facing +Z, corners counter-clockwise
/// from (-1, -1), [`QUAD_UVS`] spanning it, no second UV set or colours
/// (set them over it: the bounds hold only the positions).
pub fn quad() -> spreadlight_render::mesh::MeshData {
    let mut quad = spreadlight_render::mesh::MeshData {
        positions: vec![
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
        ],
        normals: vec![[0.0, 0.0, 1.0]; 4],
        uvs: Some(QUAD_UVS.to_vec()),
        tangents: None,
        uvs1: None,
        colors: None,
        indices: vec![0, 1, 2, 0, 2, 3],
        bounds: spreadlight_render::mesh::Aabb::ZERO,
    };
    quad.recompute_bounds();
    quad
}

/// A 2 x 2 RGBA PNG: red, green / blue, white.
pub fn png_2x2() -> Vec<u8> {
    let pixels = vec![
        255, 0, 0, 255, 0, 255, 0, 255, //
        0, 0, 255, 255, 255, 255, 255, 255,
    ];
    png(&image::RgbaImage::from_raw(2, 2, pixels).expect("2x2 pixels"))
}

fn base64(data: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in data.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

//! glTF 2.0 import: `.gltf` (external or data-URI buffers and images) and
//! `.glb`, into [`MeshData`], [`MaterialData`] and world-space
//! [`MeshInstance`]s of one scene.
//!
//! The `gltf` crate parses and validates the JSON (every index in range,
//! every enum known); the bytes are ours to check. Its own buffer import and
//! accessor readers trust the file (slices that can go out of range,
//! `unwrap`s on URIs, debug assertions on strides), so this module reads the
//! GLB container, URIs and accessors itself, with checked arithmetic
//! throughout: no input makes it panic, and every error names the file.
//!
//! What it does with what glTF allows:
//! - one primitive becomes one [`MeshData`]; a mesh with several primitives
//!   gives several meshes and, per node, several instances;
//! - the default scene is loaded, else the first, else every root node;
//! - triangle strips and fans become lists; points and lines are skipped
//!   with a warning in [`GltfScene::warnings`];
//! - missing normals are made flat (what the glTF spec asks), and then any
//!   tangents in the file are dropped (ditto); missing tangents are made
//!   with MikkTSpace when there are texture coordinates;
//! - only `TEXCOORD_0` is read; textures using another set, skins, morph
//!   targets and animations are reported as warnings and ignored;
//! - no extension can be required: a file listing any in
//!   `extensionsRequired` is refused with a [`GltfError`] naming it.

mod accessor;
mod material;
mod primitive;
mod scene;
mod source;
#[cfg(test)]
mod test_files;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Mat4;
use gltf::{Document, Semantic};
use thiserror::Error;

use super::{Aabb, MeshData, MeshError};
use accessor::Buffers;

/// Everything loaded from one glTF file.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfScene {
    /// One per triangle primitive of the file, in file order (mesh, then primitive).
    pub meshes: Vec<MeshData>,
    /// Every material of the file, in file order (so glTF material indices hold).
    pub materials: Vec<MaterialData>,
    /// One per (node, primitive) of the loaded scene.
    pub instances: Vec<MeshInstance>,
    /// World bounds of all instances ([`Aabb::ZERO`] when there are none).
    pub bounds: Aabb,
    /// What was skipped or ignored; the rest of the file loaded.
    pub warnings: Vec<String>,
}

/// A mesh placed in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshInstance {
    /// Index into [`GltfScene::meshes`].
    pub mesh: usize,
    /// World transform: the node hierarchy applied.
    pub transform: Mat4,
    /// Index into [`GltfScene::materials`]; `None` means glTF's default material.
    pub material: Option<usize>,
}

/// How a material's alpha is used.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    #[default]
    Opaque,
    /// Alpha below `cutoff` is discarded, the rest is opaque.
    Mask {
        cutoff: f32,
    },
    Blend,
}

/// A glTF metallic-roughness material. Factors are linear; texture colours
/// are as stored (see [`TextureData::srgb`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialData {
    pub name: Option<String>,
    pub base_color: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    pub emissive: [f32; 3],
    pub base_color_texture: Option<TextureData>,
    /// Roughness in green, metalness in blue.
    pub metallic_roughness_texture: Option<TextureData>,
    pub normal_texture: Option<TextureData>,
    /// Scales the normal map's x and y.
    pub normal_scale: f32,
    /// Occlusion in red.
    pub occlusion_texture: Option<TextureData>,
    /// How much of the occlusion texture applies (0..=1).
    pub occlusion_strength: f32,
    pub emissive_texture: Option<TextureData>,
    pub double_sided: bool,
    pub alpha_mode: AlphaMode,
}

impl Default for MaterialData {
    /// glTF's defaults for every property.
    fn default() -> Self {
        Self {
            name: None,
            base_color: [1.0; 4],
            metallic: 1.0,
            roughness: 1.0,
            emissive: [0.0; 3],
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive_texture: None,
            double_sided: false,
            alpha_mode: AlphaMode::Opaque,
        }
    }
}

/// A decoded texture image, 8 bits per channel, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureData {
    pub width: u32,
    pub height: u32,
    pub rgba8: Vec<u8>,
    /// True for colour (base colour, emissive): sample through an sRGB format.
    pub srgb: bool,
}

/// Why a glTF file cannot be loaded. Every message starts with the file.
#[derive(Debug, Error)]
pub enum GltfError {
    #[error("{path}: cannot read the file: {source}")]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: not a valid binary glTF (.glb): {reason}")]
    Glb { path: PathBuf, reason: String },
    #[error("{path}: malformed glTF JSON: {message}")]
    Json { path: PathBuf, message: String },
    #[error("{path}: invalid glTF: {message}")]
    Invalid { path: PathBuf, message: String },
    #[error(
        "{path}: requires the glTF extension `{extension}`, which Spreadlight does not support"
    )]
    UnsupportedExtension { path: PathBuf, extension: String },
    #[error("{path}: {what} refers to `{}`, which cannot be read: {source}", file.display())]
    MissingFile {
        path: PathBuf,
        what: String,
        file: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {what}: {reason}")]
    Uri {
        path: PathBuf,
        what: String,
        reason: String,
    },
    #[error("{path}: buffer {index}: {reason}")]
    Buffer {
        path: PathBuf,
        index: usize,
        reason: String,
    },
    #[error("{path}: accessor {index} ({usage}): {reason}")]
    Accessor {
        path: PathBuf,
        index: usize,
        usage: String,
        reason: String,
    },
    #[error("{path}: image {index}: {reason}")]
    Image {
        path: PathBuf,
        index: usize,
        reason: String,
    },
    #[error("{path}: {primitive}: {reason}")]
    Primitive {
        path: PathBuf,
        primitive: String,
        reason: String,
    },
    #[error("{path}: {primitive}: {source}")]
    Mesh {
        path: PathBuf,
        primitive: String,
        source: MeshError,
    },
}

/// Loads a `.gltf` or `.glb` file (told apart by content, not extension);
/// external files resolve next to it.
pub fn load_gltf(path: &Path) -> Result<GltfScene, GltfError> {
    let bytes = std::fs::read(path).map_err(|source| GltfError::Read {
        path: path.to_owned(),
        source,
    })?;
    let base_dir = path.parent().unwrap_or(Path::new("."));
    load(&bytes, Some(base_dir), path)
}

/// Loads glTF from bytes. External files resolve in `base_dir`; without one,
/// only embedded and data-URI resources load. Errors name the file `<memory>`.
pub fn load_gltf_slice(bytes: &[u8], base_dir: Option<&Path>) -> Result<GltfScene, GltfError> {
    load(bytes, base_dir, Path::new("<memory>"))
}

fn load(bytes: &[u8], base_dir: Option<&Path>, path: &Path) -> Result<GltfScene, GltfError> {
    let (json, bin) = source::split_glb(bytes).map_err(|reason| GltfError::Glb {
        path: path.to_owned(),
        reason,
    })?;
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(json).map_err(|e| GltfError::Json {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    // Before validation, which would call this "unsupported data" without the name.
    if let Some(extension) = root.extensions_required.first() {
        return Err(GltfError::UnsupportedExtension {
            path: path.to_owned(),
            extension: extension.clone(),
        });
    }
    check_position_indices(&root, path)?;
    let document = Document::from_json(root).map_err(|e| GltfError::Invalid {
        path: path.to_owned(),
        message: validation_message(e),
    })?;
    let buffers = source::load_buffers(&document, bin, base_dir, path)?;
    let mut importer = Importer {
        path,
        base_dir,
        buffers: Buffers(buffers),
        images: HashMap::new(),
        warnings: Vec::new(),
    };
    importer.scene(&document)
}

/// gltf-json's validation looks up each POSITION accessor without checking
/// the index (it panics on one out of range), so that one is checked first.
fn check_position_indices(root: &gltf::json::Root, path: &Path) -> Result<(), GltfError> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = gltf::json::validation::Checked::Valid(Semantic::Positions);
            if let Some(index) = primitive.attributes.get(&position)
                && index.value() >= root.accessors.len()
            {
                return Err(GltfError::Invalid {
                    path: path.to_owned(),
                    message: format!(
                        "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not exist",
                        index.value()
                    ),
                });
            }
        }
    }
    Ok(())
}

/// At most this many validation problems are listed in one error.
const MAX_LISTED: usize = 5;

fn validation_message(error: gltf::Error) -> String {
    match error {
        gltf::Error::Validation(problems) => {
            let mut listed: Vec<String> = problems
                .iter()
                .take(MAX_LISTED)
                .map(|(at, problem)| format!("{at}: {problem}"))
                .collect();
            if problems.len() > MAX_LISTED {
                listed.push(format!("and {} more", problems.len() - MAX_LISTED));
            }
            listed.join("; ")
        }
        other => other.to_string(),
    }
}

/// One load in progress: what every step needs to read data and report.
struct Importer<'a> {
    path: &'a Path,
    base_dir: Option<&'a Path>,
    buffers: Buffers,
    /// Decoded images by glTF image index, each decoded once.
    images: HashMap<usize, TextureData>,
    warnings: Vec<String>,
}

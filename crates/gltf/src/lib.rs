//! Spreadlight's glTF 2.0 import: `.gltf` (external or data-URI buffers and
//! images) and `.glb`, into the renderer's CPU-side types ([`MeshData`],
//! materials of the one world through [`MaterialData::to_material`], lights,
//! deform data) and world-space [`MeshInstance`]s of one scene.
//!
//! A crate of its own, above `spreadlight-render` and below the nodes and
//! the CLI: it uses only the renderer's public types (the renderer never
//! names it), so the renderer and its unit tests no longer compile the
//! importer and its tests with every change of an effect.
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
//! - `TEXCOORD_0`, `TEXCOORD_1` and `COLOR_0` are read; textures using a
//!   later set are reported as warnings (and mapped with set 0); node
//!   animations (TRS and morph weights) load, and [`GltfScene::pose`]
//!   poses the scene at a time;
//! - skins (up to 8 joint influences per vertex) and morph targets load
//!   beside each mesh ([`deform::Deform`]), and [`GltfScene::deform_pose`]
//!   gives what the GPU skinning pass needs for a pose;
//! - materials carry every texture with its sampler and
//!   `KHR_texture_transform`, and the `KHR_materials_*` extensions that fit
//!   the G-buffer (`material_extensions`: emissive strength, unlit, ior,
//!   specular, clearcoat, transmission as blending with its map baked into
//!   the base colour's alpha, volume read, spec-gloss converted to
//!   metal-rough); [`MaterialData::to_material`] makes them materials of the
//!   one world; `KHR_materials_variants`' mappings per instance
//!   ([`variants`]);
//! - a file requiring an extension outside [`SUPPORTED_EXTENSIONS`] is
//!   refused with a [`GltfError`] naming it; unknown optional ones are
//!   ignored with one warning each; `asset.version` must be 2.x.

mod accessor;
pub mod animation;
#[cfg(test)]
mod anisotropy_tests;
pub mod builder;
mod content;
pub mod deform;
#[cfg(test)]
mod hard_cases;
mod material;
mod material_extensions;
#[cfg(test)]
mod material_extensions_tests;
pub mod models;
pub mod morph;
pub mod pool;
mod primitive;
pub mod reference;
#[cfg(test)]
mod robustness;
mod scene;
pub mod skin;
#[cfg(test)]
mod skin_tests;
pub mod skinned_models;
mod source;
pub mod spec_gloss;
#[cfg(test)]
mod tests;
pub mod transmission;
pub mod variants;
mod volume;
#[cfg(test)]
mod volume_tests;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::Mat4;
use gltf::{Document, Semantic};
use thiserror::Error;

pub use content::{SceneCamera, SceneLights};

use accessor::Buffers;
use spreadlight_render::mesh::{Aabb, MeshData, MeshError};

/// Everything loaded from one glTF file.
#[derive(Debug, Clone, PartialEq)]
pub struct GltfScene {
    /// One per triangle primitive of the file, in file order (mesh, then primitive).
    pub meshes: Vec<MeshData>,
    /// What deforms each of `meshes` (same index): joint influences and
    /// morph targets; empty for rigid meshes.
    pub deforms: Vec<deform::Deform>,
    /// The file's skins, in file order.
    pub skins: Vec<skin::Skin>,
    /// Every material of the file, in file order (so glTF material indices hold).
    pub materials: Vec<MaterialData>,
    /// One per (node, primitive) of the loaded scene.
    pub instances: Vec<MeshInstance>,
    /// World bounds of all instances ([`Aabb::ZERO`] when there are none).
    pub bounds: Aabb,
    /// `KHR_lights_punctual` lights of the loaded scene, placed at rest.
    pub lights: SceneLights,
    /// The same lights as their nodes hold them, to place at a pose.
    pub light_sources: Vec<content::LightSource>,
    /// Cameras of the loaded scene, in node order.
    pub cameras: Vec<SceneCamera>,
    /// The scene's node tree, to pose it ([`GltfScene::pose`]).
    pub graph: animation::SceneGraph,
    /// Node animations (TRS channels), in file order.
    pub animations: Vec<animation::Animation>,
    /// `KHR_materials_variants`' variant names, in file order (empty
    /// without the extension); see [`GltfScene::variant`].
    pub variants: Vec<String>,
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
    /// The glTF node that places it (what animations move).
    pub node: usize,
    /// Index into [`GltfScene::skins`] when the instance is skinned.
    pub skin: Option<usize>,
    /// Its morph weights at rest (the node's, else the mesh's; one per target).
    pub weights: Vec<f32>,
    /// `KHR_materials_variants`: its material in each of the file's
    /// variants (`None`: its default `material`); empty without variants.
    /// [`MeshInstance::material_in`] picks.
    pub variant_materials: Vec<Option<usize>>,
}

pub use spreadlight_render::material::maps::AlphaMode;
use spreadlight_render::material::maps::{MapImage, UvTransform, Wrap};

/// A glTF metallic-roughness material. Factors are linear; texture colours
/// are as stored (see [`TextureData::srgb`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialData {
    pub name: Option<String>,
    pub base_color: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    pub emissive: [f32; 3],
    /// `KHR_materials_emissive_strength` (1 without it).
    pub emissive_strength: f32,
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
    /// `KHR_materials_unlit`: shown as its base colour, no lighting.
    pub unlit: bool,
    /// `KHR_materials_ior` (1.5 without it; 0 is the extension's "f0 = 1").
    pub ior: f32,
    /// `KHR_materials_specular`: specularFactor (1 without it).
    pub specular: f32,
    /// `KHR_materials_specular`: specularColorFactor (white without it).
    pub specular_color: [f32; 3],
    /// `KHR_materials_clearcoat`: clearcoatFactor (0: no coat).
    pub clearcoat: f32,
    /// `KHR_materials_clearcoat`: clearcoatRoughnessFactor.
    pub clearcoat_roughness: f32,
    /// `KHR_materials_iridescence`: iridescenceFactor (0 without it: no film).
    pub iridescence: f32,
    /// `KHR_materials_iridescence`: iridescenceIor, the film's index (1.3).
    pub iridescence_ior: f32,
    /// `KHR_materials_iridescence`: iridescenceThicknessMinimum and
    /// Maximum (nm; 100 and 400). Without a thickness map the film is the
    /// maximum thick.
    pub iridescence_thickness_minimum: f32,
    pub iridescence_thickness_maximum: f32,
    /// `KHR_materials_iridescence`: iridescenceTexture (red scales the
    /// factor) and iridescenceThicknessTexture (green picks the thickness
    /// between minimum and maximum), sampled per pixel by the G-buffer
    /// resolve into its sheen and film target.
    pub iridescence_texture: Option<TextureData>,
    pub iridescence_thickness_texture: Option<TextureData>,
    /// `KHR_materials_sheen`: sheenColorFactor (linear; black without it:
    /// no sheen), each channel 0..1.
    pub sheen_color: [f32; 3],
    /// `KHR_materials_sheen`: sheenRoughnessFactor (0..1).
    pub sheen_roughness: f32,
    /// `KHR_materials_sheen`: sheenColorTexture (rgb, sRGB, scales the
    /// colour) and sheenRoughnessTexture (alpha scales the roughness),
    /// sampled per pixel by the G-buffer resolve into its sheen and film target.
    pub sheen_color_texture: Option<TextureData>,
    pub sheen_roughness_texture: Option<TextureData>,
    /// `KHR_materials_transmission`: transmissionFactor (0 without it). Until
    /// a pass refracts, a transmissive material is drawn BLEND with its base
    /// colour alpha times 1 - transmission (the importer has applied that to
    /// `alpha_mode` and `base_color`; this keeps the file's value).
    pub transmission: f32,
    /// `KHR_materials_transmission`: transmissionTexture (red scales the
    /// factor). Kept as read; the importer has baked it into the base colour
    /// map's alpha ([`transmission::bake_opacity`]).
    pub transmission_texture: Option<TextureData>,
    /// `KHR_materials_volume`: thicknessFactor (0 without it: thin-walled),
    /// in the mesh's units.
    pub thickness: f32,
    /// `KHR_materials_volume`: thicknessTexture (green scales the factor),
    /// sampled by lit transparency (the surface maps' thickness slot).
    pub thickness_texture: Option<TextureData>,
    /// `KHR_materials_volume`: attenuationColor, the colour white light
    /// turns after travelling `attenuation_distance` inside (white: none).
    pub attenuation_color: [f32; 3],
    /// `KHR_materials_volume`: attenuationDistance (> 0; infinite without
    /// it: no absorption). Infinity stays on the CPU: what leaves for the
    /// GPU is [`MaterialData::transmittance`], finite.
    pub attenuation_distance: f32,
    /// `KHR_materials_dispersion`: dispersion, 20 / the Abbe number (0
    /// without it: every colour refracts alike). Lit transparency bends
    /// red, green and blue by their own index through a transmissive volume.
    pub dispersion: f32,
    /// `KHR_materials_clearcoat`: clearcoatTexture (red scales the factor)
    /// and clearcoatRoughnessTexture (green), sampled in the G-buffer
    /// resolve (the surface maps' coat slots); clearcoatNormalTexture, the
    /// coat's own tangent-space normal (its x and y scaled by
    /// `clearcoat_normal_scale`), for the coat lobe alone (the G-buffer
    /// resolve packs it beside the coat in the surface target; lit
    /// transparency samples it per fragment).
    pub clearcoat_texture: Option<TextureData>,
    pub clearcoat_roughness_texture: Option<TextureData>,
    pub clearcoat_normal_texture: Option<TextureData>,
    pub clearcoat_normal_scale: f32,
    /// `KHR_materials_specular`: specularTexture (alpha scales the factor)
    /// and specularColorTexture (rgb, sRGB), sampled per pixel into the
    /// reflectance (the surface maps' specular slots).
    pub specular_texture: Option<TextureData>,
    pub specular_color_texture: Option<TextureData>,
    /// `KHR_materials_anisotropy`: anisotropyStrength (0..=1; 0 without
    /// it: isotropic), anisotropyRotation (radians, counter-clockwise from
    /// the tangent) and anisotropyTexture (rg: the direction in the tangent
    /// frame as 0..1, b: scales the strength), drawn by the Anisotropy
    /// feature and the anisotropy map slot.
    pub anisotropy_strength: f32,
    pub anisotropy_rotation: f32,
    pub anisotropy_texture: Option<TextureData>,
    /// The file gave this material as `KHR_materials_pbrSpecularGlossiness`;
    /// base colour, metallic, roughness and their maps are its conversion
    /// (`spec_gloss`).
    pub from_spec_gloss: bool,
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
            emissive_strength: 1.0,
            base_color_texture: None,
            metallic_roughness_texture: None,
            normal_texture: None,
            normal_scale: 1.0,
            occlusion_texture: None,
            occlusion_strength: 1.0,
            emissive_texture: None,
            double_sided: false,
            alpha_mode: AlphaMode::Opaque,
            unlit: false,
            ior: 1.5,
            specular: 1.0,
            specular_color: [1.0; 3],
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            iridescence: 0.0,
            iridescence_ior: 1.3,
            iridescence_thickness_minimum: 100.0,
            iridescence_thickness_maximum: 400.0,
            iridescence_texture: None,
            iridescence_thickness_texture: None,
            sheen_color: [0.0; 3],
            sheen_roughness: 0.0,
            sheen_color_texture: None,
            sheen_roughness_texture: None,
            transmission: 0.0,
            transmission_texture: None,
            thickness: 0.0,
            thickness_texture: None,
            attenuation_color: [1.0; 3],
            attenuation_distance: f32::INFINITY,
            dispersion: 0.0,
            clearcoat_texture: None,
            clearcoat_roughness_texture: None,
            clearcoat_normal_texture: None,
            clearcoat_normal_scale: 1.0,
            specular_texture: None,
            specular_color_texture: None,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            anisotropy_texture: None,
            from_spec_gloss: false,
        }
    }
}

/// A material's texture: the decoded image (shared by every use of the
/// same glTF image) and how this use samples it.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureData {
    pub image: Arc<MapImage>,
    /// True for colour (base colour, emissive): sample through an sRGB format.
    pub srgb: bool,
    /// TEXCOORD_n, after `KHR_texture_transform`'s override.
    pub tex_coord: u32,
    pub transform: UvTransform,
    /// (s, t) wrap modes of its sampler.
    pub wrap: [Wrap; 2],
    /// Its sampler's magnification filter is NEAREST.
    pub nearest: bool,
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
    #[error("{path}: {skin}: {reason}")]
    Skin {
        path: PathBuf,
        skin: String,
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
    let mut root: gltf::json::Root =
        gltf::json::deserialize::from_slice(json).map_err(|e| GltfError::Json {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    // Before validation, which would call this "unsupported data" without the name.
    if let Some(extension) = root
        .extensions_required
        .iter()
        .find(|e| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
    {
        return Err(GltfError::UnsupportedExtension {
            path: path.to_owned(),
            extension: extension.clone(),
        });
    }
    // Every required extension is one this loader reads (checked above);
    // gltf-json's validation would refuse those it has no typed form of
    // (clearcoat, specular), so its check is not asked again.
    root.extensions_required.clear();
    let major = root.asset.version.split('.').next().unwrap_or("");
    if major != "2" {
        return Err(GltfError::Invalid {
            path: path.to_owned(),
            message: format!(
                "asset.version is `{}`: only glTF 2.x can be read",
                root.asset.version
            ),
        });
    }
    let ignored: Vec<String> = root
        .extensions_used
        .iter()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
        .map(|e| format!("extension `{e}` is not supported; what it adds is ignored"))
        .collect();
    check_position_indices(&root, path)?;
    check_camera_projections(&root, path)?;
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
    for warning in ignored {
        importer.warn(warning);
    }
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

/// gltf-json's validation accepts a camera whose `type` names a projection
/// object it lacks (a perspective camera with only `orthographic`), and
/// the gltf crate unwraps that object when asked for the projection.
fn check_camera_projections(root: &gltf::json::Root, path: &Path) -> Result<(), GltfError> {
    use gltf::json::camera::Type;
    use gltf::json::validation::Checked;
    for (c, camera) in root.cameras.iter().enumerate() {
        let missing = match camera.type_ {
            Checked::Valid(Type::Perspective) if camera.perspective.is_none() => "perspective",
            Checked::Valid(Type::Orthographic) if camera.orthographic.is_none() => "orthographic",
            _ => continue,
        };
        let name = camera
            .name
            .as_deref()
            .map_or_else(String::new, |n| format!(" `{n}`"));
        return Err(GltfError::Invalid {
            path: path.to_owned(),
            message: format!(
                "cameras[{c}]{name}: its type is {missing} but it has no `{missing}` object"
            ),
        });
    }
    Ok(())
}

/// The extensions read; a file may require these and no others.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_dispersion",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_iridescence",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_sheen",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_unlit",
    "KHR_materials_variants",
    "KHR_materials_volume",
    "KHR_texture_transform",
];

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
    images: HashMap<usize, Arc<MapImage>>,
    warnings: Vec<String>,
}

impl Importer<'_> {
    /// Record a warning once: the same problem on many objects is one line.
    fn warn(&mut self, message: String) {
        if !self.warnings.contains(&message) {
            self.warnings.push(message);
        }
    }
}

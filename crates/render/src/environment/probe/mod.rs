//! Environment probes (Castor3D's environment pass): a layer rendered into
//! a cube map from a point, then prefiltered like any [`super::Environment`]
//! (its base cube's level 0 comes from [`faces`] instead of an image or the
//! sky), so Reflection, Sky and the diffuse light read it unchanged.
//!
//! - What it sees is a simple forward shading of the layer, not the
//!   deferred pipeline: each surface's albedo (the instance colour and the
//!   layer's Color Texture) lit by the probe's own ambient and one sun, its
//!   normal perturbed by the layer's Normal Map, the sun shadowed by a
//!   ShadowMap (Sun)'s maps when given them ([`ProbeShadow`]), the
//!   background a flat colour; then each point or spot light buffer
//!   ([`ProbeLights`]) draws the layer again, adding its lights'
//!   Cook-Torrance light through the forward passes' shared light function
//!   (shaders/lib/forward_light.wgsl, lit transparency's), with their
//!   shadow maps. A glTF layer's surface maps (base colour, normal,
//!   metallic-roughness, occlusion, emissive) colour and shape what it
//!   sees. A mirror then shows the box's colour, at the cost of six
//!   rasterizations (and one more per light buffer) and a prefilter, not
//!   six G-buffers.
//! - When: the probe's content key (its position, lighting, every
//!   instance's transform, colour and mesh, its layers' textures by name,
//!   the shadow's light and casters, and every light buffer's lights and
//!   shadows) is compared with the last
//!   render's; [`ProbeUpdate`] says whether a change, a frame count or
//!   nothing triggers the next. The camera is not part of the key: a moved
//!   camera reuses the cube ("environment probe reused").
//! - Where: an influence [`ProbeVolume`] (a box or a sphere around the
//!   room) makes Reflection correct each reflected ray for parallax
//!   (Lagarde & Zanuttini 2012, "Local image-based lighting with
//!   parallax-corrected cubemaps"): the ray from the shaded point is
//!   intersected with the volume and the cube looked up towards that hit
//!   from the probe, so a box near the mirror appears where it is, not as
//!   if infinitely far.

pub(crate) mod faces;
pub(crate) mod key;

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};
use thiserror::Error;

use crate::gbuffer::Layer;
use crate::lighting::{LightBuffer, LightKind};
use crate::shadows::ShadowMaps;

/// Why a probe was refused; names the setting.
#[derive(Debug, Error, PartialEq)]
pub enum ProbeError {
    #[error("the probe's {what} is NaN or infinite")]
    NotFinite { what: &'static str },
    #[error("the probe's {what} is negative ({value})")]
    Negative { what: &'static str, value: f32 },
    #[error("update every {0} frames: it must be at least 1")]
    ZeroInterval(u32),
    #[error("the probe's sun shadow needs a ShadowMap (Sun), not a {0:?} one")]
    NotSunShadow(LightKind),
    #[error("the probe's sun shadow slice {slice} is not in the shadow maps (slices 0..{count})")]
    ShadowSlice { slice: u32, count: u32 },
    #[error(
        "the probe's lights take point and spot light buffers; its sun is its Sun pins (light buffer {index} holds suns)"
    )]
    SunBuffer { index: usize },
    #[error(
        "light buffer {index} holds {lights:?} lights but its shadow maps are a {maps:?} ShadowMap's"
    )]
    ShadowKind {
        index: usize,
        lights: LightKind,
        maps: LightKind,
    },
}

/// A point or spot light buffer that lights the probe's faces, with the
/// shadow maps its lights' slices index (a ShadowMap of the same type).
#[derive(Clone, Debug)]
pub struct ProbeLights {
    pub lights: Arc<LightBuffer>,
    pub shadows: Option<Arc<ShadowMaps>>,
}

/// How many lights of each buffer a face adds by default (Max Lights).
pub const DEFAULT_MAX_LIGHTS: u32 = 64;

/// The roughness and metallic the light passes give surfaces without a
/// material world (glTF layers bring theirs): a rough dielectric, as
/// Transparency's defaults.
pub const SURFACE_ROUGHNESS: f32 = 0.5;
pub const SURFACE_METALLIC: f32 = 0.0;

/// The shadow of a probe's sun: slice `slice` of a ShadowMap (Sun)'s maps
/// (the scene's sun, whose direction the probe's lighting should share).
#[derive(Clone, Debug)]
pub struct ProbeShadow {
    pub maps: Arc<ShadowMaps>,
    pub slice: u32,
}

/// When a probe renders its faces again.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum ProbeUpdate {
    /// Whenever what it sees changed (its content key differs from the last render's).
    #[default]
    OnChange,
    /// Every n-th frame whether or not anything changed (for scenes whose
    /// change the key cannot see: meshes deformed on the GPU, particles).
    EveryNFrames(u32),
    /// The first frame only (and again when the cube size or samples change).
    Once,
}

/// The region a probe's cube stands for, for parallax correction.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum ProbeVolume {
    /// None: the cube is looked up as if infinitely far (as Environment).
    #[default]
    Infinite,
    /// An axis-aligned box, `center` ± `size` / 2.
    Box {
        center: Vec3,
        size: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: f32,
    },
}

impl ProbeVolume {
    /// A volume with no extent along some axis is no volume: a ray cannot
    /// be intersected with it, so the cube is read as infinitely far.
    pub fn effective(self) -> ProbeVolume {
        match self {
            ProbeVolume::Box { size, .. } if size.min_element() <= 0.0 => ProbeVolume::Infinite,
            ProbeVolume::Sphere { radius, .. } if radius <= 0.0 => ProbeVolume::Infinite,
            v => v,
        }
    }
}

/// How the faces are lit: albedo x (ambient + sun_color x max(N.L, 0)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeLighting {
    /// The way the sunlight travels (as `AddLight (Sun)`): surfaces facing against it are lit.
    pub sun_direction: Vec3,
    /// The sun's radiance onto a surface facing it (linear).
    pub sun_color: Vec3,
    /// Light from every direction (linear).
    pub ambient: Vec3,
    /// What the faces show where no geometry is (linear radiance).
    pub background: Vec3,
}

impl Default for ProbeLighting {
    fn default() -> Self {
        ProbeLighting {
            sun_direction: Vec3::new(-0.3, -1.0, -0.2),
            sun_color: Vec3::splat(2.0),
            ambient: Vec3::new(0.25, 0.27, 0.3),
            background: Vec3::new(0.6, 0.7, 0.85),
        }
    }
}

/// Everything about a probe but what it sees.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ProbeSettings {
    pub position: Vec3,
    pub volume: ProbeVolume,
    pub lighting: ProbeLighting,
    pub update: ProbeUpdate,
}

/// A probe's layers and settings, checked: every number finite, sizes not negative.
#[derive(Debug)]
pub struct ProbeScene {
    layers: Vec<Arc<Layer>>,
    settings: ProbeSettings,
    sun_shadow: Option<ProbeShadow>,
    lights: Vec<ProbeLights>,
    /// The most lights of each buffer a face adds (the first ones).
    max_lights: u32,
}

impl PartialEq for ProbeScene {
    fn eq(&self, other: &Self) -> bool {
        let shadow = |s: &Option<ProbeShadow>| s.as_ref().map(|s| (Arc::as_ptr(&s.maps), s.slice));
        let lights = |l: &[ProbeLights]| -> Vec<_> {
            l.iter()
                .map(|l| (Arc::as_ptr(&l.lights), l.shadows.as_ref().map(Arc::as_ptr)))
                .collect()
        };
        self.settings == other.settings
            && shadow(&self.sun_shadow) == shadow(&other.sun_shadow)
            && lights(&self.lights) == lights(&other.lights)
            && self.max_lights == other.max_lights
            && self.layers.len() == other.layers.len()
            && self
                .layers
                .iter()
                .zip(&other.layers)
                .all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

fn finite(what: &'static str, values: &[f32]) -> Result<(), ProbeError> {
    match values.iter().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(ProbeError::NotFinite { what }),
    }
}

fn not_negative(what: &'static str, value: f32) -> Result<(), ProbeError> {
    match value < 0.0 {
        true => Err(ProbeError::Negative { what, value }),
        false => Ok(()),
    }
}

impl ProbeScene {
    /// A probe of `layers`; a NaN or infinite number, a negative size or
    /// colour, or an interval of 0 frames is refused, naming it (a NaN
    /// position would put NaN in every texel).
    pub fn new(layers: Vec<Arc<Layer>>, settings: ProbeSettings) -> Result<Self, ProbeError> {
        finite("position", &settings.position.to_array())?;
        match settings.volume {
            ProbeVolume::Infinite => {}
            ProbeVolume::Box { center, size } => {
                finite("volume centre", &center.to_array())?;
                finite("volume size", &size.to_array())?;
                not_negative("volume size", size.min_element())?;
            }
            ProbeVolume::Sphere { center, radius } => {
                finite("volume centre", &center.to_array())?;
                finite("volume radius", &[radius])?;
                not_negative("volume radius", radius)?;
            }
        }
        let l = settings.lighting;
        finite("sun direction", &l.sun_direction.to_array())?;
        for (what, c) in [
            ("sun colour", l.sun_color),
            ("ambient", l.ambient),
            ("background", l.background),
        ] {
            finite(what, &c.to_array())?;
            not_negative(what, c.min_element())?;
        }
        if settings.update == ProbeUpdate::EveryNFrames(0) {
            return Err(ProbeError::ZeroInterval(0));
        }
        Ok(ProbeScene {
            layers,
            settings,
            sun_shadow: None,
            lights: Vec::new(),
            max_lights: DEFAULT_MAX_LIGHTS,
        })
    }

    /// The probe with its sun shadowed by `shadow` (None: unshadowed). Maps
    /// of another light type, or a slice they do not have, are refused.
    pub fn with_sun_shadow(mut self, shadow: Option<ProbeShadow>) -> Result<Self, ProbeError> {
        if let Some(s) = &shadow {
            if s.maps.kind != LightKind::Sun {
                return Err(ProbeError::NotSunShadow(s.maps.kind));
            }
            let count = s.maps.slice_count();
            if s.slice >= count {
                return Err(ProbeError::ShadowSlice {
                    slice: s.slice,
                    count,
                });
            }
        }
        self.sun_shadow = shadow;
        Ok(self)
    }

    /// The probe lit by `lights` too, at most `max_lights` of each buffer
    /// (its first ones; 0: none) per face. Sun buffers are refused (the
    /// probe's sun is its own), and shadow maps of another light type.
    pub fn with_lights(
        mut self,
        lights: Vec<ProbeLights>,
        max_lights: u32,
    ) -> Result<Self, ProbeError> {
        for (index, l) in lights.iter().enumerate() {
            if l.lights.kind == LightKind::Sun {
                return Err(ProbeError::SunBuffer { index });
            }
            if let Some(maps) = &l.shadows
                && maps.kind != l.lights.kind
            {
                return Err(ProbeError::ShadowKind {
                    index,
                    lights: l.lights.kind,
                    maps: maps.kind,
                });
            }
        }
        // Buffers without lights light nothing: no pass for them.
        self.lights = lights
            .into_iter()
            .filter(|l| l.lights.count() > 0)
            .collect();
        self.max_lights = max_lights;
        Ok(self)
    }

    /// The light buffers whose light the faces add (none when Max Lights is 0).
    pub fn lights(&self) -> &[ProbeLights] {
        match self.max_lights {
            0 => &[],
            _ => &self.lights,
        }
    }

    pub fn max_lights(&self) -> u32 {
        self.max_lights
    }

    pub fn sun_shadow(&self) -> Option<&ProbeShadow> {
        self.sun_shadow.as_ref()
    }

    pub fn layers(&self) -> &[Arc<Layer>] {
        &self.layers
    }

    pub fn settings(&self) -> &ProbeSettings {
        &self.settings
    }

    /// The parallax volume as the Reflection shader reads it.
    pub(crate) fn gpu_volume(&self) -> GpuProbeVolume {
        GpuProbeVolume::new(self.settings.position, self.settings.volume)
    }

    /// What decides a re-render: position, lighting and every instance's
    /// transform, colour and mesh, and the sun shadow's slice, light and
    /// casters (not the previous transforms, which change once more after
    /// an object stops; not the volume, which only Reflection reads; not
    /// the shadow's cascades, which follow the camera: a moved camera keeps
    /// the cube).
    pub(crate) fn hash_content(&self, packed: &faces::PackedProbe, h: &mut impl Hasher) {
        let s = &self.settings;
        let l = &s.lighting;
        for v in [
            s.position,
            l.sun_direction,
            l.sun_color,
            l.ambient,
            l.background,
        ] {
            for c in v.to_array() {
                c.to_bits().hash(h);
            }
        }
        packed.hash(h);
        if let Some(s) = &self.sun_shadow {
            s.slice.hash(h);
            s.maps.hash_content(h);
        }
        // A moved, recoloured or added light renders the faces again; the
        // camera (which moves only the shadows' sun cascades) does not.
        self.max_lights.hash(h);
        for l in self.lights() {
            l.lights.hash_content(h);
            if let Some(maps) = &l.shadows {
                maps.hash_content(h);
            }
        }
    }
}

/// Matches `ProbeVolume` in shaders/environment/reflection.wgsl (PARALLAX).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuProbeVolume {
    /// Where the cube was rendered from.
    position: [f32; 3],
    /// 0: infinite (no correction), 1: box, 2: sphere.
    shape: u32,
    /// Box: its minimum corner; sphere: centre and radius.
    low: [f32; 4],
    /// Box: its maximum corner.
    high: [f32; 4],
}

impl GpuProbeVolume {
    pub(crate) fn new(position: Vec3, volume: ProbeVolume) -> Self {
        let (shape, low, high) = match volume.effective() {
            ProbeVolume::Infinite => (0, Vec4::ZERO, Vec4::ZERO),
            ProbeVolume::Box { center, size } => (
                1,
                (center - size * 0.5).extend(0.0),
                (center + size * 0.5).extend(0.0),
            ),
            ProbeVolume::Sphere { center, radius } => (2, center.extend(radius), Vec4::ZERO),
        };
        GpuProbeVolume {
            position: position.to_array(),
            shape,
            low: low.to_array(),
            high: high.to_array(),
        }
    }

    /// Whether Reflection needs its PARALLAX permutation for this volume.
    pub(crate) fn corrects(&self) -> bool {
        self.shape != 0
    }
}

/// The world direction through `uv` (-1..1, y down) of cube face `face`
/// (+X, -X, +Y, -Y, +Z, -Z), unnormalized: `cube_direction` in
/// shaders/lib/ibl.wgsl, which the prefilter and every reader use.
pub fn cube_direction(face: u32, uv: glam::Vec2) -> Vec3 {
    let (u, v) = (uv.x, uv.y);
    match face {
        0 => Vec3::new(1.0, -v, -u),
        1 => Vec3::new(-1.0, -v, u),
        2 => Vec3::new(u, 1.0, v),
        3 => Vec3::new(u, -1.0, -v),
        4 => Vec3::new(u, -v, 1.0),
        _ => Vec3::new(-u, -v, -1.0),
    }
}

/// The nearest distance a face draws (reversed-Z, no far plane).
pub const NEAR: f32 = 0.01;

/// Face `face`'s view-projection from `position`: a world point lands at
/// clip x = uv.x, y = -uv.y (raster y grows downwards like texel rows),
/// w = its distance along the face's axis, z = NEAR (reversed-Z, infinite
/// far: depth NEAR / distance, nearer is greater). Made from
/// [`cube_direction`] itself, so the faces cannot disagree with the cube's
/// readers about which way is which.
pub fn face_view_projection(face: u32, position: Vec3) -> Mat4 {
    let major = cube_direction(face, glam::Vec2::ZERO);
    let right = cube_direction(face, glam::Vec2::X) - major;
    let down = cube_direction(face, glam::Vec2::Y) - major;
    let row = |axis: Vec3| axis.extend(-axis.dot(position));
    Mat4::from_cols(
        row(right),
        row(-down),
        Vec4::new(0.0, 0.0, 0.0, NEAR),
        row(major),
    )
    .transpose()
}

#[cfg(test)]
mod tests {
    use glam::Vec2;

    use super::*;

    /// A point straight along any texel's direction from the probe lands on that texel.
    #[test]
    fn each_face_projects_its_texel_directions_onto_their_texels() {
        let position = Vec3::new(1.0, -2.0, 0.5);
        for face in 0..6 {
            let m = face_view_projection(face, position);
            for uv in [
                Vec2::new(0.3, -0.7),
                Vec2::new(-0.9, 0.2),
                Vec2::ZERO,
                Vec2::ONE * 0.5,
            ] {
                let d = cube_direction(face, uv).normalize();
                let clip = m * (position + d * 3.0).extend(1.0);
                let ndc = clip.truncate() / clip.w;
                assert!((ndc.x - uv.x).abs() < 1e-5, "face {face} {uv}: {ndc}");
                assert!((ndc.y + uv.y).abs() < 1e-5, "face {face} {uv}: {ndc}");
                assert!(ndc.z > 0.0 && ndc.z < 1.0, "face {face}: depth {}", ndc.z);
                // Nearer is greater (reversed-Z).
                let nearer = m * (position + d).extend(1.0);
                assert!(nearer.z / nearer.w > ndc.z);
            }
        }
    }

    #[test]
    fn gpu_probe_volume_matches_probe_volume_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuProbeVolume,
            crate::environment::reflection_key::ReflectionKey,
            ["PARALLAX"],
            "ProbeVolume",
            [position, shape, low, high]
        );
    }

    #[test]
    fn bad_numbers_are_refused_naming_them() {
        let settings = |f: &dyn Fn(&mut ProbeSettings)| {
            let mut s = ProbeSettings::default();
            f(&mut s);
            ProbeScene::new(Vec::new(), s).map(|_| ())
        };
        assert_eq!(
            settings(&|s| s.position.x = f32::NAN),
            Err(ProbeError::NotFinite { what: "position" })
        );
        assert_eq!(
            settings(&|s| s.volume = ProbeVolume::Sphere {
                center: Vec3::ZERO,
                radius: -1.0
            }),
            Err(ProbeError::Negative {
                what: "volume radius",
                value: -1.0
            })
        );
        assert_eq!(
            settings(&|s| s.update = ProbeUpdate::EveryNFrames(0)),
            Err(ProbeError::ZeroInterval(0))
        );
        assert!(settings(&|s| s.lighting.ambient.y = f32::INFINITY).is_err());
        // A zero-size volume is no volume: no parallax, no division by zero.
        assert!(
            settings(&|s| s.volume = ProbeVolume::Box {
                center: Vec3::ZERO,
                size: Vec3::new(2.0, 0.0, 2.0)
            })
            .is_ok()
        );
        let zero = ProbeVolume::Box {
            center: Vec3::ZERO,
            size: Vec3::new(2.0, 0.0, 2.0),
        };
        assert!(!GpuProbeVolume::new(Vec3::ZERO, zero).corrects());
    }
}

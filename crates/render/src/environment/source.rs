//! What an environment is made from (an equirectangular image or the
//! procedural sky, with its quality) and what it becomes (the maps). Shared
//! by the recipe (`environment_map.rs`), the build (`prefilter.rs`) and the
//! Sky pass (`sky.rs`), which import it and not each other.

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use spreadlight_reference::reflection::{CpuSky, Equirect, SkyInputs};
use thiserror::Error;

/// Why an environment image was refused; names the file.
#[derive(Debug, Error)]
pub enum EnvironmentError {
    #[error("{path}: cannot read the environment image: {message}")]
    Read { path: String, message: String },
    #[error("{path}: the environment image is empty")]
    Empty { path: String },
}

/// An equirectangular image: u = 0.5 looks along -z, v = 0 straight up
/// (`equirect_uv` in shaders/lib/ibl.wgsl). Linear radiance.
#[derive(Clone, Debug, PartialEq)]
pub struct EquirectImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl EquirectImage {
    /// Load a .hdr or .exr file (or any format the image crate reads, as linear).
    pub fn load(path: &Path) -> Result<Self, EnvironmentError> {
        let shown = path.display().to_string();
        let image = image::open(path).map_err(|e| EnvironmentError::Read {
            path: shown.clone(),
            message: e.to_string(),
        })?;
        let image = image.to_rgba32f();
        if image.width() == 0 || image.height() == 0 {
            return Err(EnvironmentError::Empty { path: shown });
        }
        Ok(EquirectImage {
            width: image.width(),
            height: image.height(),
            pixels: image.pixels().map(|p| p.0).collect(),
        })
    }

    /// Radiance as it is uploaded (half floats): NaN is 0, the rest within 0..=65000.
    pub fn sanitized(c: f32) -> f32 {
        if c.is_nan() {
            0.0
        } else {
            c.clamp(0.0, HALF_MAX)
        }
    }
}

/// The largest value a half-float target holds with margin: every stored texel is below it.
pub const HALF_MAX: f32 = 65000.0;

/// What an environment is made from.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSource {
    Equirect(Arc<EquirectImage>),
    Sky(SkySettings),
    /// A layer rendered into the cube from a point (`EnvironmentProbe`).
    Probe(Arc<super::probe::ProbeScene>),
}

/// The quality pins: the base cube's face size and the GGX samples per prefiltered texel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EnvironmentQuality {
    /// Face size in texels, rounded up to a power of two within 8..=1024.
    pub cube_size: u32,
    /// Samples per texel of each rough level, 1..=4096.
    pub samples: u32,
}

impl Default for EnvironmentQuality {
    fn default() -> Self {
        EnvironmentQuality {
            cube_size: 128,
            samples: 64,
        }
    }
}

impl EnvironmentQuality {
    pub fn sanitized(self) -> Self {
        EnvironmentQuality {
            cube_size: self.cube_size.clamp(8, 1024).next_power_of_two(),
            samples: self.samples.clamp(1, 4096),
        }
    }

    /// Mips of the base cube: down to 1x1.
    pub fn base_mips(self) -> u32 {
        self.cube_size.max(1).ilog2() + 1
    }

    /// Prefiltered levels: roughness 0, 1/(n-1), ..., 1; at most 6, each half the size of the last.
    pub fn levels(self) -> u32 {
        self.base_mips().min(MAX_LEVELS)
    }
}

pub const MAX_LEVELS: u32 = 6;
/// The diffuse irradiance cube's face size: irradiance is smooth, 16 texels resolve it.
pub const IRRADIANCE_SIZE: u32 = 16;
/// The split-sum table's size (N.V by roughness) and its samples per texel.
pub const LUT_SIZE: u32 = 64;
pub const LUT_SAMPLES: u32 = 512;

/// The built maps, kept between frames.
pub struct EnvironmentMaps {
    pub(crate) key: u64,
    pub quality: EnvironmentQuality,
    /// The source as a cube with its mip chain (mip 0: the unfiltered environment).
    pub base: wgpu::Texture,
    /// Roughness level m (0..levels) in mip m.
    pub prefiltered: wgpu::Texture,
    /// What a white Lambertian surface facing each direction reflects (E / pi).
    pub irradiance: wgpu::Texture,
    /// The split-sum table: (A, B) in RG, N.V along x, roughness along y.
    pub lut: wgpu::Texture,
    /// Trilinear, clamped: for the cubes and the table.
    pub sampler: wgpu::Sampler,
}

impl EnvironmentMaps {
    pub fn levels(&self) -> u32 {
        self.prefiltered.mip_level_count()
    }

    pub(crate) fn cube_view(texture: &wgpu::Texture) -> wgpu::TextureView {
        texture.create_view(&crate::texture_pool::ViewSpec::cube().descriptor())
    }
}

/// A procedural sky: linear radiance colours and the sun.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkySettings {
    pub zenith: Vec3,
    pub horizon: Vec3,
    pub ground: Vec3,
    /// The direction the sunlight travels (as a `SunLight`'s): the disk is opposite it.
    pub sun_direction: Vec3,
    /// The disk's radiance.
    pub sun_color: Vec3,
    /// The disk's angular radius in radians (the sun's: 0.0047).
    pub sun_radius: f32,
    /// How bright the glow around the disk is, 0 for none.
    pub glow: f32,
}

impl Default for SkySettings {
    fn default() -> Self {
        SkySettings {
            zenith: Vec3::new(0.12, 0.25, 0.6),
            horizon: Vec3::new(0.6, 0.7, 0.85),
            ground: Vec3::new(0.2, 0.18, 0.16),
            sun_direction: Vec3::new(-0.3, -1.0, -0.2),
            sun_color: Vec3::new(50.0, 45.0, 38.0),
            sun_radius: 0.0047,
            glow: 1.0,
        }
    }
}

/// The sky the CPU reference ray-traces against: the same numbers.
impl From<&SkySettings> for CpuSky {
    fn from(s: &SkySettings) -> Self {
        CpuSky::new(&SkyInputs {
            zenith: s.zenith,
            horizon: s.horizon,
            ground: s.ground,
            sun_direction: s.sun_direction,
            sun_color: s.sun_color,
            sun_radius: s.sun_radius,
            glow: s.glow,
        })
    }
}

/// The image as the CPU reference reads it (it sanitizes as the upload does).
impl<'a> From<&'a EquirectImage> for Equirect<'a> {
    fn from(image: &'a EquirectImage) -> Self {
        Equirect {
            width: image.width,
            height: image.height,
            pixels: &image.pixels,
        }
    }
}

/// Matches `Sky` in shaders/lib/sky.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct GpuSky {
    zenith: [f32; 4],
    horizon: [f32; 4],
    ground: [f32; 4],
    sun: [f32; 4],
    sun_color: [f32; 4],
}

/// Colours: finite and not negative (NaN is 0).
fn radiance(v: Vec3) -> [f32; 4] {
    let clean = |c: f32| {
        if c.is_finite() {
            c.clamp(0.0, 65000.0)
        } else {
            0.0
        }
    };
    [clean(v.x), clean(v.y), clean(v.z), 0.0]
}

impl GpuSky {
    /// The settings as the shader reads them, sanitized: colours finite and
    /// within 0..=65000, the sun's radius within 0..=0.5, glow within 0..=1000,
    /// a zero sun direction straight up.
    pub(crate) fn from_settings(settings: &SkySettings) -> Self {
        // Towards the sun: against the light's travel; straight up for a zero direction.
        let towards = (-settings.sun_direction).try_normalize().unwrap_or(Vec3::Y);
        let radius = if settings.sun_radius.is_finite() {
            settings.sun_radius.clamp(0.0, 0.5)
        } else {
            0.0
        };
        let glow = if settings.glow.is_finite() {
            settings.glow.clamp(0.0, 1e3)
        } else {
            0.0
        };
        let mut sun_color = radiance(settings.sun_color);
        sun_color[3] = glow;
        GpuSky {
            zenith: radiance(settings.zenith),
            horizon: radiance(settings.horizon),
            ground: radiance(settings.ground),
            sun: towards.extend(radius.cos()).to_array(),
            sun_color,
        }
    }
}

impl EnvironmentSource {
    /// The sky as the shaders read it, for a sky source.
    pub(crate) fn gpu_sky(&self) -> Option<GpuSky> {
        match self {
            EnvironmentSource::Sky(s) => Some(GpuSky::from_settings(s)),
            EnvironmentSource::Equirect(_) | EnvironmentSource::Probe(_) => None,
        }
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_sky_matches_sky_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuSky,
            crate::environment::prefilter_key::PrefilterKey,
            [],
            "Sky",
            [zenith, horizon, ground, sun, sun_color]
        );
    }
}

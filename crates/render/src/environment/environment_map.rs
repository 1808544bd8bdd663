//! An environment for image-based light: a cube map made from an
//! equirectangular HDR image or from the procedural sky, prefiltered per
//! roughness level (split-sum), its diffuse irradiance, and the split-sum
//! BRDF table (built by compute in [`super::prefilter`]).
//!
//! The maps outlive frames: they are kept in `Renderer::state` under the
//! owning node and rebuilt only when the source or quality changes (the
//! frame report counts "environment prefiltered" and "environment reused").
//! Readers order themselves after the build by reading [`Environment::token`].

use std::hash::{Hash, Hasher};
use std::path::Path;
use std::sync::{Arc, Mutex};

use thiserror::Error;

use super::sky::{GpuSky, SkySettings};
use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, TextureDesc};
use crate::recipe::{Recipe, next_recipe_id};
use crate::renderer::Renderer;

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
        texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        })
    }
}

/// Where a node's maps are kept across frames.
#[derive(Default)]
pub struct EnvironmentStore(pub(crate) Mutex<Option<Arc<EnvironmentMaps>>>);

/// The environment recipe: one pass that builds the maps when its source or
/// quality changed and otherwise only counts the reuse.
pub struct Environment {
    id: u64,
    owner: Option<u32>,
    pub source: EnvironmentSource,
    pub quality: EnvironmentQuality,
    key: u64,
    store: Arc<EnvironmentStore>,
    token: String,
}

impl std::fmt::Debug for Environment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Environment({:?})", self.quality)
    }
}

/// Identifies a source and quality: a change means a rebuild.
fn source_key(source: &EnvironmentSource, quality: EnvironmentQuality) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    quality.hash(&mut h);
    match source {
        EnvironmentSource::Equirect(image) => {
            0u8.hash(&mut h);
            (image.width, image.height).hash(&mut h);
            for p in &image.pixels {
                for c in p {
                    c.to_bits().hash(&mut h);
                }
            }
        }
        EnvironmentSource::Sky(s) => {
            1u8.hash(&mut h);
            for v in [s.zenith, s.horizon, s.ground, s.sun_direction, s.sun_color] {
                for c in v.to_array() {
                    c.to_bits().hash(&mut h);
                }
            }
            s.sun_radius.to_bits().hash(&mut h);
            s.glow.to_bits().hash(&mut h);
        }
    }
    h.finish()
}

impl Environment {
    /// An environment for node `owner` (its maps are kept under it and
    /// reused while the source and quality stay the same; without an owner
    /// every recipe builds its own).
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: EnvironmentSource,
        quality: EnvironmentQuality,
    ) -> Arc<Self> {
        let quality = quality.sanitized();
        let id = next_recipe_id();
        let store = match owner {
            Some(node) => renderer.state::<EnvironmentStore>(u64::from(node)),
            None => Arc::new(EnvironmentStore::default()),
        };
        Arc::new(Environment {
            id,
            owner,
            key: source_key(&source, quality),
            source,
            quality,
            store,
            token: format!("environment{id}/maps"),
        })
    }

    /// Read this in a pass that uses [`Environment::maps`]: it orders the build first.
    pub fn token(&self) -> &str {
        &self.token
    }

    /// The maps, once the build pass has run (this frame or an earlier one).
    pub fn maps(&self) -> Option<Arc<EnvironmentMaps>> {
        self.store
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .clone()
    }

    /// The maps a reader's pass needs now, or an error naming that pass.
    pub(crate) fn maps_for(&self, pass: &str) -> Result<Arc<EnvironmentMaps>, RenderError> {
        self.maps().ok_or_else(|| RenderError::Pass {
            pass: pass.to_owned(),
            message: "the environment was not built this frame".to_owned(),
        })
    }

    pub(crate) fn gpu_sky(&self) -> Option<GpuSky> {
        match &self.source {
            EnvironmentSource::Sky(s) => Some(GpuSky::from_settings(s)),
            EnvironmentSource::Equirect(_) => None,
        }
    }

    fn run(&self, cx: &mut PassContext<'_>) -> Result<(), RenderError> {
        let mut guard = self.store.0.lock().unwrap_or_else(|e| e.into_inner());
        if guard.as_ref().is_some_and(|m| m.key == self.key) {
            cx.count("environment reused", 1);
            return Ok(());
        }
        let maps = super::prefilter::build(cx, self, self.key)?;
        *guard = Some(Arc::new(maps));
        cx.count("environment prefiltered", 1);
        Ok(())
    }
}

impl Recipe for Environment {
    fn declare<'a>(&'a self, _: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        let name = crate::recipe::pass_name("Environment", self.owner, Some("prefilter"));
        fg.add_pass(
            name,
            self.owner,
            &[],
            &[(&self.token, TextureDesc::token())],
            move |cx| self.run(cx),
        );
    }
}

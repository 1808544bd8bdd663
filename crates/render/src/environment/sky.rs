//! `Sky`: a procedural sky behind the scene (shaders/environment/sky.wgsl),
//! written where the G-buffer's depth is empty, the lit image passed
//! through elsewhere.

use std::sync::Arc;

use super::ImagePass;
use super::environment_map::Environment;
use crate::gbuffer::GBuffer;
use crate::recipe::TextureRef;
use crate::renderer::Renderer;
use glam::Vec3;

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

/// The sky pass: an [`ImagePass`] over shaders/environment/sky.wgsl.
pub struct Sky;

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

impl Sky {
    pub fn pass(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        settings: SkySettings,
    ) -> Arc<ImagePass> {
        Self::with_environment(renderer, owner, gbuffer, source, settings, None)
    }

    /// The background from `environment` (its unblurred cube) instead of the
    /// procedural sky, when given.
    pub fn with_environment(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        settings: SkySettings,
        environment: Option<Arc<Environment>>,
    ) -> Arc<ImagePass> {
        let gpu = GpuSky::from_settings(&settings);
        let pass = ImagePass::new(
            renderer,
            owner,
            ("Sky", "environment/sky.wgsl"),
            gbuffer,
            source,
            bytemuck::bytes_of(&gpu),
        );
        match environment {
            Some(environment) => pass.with_environment(environment),
            None => pass,
        }
    }
}

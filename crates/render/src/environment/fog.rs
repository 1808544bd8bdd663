//! `Fog`: distance and height fog over the lit image
//! (shaders/environment/fog.wgsl), analytic along each view ray.

use std::sync::Arc;

use super::{ImageKind, ImagePass};
use crate::gbuffer::GBuffer;
use crate::recipe::TextureRef;
use crate::renderer::Renderer;
use glam::Vec3;

pub use super::fog_key::FogKey;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FogSettings {
    /// The fog's own radiance (linear).
    pub color: Vec3,
    /// Extinction per unit length at the base height.
    pub density: f32,
    /// How fast it thins with height, per unit (0: uniform).
    pub height_falloff: f32,
    pub base_height: f32,
    /// No fog nearer than this to the camera.
    pub start: f32,
}

impl Default for FogSettings {
    fn default() -> Self {
        FogSettings {
            color: Vec3::new(0.5, 0.55, 0.6),
            density: 0.02,
            height_falloff: 0.2,
            base_height: 0.0,
            start: 0.0,
        }
    }
}

/// The fog pass: an [`ImagePass`] over shaders/environment/fog.wgsl.
pub struct Fog;

impl Fog {
    pub fn pass(
        renderer: &Renderer,
        owner: Option<u32>,
        gbuffer: Arc<GBuffer>,
        source: TextureRef,
        settings: FogSettings,
    ) -> Arc<ImagePass> {
        let clean = |v: f32, lo: f32, hi: f32| if v.is_finite() { v.clamp(lo, hi) } else { 0.0 };
        let params = [
            clean(settings.color.x, 0.0, 65000.0),
            clean(settings.color.y, 0.0, 65000.0),
            clean(settings.color.z, 0.0, 65000.0),
            clean(settings.density, 0.0, 1e6),
            clean(settings.height_falloff, 0.0, 1e3),
            clean(settings.base_height, -1e9, 1e9),
            clean(settings.start, 0.0, 1e9),
            0.0,
        ];
        ImagePass::new(
            renderer,
            owner,
            ImageKind::Fog,
            gbuffer,
            source,
            bytemuck::cast_slice(&params),
        )
    }
}

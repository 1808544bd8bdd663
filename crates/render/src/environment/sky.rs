//! `Sky`: a procedural sky behind the scene (shaders/environment/sky.wgsl),
//! written where the G-buffer's depth is empty, the lit image passed
//! through elsewhere.

use std::sync::Arc;

use super::environment_map::Environment;
use super::source::{GpuSky, SkySettings};
use super::{ImageKind, ImagePass};
use crate::gbuffer::GBuffer;
use crate::recipe::TextureRef;
use crate::renderer::Renderer;

pub use super::sky_key::SkyKey;

/// The sky pass: an [`ImagePass`] over shaders/environment/sky.wgsl.
pub struct Sky;

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
            ImageKind::Sky,
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

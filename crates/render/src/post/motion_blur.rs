//! `MotionBlur`: blur along the G-buffer's velocity with McGuire et al.'s
//! tile-max / neighbour-max reconstruction (shaders/post/motion_blur.wgsl),
//! three compute passes. A frame where nothing moves (the G-buffer knows:
//! camera and instances where they were, `GBuffer::is_still`) costs one copy
//! and does not even resolve the velocity target; on the GPU, tiles whose
//! neighbourhood moves less than half a pixel copy their pixels.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{FrameGraph, PassContext, SizeRule, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::shaders::ShaderKey;

const SHADER: &str = "post/motion_blur.wgsl";

/// Counted when a MotionBlur ran only its copy: nothing in the frame moves.
pub const SKIPPED: &str = "motion blur skipped (no motion)";
/// Counted when a MotionBlur blurred.
pub const BLURRED: &str = "motion blur blurred";

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionBlurSettings {
    /// Degrees of a frame the shutter is open (360: the whole frame, 180: the film default).
    pub shutter_angle: f32,
    /// Taps along the motion per pixel: the quality.
    pub samples: u32,
    /// The tile size K in pixels, which is also the longest blur each way.
    pub tile_size: u32,
}

impl Default for MotionBlurSettings {
    fn default() -> Self {
        MotionBlurSettings {
            shutter_angle: 180.0,
            samples: 15,
            tile_size: 20,
        }
    }
}

impl MotionBlurSettings {
    pub fn clean(self) -> Self {
        MotionBlurSettings {
            shutter_angle: if self.shutter_angle.is_finite() {
                self.shutter_angle.clamp(0.0, 360.0)
            } else {
                180.0
            },
            samples: self.samples.clamp(2, 256),
            tile_size: self.tile_size.clamp(4, 64),
        }
    }
}

pub struct MotionBlur {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    gbuffer: Arc<GBuffer>,
    settings: MotionBlurSettings,
    params: wgpu::Buffer,
    tile_max: String,
    neighbor_max: String,
    pub output: String,
}

impl MotionBlur {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        settings: MotionBlurSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        let s = settings.clean();
        let params = super::uniform(
            renderer,
            owner,
            "motion blur",
            &super::words(&[
                s.shutter_angle / 360.0,
                s.tile_size as f32,
                s.samples as f32,
                0.0,
            ]),
        );
        Arc::new(MotionBlur {
            id,
            owner,
            source,
            gbuffer,
            settings: s,
            params,
            tile_max: format!("motion blur{id} tile max"),
            neighbor_max: format!("motion blur{id} neighbour max"),
            output: format!("motion blur{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        reads: &[(u32, &str)],
        write: (u32, &str),
    ) -> Result<(), RenderError> {
        let mut views = Vec::new();
        for (binding, name) in reads.iter().chain([&write]) {
            views.push((*binding, cx.view_named(name)?));
        }
        let mut all = vec![
            (0, self.gbuffer.camera_buffer().as_entire_binding()),
            (1, self.params.as_entire_binding()),
        ];
        all.extend(
            views
                .iter()
                .map(|(b, v)| (*b, wgpu::BindingResource::TextureView(v))),
        );
        let size = super::size_of(cx, write.1)?;
        let key = ShaderKey::new(SHADER, []);
        if entry == "tile_max" {
            // A workgroup per tile: its lanes share the tile's pixels.
            super::dispatch_groups(cx, entry, &key, entry, &all, size)
        } else {
            super::dispatch_entry(cx, entry, &key, entry, &all, size)
        }
    }
}

impl Recipe for MotionBlur {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if self.gbuffer.is_still() || self.settings.shutter_angle == 0.0 {
            fg.add_pass(
                crate::recipe::pass_name("MotionBlur", self.owner, Some("copy")),
                self.owner,
                &[&self.source.name],
                &[(&self.output, desc)],
                move |cx| {
                    cx.count(SKIPPED, 1);
                    super::copy(cx, &self.source.name, &self.output)
                },
            );
            return;
        }
        self.gbuffer.declare(renderer, fg);
        let (w, h) = self.gbuffer.pixel_size(fg.output_size());
        let k = self.settings.tile_size;
        let tiles = TextureDesc::storage(wgpu::TextureFormat::Rg32Float).size(SizeRule::Absolute {
            width: w.div_ceil(k),
            height: h.div_ceil(k),
        });
        let t = &self.gbuffer.targets;
        fg.add_pass(
            crate::recipe::pass_name("MotionBlur", self.owner, Some("tile max")),
            self.owner,
            &[&t.velocity_uv],
            &[(&self.tile_max, tiles)],
            move |cx| {
                self.run(
                    cx,
                    "tile_max",
                    &[(4, &self.gbuffer.targets.velocity_uv)],
                    (6, &self.tile_max),
                )
            },
        );
        fg.add_pass(
            crate::recipe::pass_name("MotionBlur", self.owner, Some("neighbour max")),
            self.owner,
            &[&self.tile_max],
            &[(&self.neighbor_max, tiles)],
            move |cx| {
                self.run(
                    cx,
                    "neighbor_max",
                    &[(5, &self.tile_max)],
                    (6, &self.neighbor_max),
                )
            },
        );
        fg.add_pass(
            crate::recipe::pass_name("MotionBlur", self.owner, Some("gather")),
            self.owner,
            &[
                &self.source.name,
                &t.depth,
                &t.velocity_uv,
                &self.neighbor_max,
            ],
            &[(&self.output, desc)],
            move |cx| {
                cx.count(BLURRED, 1);
                let t = &self.gbuffer.targets;
                self.run(
                    cx,
                    "main",
                    &[
                        (2, &self.source.name),
                        (3, &t.depth),
                        (4, &t.velocity_uv),
                        (5, &self.neighbor_max),
                    ],
                    (7, &self.output),
                )
            },
        );
    }
}

//! `DOF`: depth of field from a thin lens (shaders/post/dof.wgsl). A circle
//! of confusion pass over the G-buffer's depth, then a stochastic
//! scatter-as-gather lens blur with near and far fields and an optional
//! bokeh texture. When the lens cannot blur anything by half a pixel
//! anywhere between the near plane and infinity (a huge f-stop, a tiny focal
//! length) the CPU knows it before the frame and the node costs one copy.
//!
//! At [`Resolution::Half`] the blur (the expensive pass; the circle of
//! confusion and tiles stay full size) runs for one pixel in four, and an
//! upsample (crate::resolution) fills the output with depth awareness,
//! bringing back the full image's detail where a pixel is in focus.

use std::sync::Arc;

use glam::Mat4;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassBuilder, PassContext, Tex, TextureDesc};
use crate::gbuffer::GBuffer;
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::resolution::{
    Resolution, UpsampleFormat, UpsamplePass, declare_upsample, written_target,
};
use crate::shaders::{Permutation, ShaderKey};

pub use super::dof_key::DofKey;

/// Counted when a DOF ran only its copy: its circle of confusion stays under half a pixel.
pub const SKIPPED: &str = "dof skipped (circle under half a pixel)";
/// Counted when a DOF blurred.
pub const BLURRED: &str = "dof blurred";
/// Counted when a DOF blurred at half resolution.
pub const HALF_RESOLUTION: &str = "DOF at half resolution";

/// The lens. Distances are in scene units (metres), the focal length in millimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DofSettings {
    pub focal_length_mm: f32,
    pub f_stop: f32,
    /// Lens samples per pixel: the quality.
    pub samples: u32,
    /// The largest blur radius gathered, in pixels: the cost's bound.
    pub max_radius: f32,
    /// Where the blur runs: every pixel, or one in four upsampled.
    pub resolution: Resolution,
}

impl Default for DofSettings {
    fn default() -> Self {
        DofSettings {
            focal_length_mm: 50.0,
            f_stop: 2.8,
            samples: 32,
            max_radius: 16.0,
            resolution: Resolution::Full,
        }
    }
}

/// Where the lens is focused.
#[derive(Clone, Debug)]
pub enum Focus {
    /// A distance along the view axis; 0 or less focuses as near as the lens can, infinity at infinity.
    Distance(f32),
    /// A 1x1 R32Float texture of the inverse focus distance (an `Autofocus`), read on the GPU.
    Texture(TextureRef),
}

/// The smallest f-stop accepted (a lens wider than f/0.5 does not exist).
pub const MIN_F_STOP: f32 = 0.5;

impl DofSettings {
    /// The settings made usable: finite, positive, within bounds.
    pub fn clean(self) -> Self {
        let pick = |v: f32, lo: f32, hi: f32, fallback: f32| {
            if v.is_finite() {
                v.clamp(lo, hi)
            } else {
                fallback
            }
        };
        DofSettings {
            focal_length_mm: pick(self.focal_length_mm, 1.0, 2000.0, 50.0),
            // An infinite f-stop is a pinhole: nothing blurs.
            f_stop: if self.f_stop == f32::INFINITY {
                1e9
            } else {
                pick(self.f_stop, MIN_F_STOP, 1e9, 2.8)
            },
            samples: self.samples.clamp(1, 512),
            max_radius: pick(self.max_radius, 0.0, 128.0, 16.0),
            resolution: self.resolution,
        }
    }

    fn focal_length(&self) -> f32 {
        self.focal_length_mm / 1000.0
    }

    /// The largest inverse focus distance: the lens focuses no nearer than twice its focal length.
    fn max_inverse_focus(&self) -> f32 {
        0.5 / self.focal_length()
    }

    /// Pixels of circle diameter per unit of |1/s - 1/z| for an image `height` pixels high seen through `projection`.
    ///
    /// The renderer's field of view is fixed, so the sensor sits where the
    /// image of the focus plane forms: a lens of aperture A = f / N blurs a
    /// point at z to A |1/s - 1/z| times the image distance, and the image
    /// height is twice that distance over projection[1][1]. The same as
    /// averaging views from every point of the aperture re-aimed at the focus
    /// plane, which is what `spreadlight accuracy post dof` does.
    fn coc_scale(&self, projection: Mat4, height: u32) -> f32 {
        let aperture = self.focal_length() / self.f_stop;
        let scale = aperture * height as f32 * projection.y_axis.y.abs() / 2.0;
        if scale.is_finite() { scale } else { 0.0 }
    }

    /// The lens's aperture diameter in scene units.
    pub fn aperture(&self) -> f32 {
        let s = self.clean();
        s.focal_length() / s.f_stop
    }
}

/// The near plane of a standard (0..1 depth) perspective projection; None for other projections.
fn near_plane(projection: Mat4) -> Option<f32> {
    let near = projection.w_axis.z / projection.z_axis.z;
    (near.is_finite() && near > 0.0 && projection.z_axis.w == -1.0).then_some(near)
}

/// The largest circle-of-confusion diameter, in pixels, anything from the
/// near plane to infinity can have: at the near plane or at infinity, for a
/// fixed focus; over every focus from the near plane to infinity when the
/// focus is `None` (decided on the GPU). None when the projection is not a
/// perspective the bound understands (then the pass always runs).
pub fn max_coc_pixels(
    settings: DofSettings,
    focus: Option<f32>,
    projection: Mat4,
    height: u32,
) -> Option<f32> {
    let s = settings.clean();
    let near = near_plane(projection)?;
    let (inv_near, limit) = (1.0 / near, s.max_inverse_focus());
    let worst = |inv_s: f32| inv_s.max(inv_near - inv_s);
    let spread = match focus {
        Some(distance) => worst(inverse_focus(distance, limit)),
        None => worst(0.0).max(worst(limit.min(inv_near))),
    };
    Some(s.coc_scale(projection, height) * spread)
}

/// 1 / distance, within what the lens can focus (0 for infinity).
fn inverse_focus(distance: f32, limit: f32) -> f32 {
    if distance.is_nan() || distance <= 0.0 {
        return limit;
    }
    (1.0 / distance).min(limit)
}

pub struct Dof {
    id: u64,
    owner: Option<u32>,
    source: TextureRef,
    gbuffer: Arc<GBuffer>,
    focus: Focus,
    bokeh: Option<TextureRef>,
    settings: DofSettings,
    params: wgpu::Buffer,
    coc: String,
    /// Each tile's largest circle of confusion.
    tile_max: String,
    /// Each tile's and its eight neighbours' largest: what the blur reads.
    tiles: String,
    /// The half-size blur (Half only).
    pub output: String,
}

impl Dof {
    pub fn new(
        renderer: &Renderer,
        owner: Option<u32>,
        source: TextureRef,
        gbuffer: Arc<GBuffer>,
        focus: Focus,
        bokeh: Option<TextureRef>,
        settings: DofSettings,
    ) -> Arc<Self> {
        let id = next_recipe_id();
        // Kept under the node, filled as the recipe declares (write_kept): a
        // recipe made again each frame (a jittered camera) writes only a change.
        let params = renderer.kept_buffer(
            owner,
            "dof",
            32,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        );
        Arc::new(Dof {
            id,
            owner,
            source,
            gbuffer,
            focus,
            bokeh,
            settings: settings.clean(),
            params,
            coc: format!("dof{id} coc"),
            tile_max: format!("dof{id} tile max"),
            tiles: format!("dof{id} tiles"),
            output: format!("dof{id}"),
        })
    }

    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.output.clone(),
        }
    }

    fn key(&self) -> ShaderKey {
        DofKey {
            autofocus: matches!(self.focus, Focus::Texture(_)),
            bokeh: self.bokeh.is_some(),
            half: self.settings.resolution.is_half(),
        }
        .key()
    }

    /// Full resolution: the tiles and the blur make each pixel's circle of
    /// confusion from the depth where they read it (a few operations) and
    /// no pass writes a CoC target. At half resolution the upsample reads
    /// that target, so the `coc` pass makes it.
    fn inline_coc(&self) -> bool {
        !self.settings.resolution.is_half()
    }

    /// `entry` of dof.wgsl writing `output` (`coc`: the circle of
    /// confusion, `tiles`: each tile's largest, `neighbour_max`: the largest
    /// of each tile's 3x3, `main`: the blur), with what
    /// its pass declared in `bindings` and the camera and parameters every
    /// entry binds.
    fn run(
        &self,
        cx: &mut PassContext<'_>,
        entry: &'static str,
        bindings: Bindings<'_>,
        output: Tex,
    ) -> Result<(), RenderError> {
        super::dispatch_entry(
            cx,
            &self.key(),
            entry,
            entry == "tiles",
            self.gbuffer.camera_buffer(),
            &self.params,
            bindings,
            output,
        )
    }

    /// Where the blur writes: the output, or its half-size twin.
    fn blur_target(&self) -> String {
        written_target(&self.output, self.settings.resolution)
    }
}

impl Recipe for Dof {
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        self.source.recipe.declare(renderer, fg);
        let size = self.gbuffer.pixel_size(fg.output_size());
        let projection = self.gbuffer.camera.projection;
        let fixed = match &self.focus {
            Focus::Distance(d) => Some(*d),
            Focus::Texture(_) => None,
        };
        let bound = max_coc_pixels(self.settings, fixed, projection, size.1);
        let desc = TextureDesc::storage(wgpu::TextureFormat::Rgba16Float).size(self.gbuffer.size);
        if bound.is_some_and(|b| b < 0.5) || self.settings.max_radius < 0.5 {
            super::declare_copy(
                fg,
                PassName::new("DOF").step("copy"),
                self.owner,
                &self.source.name,
                (&self.output, desc),
                SKIPPED,
            );
            return;
        }
        self.gbuffer.declare(renderer, fg);
        if let Focus::Texture(t) = &self.focus {
            t.recipe.declare(renderer, fg);
        }
        if let Some(b) = &self.bokeh {
            b.recipe.declare(renderer, fg);
        }
        let s = self.settings;
        let radius = (bound.unwrap_or(f32::INFINITY) / 2.0)
            .min(s.max_radius)
            .max(0.5);
        // Tiles at least as wide as the largest radius: a circle reaches no further than the next tile.
        let tile = (radius.ceil() as u32).max(8);
        let params = super::words(&[
            s.coc_scale(projection, size.1),
            match self.focus {
                Focus::Distance(d) => inverse_focus(d, s.max_inverse_focus()),
                Focus::Texture(_) => 0.0,
            },
            radius,
            s.samples as f32,
            s.focal_length(),
            s.max_inverse_focus(),
            tile as f32,
            0.0,
        ]);
        // Only when the lens, the focus or the projection changed.
        renderer.write_kept(
            self.owner,
            "dof",
            &self.params,
            bytemuck::cast_slice(&params),
        );
        let coc_desc = TextureDesc::storage(wgpu::TextureFormat::Rg32Float).size(self.gbuffer.size);
        let depth = self.gbuffer.targets.depth.as_str();
        let focus = match &self.focus {
            Focus::Texture(t) => Some(t.name.as_str()),
            Focus::Distance(_) => None,
        };
        let inline = self.inline_coc();
        // The pipelines `run` dispatches (frame_graph/gather.rs).
        let key = self.key();
        let entries: &[&'static str] = match inline {
            true => &["tiles", "neighbour_max", "main"],
            false => &["coc", "tiles", "neighbour_max", "main"],
        };
        for entry in entries {
            fg.will_dispatch(&key, entry);
        }
        if !inline {
            let mut pass = fg.pass(PassName::new("DOF").step("circle of confusion"), self.owner);
            let (depth, focus) = (pass.read(depth), pass.read_opt(focus));
            let output = pass.write(&self.coc, coc_desc);
            pass.run(move |cx| {
                let b = Bindings::new()
                    .texture("depth", depth)
                    .texture_opt("focus", focus)
                    .texture("coc_out", output);
                self.run(cx, "coc", b, output)
            });
        }
        // What the tiles and the blur make the circles of confusion from.
        let read_coc = |pass: &mut PassBuilder<'_, 'a>| {
            if inline {
                CocIo::Depth {
                    depth: pass.read(depth),
                    focus: pass.read_opt(focus),
                }
            } else {
                CocIo::Target(pass.read(&self.coc))
            }
        };
        let tiles_desc = TextureDesc::storage(wgpu::TextureFormat::R32Float).size(
            crate::frame_graph::SizeRule::Absolute {
                width: size.0.div_ceil(tile),
                height: size.1.div_ceil(tile),
            },
        );
        let mut pass = fg.pass(PassName::new("DOF").step("tiles"), self.owner);
        let coc = read_coc(&mut pass);
        let tile_max = pass.write(&self.tile_max, tiles_desc);
        pass.run(move |cx| {
            let b = coc.bind(Bindings::new()).texture("tiles_out", tile_max);
            self.run(cx, "tiles", b, tile_max)
        });
        let mut pass = fg.pass(PassName::new("DOF").step("neighbour max"), self.owner);
        let tile_max = pass.read(&self.tile_max);
        let tiles = pass.write(&self.tiles, tiles_desc);
        pass.run(move |cx| {
            let b = Bindings::new()
                .texture("tiles_in", tile_max)
                .texture("tiles_out", tiles);
            self.run(cx, "neighbour_max", b, tiles)
        });
        let resolution = s.resolution;
        let mut pass = fg.pass(
            PassName::new("DOF").step(format!("blur{}", resolution.pass_suffix())),
            self.owner,
        );
        let source = pass.read(&self.source.name);
        let tiles = pass.read(&self.tiles);
        let coc = read_coc(&mut pass);
        let bokeh = pass.read_opt(self.bokeh.as_ref().map(|b| b.name.as_str()));
        let output = pass.write(
            &self.blur_target(),
            desc.size(resolution.size_rule(self.gbuffer.size, size)),
        );
        pass.run(move |cx| {
            let b = coc
                .bind(Bindings::new())
                .texture("source", source)
                .texture("tiles_in", tiles)
                .texture_opt("bokeh", bokeh)
                .texture("output", output);
            self.run(cx, "main", b, output)?;
            cx.count(BLURRED, 1);
            Ok(())
        });
        declare_upsample(
            fg,
            resolution,
            UpsamplePass {
                name: PassName::new("DOF").step("upsample"),
                owner: self.owner,
                gbuffer: &self.gbuffer,
                half: &self.blur_target(),
                full: &self.output,
                desc,
                format: UpsampleFormat::Rgba16,
                counter: HALF_RESOLUTION,
                label: "dof upsample",
                detail: Some((&self.source.name, &self.coc)),
            },
        );
    }
}

/// What the circles of confusion come from, in a pass that needs them.
#[derive(Clone, Copy)]
enum CocIo {
    /// Full resolution (INLINE_COC): made from the depth (and the focus
    /// texture with autofocus) where they are read.
    Depth { depth: Tex, focus: Option<Tex> },
    /// Half resolution: the `coc` pass's target, which the upsample reads too.
    Target(Tex),
}

impl CocIo {
    fn bind(self, b: Bindings<'_>) -> Bindings<'_> {
        match self {
            CocIo::Depth { depth, focus } => b.texture("depth", depth).texture_opt("focus", focus),
            CocIo::Target(coc) => b.texture("coc_in", coc),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn projection() -> Mat4 {
        glam::camera::rh::proj::directx::perspective(0.8, 1.5, 0.1, 100.0)
    }

    #[test]
    fn a_pinhole_lens_cannot_blur_and_a_wide_one_can() {
        let pinhole = DofSettings {
            f_stop: 1e6,
            ..Default::default()
        };
        let bound = max_coc_pixels(pinhole, Some(5.0), projection(), 1080).expect("perspective");
        assert!(bound < 0.5, "{bound}");
        let wide = DofSettings {
            f_stop: 1.4,
            ..Default::default()
        };
        let bound = max_coc_pixels(wide, Some(5.0), projection(), 1080).expect("perspective");
        assert!(bound > 10.0, "{bound}");
        // The GPU-decided focus bounds over every focus, so never below a fixed one.
        let any = max_coc_pixels(wide, None, projection(), 1080).expect("perspective");
        assert!(any >= bound);
    }

    #[test]
    fn focus_at_zero_nan_and_infinity_stays_finite() {
        for focus in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e-30] {
            let b = max_coc_pixels(DofSettings::default(), Some(focus), projection(), 720)
                .expect("perspective");
            assert!(b.is_finite() && b >= 0.0, "{focus}: {b}");
        }
    }
}

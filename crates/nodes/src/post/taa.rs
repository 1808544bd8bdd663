//! `TAA`: temporal anti-aliasing over the `Camera`'s jittered projection.
//! Keeps last frame's jitter, so the velocity's jitter part can be taken out.

use glam::{Mat4, Vec2};
use spreadlight_graph::{
    Choice, Choices, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res,
};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::post::{Taa, TaaQuality, TaaSettings, is_cut};

use super::{float, gbuffer, gbuffer_input, set_texture, texture, texture_input, texture_output};
use crate::gpu::renderer;

pub static QUALITY: Choices<TaaQuality> = Choices::new(
    "TAA Quality",
    &["Low", "Medium", "High"],
    &[TaaQuality::Low, TaaQuality::Medium, TaaQuality::High],
);

pub fn register(r: &mut Registry) {
    let d = TaaSettings::default();
    r.add(
        NodeDef::new(
            "TAA",
            "Post",
            "Temporal anti-aliasing: blends each frame into a history reprojected along the G-buffer's velocity. \
             Switch on the Camera's Jitter and link its Jitter output here. The history is checked against the 3x3 \
             neighbourhood of the current frame: Quality Low clamps to its YCoCg box, Medium clips towards its mean \
             (variance clipping), High also reads the history bicubically (sharper in motion). Feedback is the share \
             of history kept each frame (0.9 averages about ten); Sharpen adds back the current frame's detail. \
             Reset throws the history away, as do a resize, the first frame, and a camera cut: the G-buffer's \
             camera moving further than Cut Distance in a frame (0: never by distance) or turning more than 45 \
             degrees.",
        )
        .stateful()
        .with_pins_node(|p| {
            let pins = TaaPins {
                texture: texture_input(p, "Texture"),
                g_buffer: gbuffer_input(p),
                jitter: p.input("Jitter", Vec2::ZERO),
                quality: p.input_choice("Quality", &QUALITY, TaaQuality::High),
                feedback: p.input("Feedback", d.feedback),
                sharpen: p.input("Sharpen", d.sharpen),
                reset: p.input("Reset", false),
                cut_distance: p.input("Cut Distance", 1.0f32),
                out: texture_output(p, "Texture"),
            };
            move || TaaNode {
                pins,
                previous_jitter: None,
                previous_view: None,
            }
        }),
    );
}

#[derive(Clone, Copy)]
struct TaaPins {
    texture: In<Res<TextureRef>>,
    g_buffer: In<Res<GBuffer>>,
    jitter: In<Vec2>,
    quality: In<Choice<TaaQuality>>,
    feedback: In<f32>,
    sharpen: In<f32>,
    reset: In<bool>,
    cut_distance: In<f32>,
    out: Out<Res<TextureRef>>,
}

struct TaaNode {
    pins: TaaPins,
    previous_jitter: Option<Vec2>,
    previous_view: Option<Mat4>,
}

impl Node for TaaNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let renderer = renderer(cx)?;
        let pins = self.pins;
        let source = texture(cx, pins.texture)?;
        let g = gbuffer(cx, pins.g_buffer, "TAA reprojects with its velocity")?;
        let jitter = cx.first(pins.jitter, Vec2::ZERO)?;
        if !jitter.is_finite() {
            return Err(cx.error(pins.jitter, "slice 0 is NaN or infinite"));
        }
        let quality = cx.choice(pins.quality)?;
        let feedback = float(cx, pins.feedback, 0.9, false)?;
        if !(0.0..=1.0).contains(&feedback) {
            return Err(cx.error(pins.feedback, "must be 0 to 1"));
        }
        let sharpen = float(cx, pins.sharpen, 0.0, false)?;
        if sharpen < 0.0 {
            return Err(cx.error(pins.sharpen, "is negative"));
        }
        let cut_distance = float(cx, pins.cut_distance, 1.0, true)?;
        let view = g.camera.view;
        let cut = self
            .previous_view
            .replace(view)
            .is_some_and(|last| is_cut(last, view, cut_distance));
        if cut {
            // The recipe made now resets the history; next frame's must not.
            cx.reevaluate_next_frame();
        }
        let reset = cx.first(pins.reset, false)? || cut;
        let previous_jitter = self.previous_jitter.replace(jitter).unwrap_or(jitter);
        let settings = TaaSettings {
            quality,
            feedback,
            sharpen,
            jitter,
            previous_jitter,
            reset,
        };
        let taa = Taa::new(&renderer, Some(cx.node_id.0), source, g, settings, None);
        set_texture(cx, pins.out, taa.texture());
        Ok(())
    }
}

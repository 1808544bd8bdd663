//! `TAA`: temporal anti-aliasing over the `Camera`'s jittered projection.
//! Keeps last frame's jitter, so the velocity's jitter part can be taken out.

use glam::{Mat4, Vec2};
use spreadlight_graph::{
    EnumDef, EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::post::{Taa, TaaQuality, TaaSettings, is_cut};

use super::{float, gbuffer, set_texture, texture};
use crate::gpu::renderer;

pub static QUALITY: EnumDef = EnumDef {
    name: "TAA Quality",
    options: &["Low", "Medium", "High"],
};

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
        .input_spread("Texture", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![]))
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input("Jitter", Vec2::ZERO)
        .input_enum("Quality", &QUALITY, "High")
        .input("Feedback", d.feedback)
        .input("Sharpen", d.sharpen)
        .input("Reset", false)
        .input("Cut Distance", 1.0f32)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .stateful()
        .construct(TaaNode::default),
    );
}

#[derive(Default)]
struct TaaNode {
    previous_jitter: Option<Vec2>,
    previous_view: Option<Mat4>,
}

impl Node for TaaNode {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let renderer = renderer(cx)?;
        let source = texture(cx, 0)?;
        let g = gbuffer(cx, 1, "TAA reprojects with its velocity")?;
        let jitter = cx.slices::<Vec2>(2)?.first().copied().unwrap_or(Vec2::ZERO);
        if !jitter.is_finite() {
            return Err(cx.input_error(2, "slice 0 is NaN or infinite"));
        }
        let quality = match cx.enum_slices(3)?.first().map(String::as_str) {
            Some("Low") => TaaQuality::Low,
            Some("Medium") => TaaQuality::Medium,
            _ => TaaQuality::High,
        };
        let feedback = float(cx, 4, 0.9, false)?;
        if !(0.0..=1.0).contains(&feedback) {
            return Err(cx.input_error(4, "must be 0 to 1"));
        }
        let sharpen = float(cx, 5, 0.0, false)?;
        if sharpen < 0.0 {
            return Err(cx.input_error(5, "is negative"));
        }
        let cut_distance = float(cx, 7, 1.0, true)?;
        let view = g.camera.view;
        let cut = self
            .previous_view
            .replace(view)
            .is_some_and(|last| is_cut(last, view, cut_distance));
        if cut {
            // The recipe made now resets the history; next frame's must not.
            cx.reevaluate_next_frame();
        }
        let reset = cx.slices::<bool>(6)?.first().copied().unwrap_or(false) || cut;
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
        set_texture(cx, taa.texture());
        Ok(())
    }
}

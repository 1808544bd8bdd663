//! `SSAO` and `HBAO`: screen-space ambient occlusion over a G-buffer
//! (render::occlusion), visibility 0..1 for `CompositeLight`'s AO input.
//! SSAO is the wide-range kind (Emeshe's stochastic AO, or SAO); HBAO the
//! short-range local kind, which multiplies an incoming AO in, as Emeshe
//! pairs the two.

use spreadlight_graph::{
    Choice, Choices, EvalContext, In, NodeDef, NodeError, Pins, Registry, Res,
};
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::resolution::Resolution;
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings};

use super::require_finite;
use crate::gpu::renderer;
use crate::post::{gbuffer_input, optional_texture, set_texture, texture_input, texture_output};

/// SSAO's Mode pin: its two estimators.
pub static SSAO_MODES: Choices<AoMode> = Choices::new(
    "SSAO Mode",
    &["Stochastic", "SAO"],
    &[AoMode::Stochastic, AoMode::Sao],
);

/// What the pins both nodes share mean, closing each node's help.
macro_rules! temporal_help {
    () => {
        " Temporal Blend 0..0.98: the weight of last frame's result, reprojected with the G-buffer's velocity and \
         dropped where the surface changed (0: this frame only). Blur Radius: pixels (0..16) of a depth- and \
         normal-aware blur. Reset: drop the history (a camera cut). Intensity: an exponent on visibility (1: as \
         estimated)."
    };
}

/// The pins both nodes share, after their own: Radius, (Samples or Directions), Steps, Intensity,
/// Temporal Blend, Blur Radius, Reset, Resolution.
#[derive(Clone, Copy)]
struct Common {
    radius: In<f32>,
    count: In<i64>,
    steps: In<i64>,
    intensity: In<f32>,
    blend: In<f32>,
    blur: In<i64>,
    reset: In<bool>,
    resolution: In<Choice<Resolution>>,
}

impl Common {
    fn declare(p: &mut Pins<'_>, count_name: &'static str, radius: f32, count: i64) -> Self {
        Common {
            radius: p.input("Radius", radius),
            count: p.input(count_name, count),
            steps: p.input("Steps", 4i64),
            intensity: p.input("Intensity", 1.0f32),
            blend: p.input("Temporal Blend", 0.9f32),
            blur: p.input("Blur Radius", 4i64),
            reset: p.input("Reset", false),
            resolution: crate::resolution::input(p),
        }
    }

    /// The settings the pins give; a value out of range is an error naming its pin.
    fn settings(self, cx: &EvalContext<'_>, mode: AoMode) -> Result<AoSettings, NodeError> {
        require_finite(cx, self.radius)?;
        require_finite(cx, self.count)?;
        require_finite(cx, self.steps)?;
        require_finite(cx, self.intensity)?;
        require_finite(cx, self.blend)?;
        require_finite(cx, self.blur)?;
        let int = |pin: In<i64>, fallback: i64| -> Result<u32, NodeError> {
            Ok(cx.first(pin, fallback)?.clamp(0, i64::from(u32::MAX)) as u32)
        };
        let radius = cx.first(self.radius, 1.0)?;
        if radius < 0.0 {
            return Err(cx.error(self.radius, "must be 0 or more (world units)"));
        }
        let blend = cx.first(self.blend, 0.9)?;
        if !(0.0..1.0).contains(&blend) {
            return Err(cx.error(self.blend, "must be in 0..1 (0.98 at most is used)"));
        }
        Ok(AoSettings {
            mode,
            radius,
            samples: int(self.count, 8)?,
            steps: int(self.steps, 4)?,
            intensity: cx.first(self.intensity, 1.0)?,
            temporal_blend: blend,
            blur_radius: int(self.blur, 4)?,
            reset: cx.first(self.reset, false)?,
            resolution: cx.choice(self.resolution)?,
        })
    }
}

fn gbuffer(
    cx: &EvalContext<'_>,
    pin: In<Res<GBuffer>>,
) -> Result<std::sync::Arc<GBuffer>, NodeError> {
    cx.first_resource(pin)?
        .ok_or_else(|| cx.error(pin, "no G-buffer connected: AO reads its depth and normals"))
}

pub fn register(r: &mut Registry) {
    r.add(
        crate::resolution::with_help(NodeDef::new(
            "SSAO",
            super::CATEGORY,
            concat!(
                "Wide-range ambient occlusion: visibility 0..1 (1 = open) for CompositeLight's AO. Mode: Stochastic ",
                "(Emeshe's: Samples rays in a cosine-weighted hemisphere, each marched Steps times; blocked where it ",
                "passes behind a surface within Radius — what ray-cast AO computes) or SAO (McGuire's scalable ",
                "obscurance: a spiral of Samples taps over a depth mip chain; cheap at large radii, darker; it takes no ",
                "Steps). Radius in world units.",
                temporal_help!(),
            ),
        ))
        // Temporal accumulation, and sample patterns turned by a count of its own frames.
        .stateful()
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let mode = p.input_choice("Mode", &SSAO_MODES, AoMode::Stochastic);
            let common = Common::declare(p, "Samples", 1.0, 8);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let mode = cx.choice(mode)?;
                // Settings first: a wrong pin is named even before anything is wired.
                let s = common.settings(cx, mode)?;
                let g = gbuffer(cx, g_buffer)?;
                let ao = AmbientOcclusion::new(&renderer, Some(cx.node_id.0), g, s, None);
                set_texture(cx, out, ao.texture());
                Ok(())
            }
        }),
    );
    r.add(
        crate::resolution::with_help(NodeDef::new(
            "HBAO",
            super::CATEGORY,
            concat!(
                "Short-range local ambient occlusion, horizon-based: Directions screen directions, Steps taps each ",
                "within Radius (world units); the highest horizon in each direction occludes its slice. AO (optional): ",
                "a wide-range AO (SSAO) multiplied in, so one texture feeds CompositeLight.",
                temporal_help!(),
            ),
        ))
        // Temporal accumulation, and sample patterns turned by a count of its own frames.
        .stateful()
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let combine = texture_input(p, "AO");
            let common = Common::declare(p, "Directions", 0.3, 8);
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let s = common.settings(cx, AoMode::Hbao)?;
                let g = gbuffer(cx, g_buffer)?;
                let combine = optional_texture(cx, combine)?;
                let ao = AmbientOcclusion::new(&renderer, Some(cx.node_id.0), g, s, combine);
                set_texture(cx, out, ao.texture());
                Ok(())
            }
        }),
    );
}

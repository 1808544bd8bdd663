//! `SSAO` and `HBAO`: screen-space ambient occlusion over a G-buffer
//! (render::occlusion), visibility 0..1 for `CompositeLight`'s AO input.
//! SSAO is the wide-range kind (Emeshe's stochastic AO, or SAO); HBAO the
//! short-range local kind, which multiplies an incoming AO in, as Emeshe
//! pairs the two.

use spreadlight_graph::{
    EnumDef, EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::ssao::{AmbientOcclusion, AoMode, AoSettings};

use crate::gpu::{renderer, resource_spread, resources};

pub static SSAO_MODE: EnumDef = EnumDef {
    name: "SSAO Mode",
    options: &["Stochastic", "SAO"],
};

/// What the pins both nodes share mean, closing each node's help.
macro_rules! temporal_help {
    () => {
        " Temporal Blend 0..0.98: the weight of last frame's result, reprojected with the G-buffer's velocity and \
         dropped where the surface changed (0: this frame only). Blur Radius: pixels (0..16) of a depth- and \
         normal-aware blur. Reset: drop the history (a camera cut). Intensity: an exponent on visibility (1: as \
         estimated)."
    };
}

fn gbuffer_pin(def: NodeDef) -> NodeDef {
    def.input_spread(
        "G-Buffer",
        PinType::Resource(ResourceKind::GBuffer),
        Spread::Resource(ResourceKind::GBuffer, vec![]),
    )
}

/// The pins both nodes share, after their own: Radius, (Samples or Directions), Steps, Intensity,
/// Temporal Blend, Blur Radius, Reset, Resolution.
fn common(def: NodeDef, count_name: &'static str, radius: f32, count: i64) -> NodeDef {
    let def = def
        .input("Radius", radius)
        .input(count_name, count)
        .input("Steps", 4i64)
        .input("Intensity", 1.0f32)
        .input("Temporal Blend", 0.9f32)
        .input("Blur Radius", 4i64)
        .input("Reset", false);
    crate::resolution::pin(def)
}

/// Settings from the common pins starting at `first` (Radius), and the
/// Resolution pin after them.
fn settings(cx: &EvalContext<'_>, first: usize, mode: AoMode) -> Result<AoSettings, NodeError> {
    super::require_finite(cx, first..first + 6)?;
    let float = |pin: usize, fallback: f32| -> Result<f32, NodeError> {
        Ok(cx.slices::<f32>(pin)?.first().copied().unwrap_or(fallback))
    };
    let int = |pin: usize, fallback: i64| -> Result<u32, NodeError> {
        Ok(cx
            .slices::<i64>(pin)?
            .first()
            .copied()
            .unwrap_or(fallback)
            .clamp(0, i64::from(u32::MAX)) as u32)
    };
    let radius = float(first, 1.0)?;
    if radius < 0.0 {
        return Err(cx.input_error(first, "must be 0 or more (world units)"));
    }
    let blend = float(first + 4, 0.9)?;
    if !(0.0..1.0).contains(&blend) {
        return Err(cx.input_error(first + 4, "must be in 0..1 (0.98 at most is used)"));
    }
    Ok(AoSettings {
        mode,
        radius,
        samples: int(first + 1, 8)?,
        steps: int(first + 2, 4)?,
        intensity: float(first + 3, 1.0)?,
        temporal_blend: blend,
        blur_radius: int(first + 5, 4)?,
        reset: cx
            .slices::<bool>(first + 6)?
            .first()
            .copied()
            .unwrap_or(false),
        resolution: crate::resolution::read(cx, first + 7)?,
    })
}

fn gbuffer(cx: &EvalContext<'_>) -> Result<std::sync::Arc<GBuffer>, NodeError> {
    resources::<GBuffer>(cx, 0)?
        .into_iter()
        .next()
        .ok_or_else(|| cx.input_error(0, "no G-buffer connected: AO reads its depth and normals"))
}

pub fn register(r: &mut Registry) {
    r.add(
        common(
            gbuffer_pin(NodeDef::new(
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
            .input_enum("Mode", &SSAO_MODE, "Stochastic"),
            "Samples",
            1.0,
            8,
        )
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        // Temporal accumulation, and sample patterns turned by a count of its own frames.
        .stateful()
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let mode = match cx.enum_slices(1)?.first().map(String::as_str) {
                Some("SAO") => AoMode::Sao,
                _ => AoMode::Stochastic,
            };
            // Settings first: a wrong pin is named even before anything is wired.
            let s = settings(cx, 2, mode)?;
            let g = gbuffer(cx)?;
            let ao = AmbientOcclusion::new(&renderer, Some(cx.node_id.0), g, s, None);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(ao.texture())]));
            Ok(())
        }),
    );
    r.add(
        common(
            gbuffer_pin(NodeDef::new(
                "HBAO",
                super::CATEGORY,
                concat!(
                    "Short-range local ambient occlusion, horizon-based: Directions screen directions, Steps taps each ",
                    "within Radius (world units); the highest horizon in each direction occludes its slice. AO (optional): ",
                    "a wide-range AO (SSAO) multiplied in, so one texture feeds CompositeLight.",
                    temporal_help!(),
                ),
            ))
            .input_spread("AO", PinType::Resource(ResourceKind::Texture), Spread::Resource(ResourceKind::Texture, vec![])),
            "Directions",
            0.3,
            8,
        )
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        // Temporal accumulation, and sample patterns turned by a count of its own frames.
        .stateful()
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let s = settings(cx, 2, AoMode::Hbao)?;
            let g = gbuffer(cx)?;
            let combine = resources::<TextureRef>(cx, 1)?.into_iter().next().map(|t| (*t).clone());
            let ao = AmbientOcclusion::new(&renderer, Some(cx.node_id.0), g, s, combine);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(ao.texture())]));
            Ok(())
        }),
    );
}

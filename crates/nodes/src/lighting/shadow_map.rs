//! `ShadowMap (Spot)`, `ShadowMap (Point)`, `ShadowMap (Sun)`: the shadows
//! of a whole spread of lights of one type (unlike Emeshe, where each
//! casting light needs its own node). Each light whose AddLight gives it a
//! Shadow Slice gets that slice: a spot one layer of a 2D depth array, a
//! point light six (a cube map array's layout), a sun one per cascade. Feed
//! the output to the `CookTorrance` that shades the same lights.
//!
//! Only what the scene calls for: a light with no slice, or whose volume
//! misses the camera, renders no map, and a map whose light and casters have
//! not changed is reused from the last frame; `spreadlight stats` shows the
//! counts ("shadow maps rendered / reused / culled").

use spreadlight_graph::{
    Choice, Choices, EvalContext, In, NodeDef, NodeError, Out, Pins, Registry, Res, ResourceKind,
};
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};
use spreadlight_render::lighting::{PointLight, SpotLight, SunLight};
use spreadlight_render::shadows::{
    Cascades, ShadowError, ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings,
};

use super::add_light::{LightList, LightsPin};
use crate::gpu::renderer;

/// The Filter pin's options; the settings each needs come from other pins.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterKind {
    Raw,
    Pcf,
    Pcss,
    Vsm,
}

pub static SHADOW_FILTER: Choices<FilterKind> = Choices::new(
    "Shadow Filter",
    &["Raw", "PCF", "PCSS", "VSM"],
    &[
        FilterKind::Raw,
        FilterKind::Pcf,
        FilterKind::Pcss,
        FilterKind::Vsm,
    ],
);

/// The pins the three nodes share (the sun's cascade pins follow them), and
/// their output.
struct ShadowPins<T: Send + Sync + 'static> {
    layer: In<Res<Layer>>,
    gbuffer: In<Res<GBuffer>>,
    lights: LightsPin<T>,
    resolution: In<i64>,
    filter: In<Choice<FilterKind>>,
    kernel: In<i64>,
    light_size: In<f32>,
    samples: In<i64>,
    bleeding: In<f32>,
    blur: In<i64>,
    depth_bias: In<f32>,
    normal_bias: In<f32>,
    raster: In<Choice<RasterChoice>>,
    out: Out<Res<ShadowMaps>>,
}

// By hand: a derive would ask `T: Copy`, and only the handles are copied.
impl<T: Send + Sync + 'static> Clone for ShadowPins<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T: Send + Sync + 'static> Copy for ShadowPins<T> {}

impl<T: Clone + Send + Sync + 'static> ShadowPins<T> {
    fn declare(p: &mut Pins<'_>, kind: ResourceKind, light_size: f32) -> Self {
        ShadowPins {
            layer: p.input_resource::<Layer>("Layer", ResourceKind::Layer),
            gbuffer: p.input_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer),
            lights: LightList::input(p, kind),
            resolution: p.input("Resolution", 1024i64),
            filter: p.input_choice("Filter", &SHADOW_FILTER, FilterKind::Pcf),
            kernel: p.input("PCF Kernel", 3i64),
            light_size: p.input("Light Size", light_size),
            samples: p.input("PCSS Samples", 16i64),
            bleeding: p.input("VSM Bleeding", 0.2f32),
            blur: p.input("VSM Blur", 1i64),
            depth_bias: p.input("Depth Bias", 0.02f32),
            normal_bias: p.input("Normal Bias", 1.5f32),
            raster: p.input_choice("Raster", &crate::deferred::mre::RASTER, RasterChoice::Auto),
            out: p.output_resource::<ShadowMaps>("Shadows", ResourceKind::Shadows),
        }
    }
}

/// A node's help: its own first sentence, then what every ShadowMap's pins mean.
macro_rules! help {
    ($own:literal) => {
        concat!(
            $own,
            " Layer: the casters (DeferredBase or Group (Layer)). G-Buffer: the view the shadows are \
     for (lights outside it render nothing; sun cascades follow it). Filter: Raw (one texel), PCF (PCF Kernel x PCF \
     Kernel texels, odd, up to 9), PCSS (soft shadows from a light of Light Size, PCSS Samples 1..64 per search and \
     filter), VSM (blurred depth moments, VSM Blur texels, VSM Bleeding 0..1 cuts light bleeding). Depth Bias is in \
     world units, Normal Bias in texels. Raster: which rasterizer draws the maps, Compute (32-bit depth atomics), \
     Hardware, or Auto (per adapter: on a GPU compute, on a CPU \
     adapter the hardware)."
        )
    };
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "ShadowMap (Spot)",
            super::CATEGORY,
            help!("Shadow maps for spot lights: one layer each, seen through the spot's own view and projection."),
        )
        .with_pins(|p| {
            let pins = ShadowPins::<SpotLight>::declare(p, ResourceKind::SpotLights, 0.2);
            move |cx| {
                let list = LightList::gather(cx, pins.lights)?;
                let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.view, l.projection))).collect();
                build(cx, pins, ShadowLights::Spot(casting), &list.ids, list.lights.iter().map(|l| l.shadow))
            }
        }),
    );
    r.add(
        NodeDef::new(
            "ShadowMap (Point)",
            super::CATEGORY,
            help!("Shadow maps for point lights: six 90-degree faces each (a cube map array's layout), out to the light's range."),
        )
        .with_pins(|p| {
            let pins = ShadowPins::<PointLight>::declare(p, ResourceKind::PointLights, 0.2);
            move |cx| {
                let list = LightList::gather(cx, pins.lights)?;
                let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.position, l.range))).collect();
                build(cx, pins, ShadowLights::Point(casting), &list.ids, list.lights.iter().map(|l| l.shadow))
            }
        }),
    );
    r.add(
        NodeDef::new(
            "ShadowMap (Sun)",
            super::CATEGORY,
            help!(
                "Cascaded shadow maps for suns: Cascades (1..4) orthographic maps each, splitting the camera's view up to \
                 Distance; Split 0 spaces them evenly, 1 logarithmically (the practical scheme blends the two). For a sun, \
                 Light Size is the tangent of its angular radius (0.0047 for ours). Cascade Step 0 moves each cascade \
                 with the camera texel by texel (scrolled: only the texels a move uncovers are drawn); 0.1..0.5 widens each cascade by \
                 that share of its width on each side and moves it only in steps of that share, so a camera moving \
                 within a step re-renders no map."
            ),
        )
        .with_pins(|p| {
            let pins = ShadowPins::<SunLight>::declare(p, ResourceKind::SunLights, 0.01);
            let cascades = p.input("Cascades", 4i64);
            let split = p.input("Split", 0.6f32);
            let distance = p.input("Distance", 60.0f32);
            let step = p.input("Cascade Step", 0.0f32);
            move |cx| {
                let list = LightList::gather(cx, pins.lights)?;
                let cascades = Cascades {
                    count: cx.first(cascades, 4)?.clamp(1, 4) as u32,
                    split_lambda: cx.first(split, 0.6)?,
                    distance: cx.first(distance, 60.0)?,
                    step: cascade_step(cx, step)?,
                };
                let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.direction))).collect();
                build(cx, pins, ShadowLights::Sun { lights: casting, cascades }, &list.ids, list.lights.iter().map(|l| l.shadow))
            }
        }),
    );
}

/// The sun's Cascade Step: 0 or 0.01..=0.5 (a share of a cascade's width).
fn cascade_step(cx: &EvalContext<'_>, pin: In<f32>) -> Result<f32, NodeError> {
    let step = cx.first(pin, 0.0)?;
    if step.is_finite() && (step == 0.0 || (0.01..=0.5).contains(&step)) {
        Ok(step)
    } else {
        Err(cx.error(pin, format!("is {step}; it must be 0 or 0.01..=0.5")))
    }
}

/// The node's settings from its pins; a value outside its range is an error naming the pin.
fn settings<T: Send + Sync + 'static>(
    cx: &EvalContext<'_>,
    pins: ShadowPins<T>,
) -> Result<ShadowSettings, NodeError> {
    for pin in [
        pins.light_size,
        pins.bleeding,
        pins.depth_bias,
        pins.normal_bias,
    ] {
        super::require_finite(cx, pin)?;
    }
    let resolution = cx.first(pins.resolution, 1024)?;
    let resolution = u32::try_from(resolution)
        .ok()
        .filter(|r| (16..=spreadlight_render::shadows::MAX_RESOLUTION).contains(r))
        .ok_or_else(|| {
            cx.error(
                pins.resolution,
                format!(
                    "is {resolution}; it must be 16..={}",
                    spreadlight_render::shadows::MAX_RESOLUTION
                ),
            )
        })?;
    let kernel = cx.first(pins.kernel, 3)?;
    let filter = match cx.choice(pins.filter)? {
        FilterKind::Raw => ShadowFilter::Raw,
        FilterKind::Pcss => ShadowFilter::Pcss {
            light_size: cx.first(pins.light_size, 0.2)?,
            samples: cx.first(pins.samples, 16)?.clamp(1, 64) as u32,
        },
        FilterKind::Vsm => ShadowFilter::Vsm {
            bleeding: cx.first(pins.bleeding, 0.2)?,
            blur: cx.first(pins.blur, 1)?.clamp(0, 8) as u32,
        },
        FilterKind::Pcf => {
            if !(1..=9).contains(&kernel) || kernel % 2 == 0 {
                return Err(cx.error(pins.kernel, format!("is {kernel}; it must be odd, 1..=9")));
            }
            ShadowFilter::Pcf {
                kernel: kernel as u32,
            }
        }
    };
    Ok(ShadowSettings {
        resolution,
        filter,
        depth_bias: cx.first(pins.depth_bias, 0.02)?,
        normal_bias: cx.first(pins.normal_bias, 1.5)?,
        raster: cx.choice(pins.raster)?,
    })
}

/// The maps of `lights` as the node's output. A slice given twice names the lights that share it.
fn build<T: Send + Sync + 'static>(
    cx: &mut EvalContext<'_>,
    pins: ShadowPins<T>,
    lights: ShadowLights,
    ids: &[String],
    slices: impl Iterator<Item = Option<u32>>,
) -> Result<(), NodeError> {
    let renderer = renderer(cx)?;
    let settings = settings(cx, pins)?;
    let casters: Vec<std::sync::Arc<Layer>> = cx.resources(pins.layer)?;
    let gbuffer = cx.first_resource(pins.gbuffer)?.ok_or_else(|| {
        cx.error(
            pins.gbuffer,
            "no G-buffer connected: the shadows need the view they are for",
        )
    })?;
    let slices: Vec<Option<u32>> = slices.collect();
    let maps = ShadowMaps::new(
        &renderer,
        Some(cx.node_id.0),
        &lights,
        casters,
        &gbuffer.camera,
        settings,
    )
    .map_err(|e| match e {
        ShadowError::SliceTwice { slice } => {
            let owners: Vec<&str> = ids
                .iter()
                .zip(&slices)
                .filter(|(_, s)| **s == Some(slice))
                .map(|(id, _)| id.as_str())
                .collect();
            cx.error(
                pins.lights,
                format!(
                    "shadow slice {slice} is given to lights `{}`",
                    owners.join("`, `")
                ),
            )
        }
        ShadowError::Resolution(..) => cx.error(pins.resolution, e.to_string()),
        ShadowError::TooManySlices { .. } => cx.error(pins.lights, e.to_string()),
    })?;
    cx.put_resources(pins.out, vec![maps]);
    Ok(())
}

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
    EnumDef, EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};
use spreadlight_render::lighting::{PointLight, SpotLight, SunLight};
use spreadlight_render::shadows::{
    Cascades, ShadowError, ShadowFilter, ShadowLights, ShadowMaps, ShadowSettings,
};

use super::add_light::LightList;
use crate::gpu::{renderer, resource_spread, resources};

pub static SHADOW_FILTER: EnumDef = EnumDef {
    name: "Shadow Filter",
    options: &["Raw", "PCF", "PCSS", "VSM"],
};

// Pin indices shared by the three nodes; the sun's cascade pins follow.
const LAYER: usize = 0;
const GBUFFER: usize = 1;
const LIGHTS: usize = 2;
const RESOLUTION: usize = 3;
const FILTER: usize = 4;
const KERNEL: usize = 5;
const LIGHT_SIZE: usize = 6;
const SAMPLES: usize = 7;
const BLEEDING: usize = 8;
const BLUR: usize = 9;
const DEPTH_BIAS: usize = 10;
const NORMAL_BIAS: usize = 11;
const RASTER: usize = 12;
const CASCADES: usize = 13;
const SPLIT: usize = 14;
const DISTANCE: usize = 15;
const CASCADE_STEP: usize = 16;

fn node(name: &'static str, lights: ResourceKind, help: &'static str, light_size: f32) -> NodeDef {
    NodeDef::new(name, super::CATEGORY, help)
        .input_spread(
            "Layer",
            PinType::Resource(ResourceKind::Layer),
            Spread::Resource(ResourceKind::Layer, vec![]),
        )
        .input_spread(
            "G-Buffer",
            PinType::Resource(ResourceKind::GBuffer),
            Spread::Resource(ResourceKind::GBuffer, vec![]),
        )
        .input_spread(
            "Lights",
            PinType::Resource(lights),
            Spread::Resource(lights, vec![]),
        )
        .input("Resolution", 1024i64)
        .input_enum("Filter", &SHADOW_FILTER, "PCF")
        .input("PCF Kernel", 3i64)
        .input("Light Size", light_size)
        .input("PCSS Samples", 16i64)
        .input("VSM Bleeding", 0.2f32)
        .input("VSM Blur", 1i64)
        .input("Depth Bias", 0.02f32)
        .input("Normal Bias", 1.5f32)
        .input_enum("Raster", &crate::deferred::mre::RASTER, "Auto")
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
     Hardware, or Auto (per adapter: on a GPU compute up to 1024 texels a side and the hardware beyond, on a CPU \
     adapter the hardware)."
        )
    };
}

pub fn register(r: &mut Registry) {
    r.add(
        node(
            "ShadowMap (Spot)",
            ResourceKind::SpotLights,
            help!("Shadow maps for spot lights: one layer each, seen through the spot's own view and projection."),
            0.2,
        )
        .output_typed("Shadows", PinType::Resource(ResourceKind::Shadows))
        .evaluate(|cx| {
            let list = LightList::<SpotLight>::gather(cx, LIGHTS)?;
            let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.view, l.projection))).collect();
            build(cx, ShadowLights::Spot(casting), &list.ids, list.lights.iter().map(|l| l.shadow))
        }),
    );
    r.add(
        node(
            "ShadowMap (Point)",
            ResourceKind::PointLights,
            help!("Shadow maps for point lights: six 90-degree faces each (a cube map array's layout), out to the light's range."),
            0.2,
        )
        .output_typed("Shadows", PinType::Resource(ResourceKind::Shadows))
        .evaluate(|cx| {
            let list = LightList::<PointLight>::gather(cx, LIGHTS)?;
            let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.position, l.range))).collect();
            build(cx, ShadowLights::Point(casting), &list.ids, list.lights.iter().map(|l| l.shadow))
        }),
    );
    r.add(
        node(
            "ShadowMap (Sun)",
            ResourceKind::SunLights,
            help!(
                "Cascaded shadow maps for suns: Cascades (1..4) orthographic maps each, splitting the camera's view up to \
                 Distance; Split 0 spaces them evenly, 1 logarithmically (the practical scheme blends the two). For a sun, \
                 Light Size is the tangent of its angular radius (0.0047 for ours). Cascade Step 0 moves each cascade \
                 with the camera texel by texel (re-rendered whenever the camera moves); 0.1..0.5 widens each cascade by \
                 that share of its width on each side and moves it only in steps of that share, so a camera moving \
                 within a step re-renders no map."
            ),
            0.01,
        )
        .input("Cascades", 4i64)
        .input("Split", 0.6f32)
        .input("Distance", 60.0f32)
        .input("Cascade Step", 0.0f32)
        .output_typed("Shadows", PinType::Resource(ResourceKind::Shadows))
        .evaluate(|cx| {
            let list = LightList::<SunLight>::gather(cx, LIGHTS)?;
            let cascades = Cascades {
                count: first(cx.slices::<i64>(CASCADES)?, 4).clamp(1, 4) as u32,
                split_lambda: first(cx.slices::<f32>(SPLIT)?, 0.6),
                distance: first(cx.slices::<f32>(DISTANCE)?, 60.0),
                step: cascade_step(cx)?,
            };
            let casting = list.lights.iter().filter_map(|l| l.shadow.map(|s| (s, l.direction))).collect();
            build(cx, ShadowLights::Sun { lights: casting, cascades }, &list.ids, list.lights.iter().map(|l| l.shadow))
        }),
    );
}

/// The sun's Cascade Step: 0 or 0.01..=0.5 (a share of a cascade's width).
fn cascade_step(cx: &EvalContext<'_>) -> Result<f32, NodeError> {
    let step = first(cx.slices::<f32>(CASCADE_STEP)?, 0.0);
    if step.is_finite() && (step == 0.0 || (0.01..=0.5).contains(&step)) {
        Ok(step)
    } else {
        Err(cx.input_error(
            CASCADE_STEP,
            format!("is {step}; it must be 0 or 0.01..=0.5"),
        ))
    }
}

fn first<T: Copy>(slices: &[T], fallback: T) -> T {
    slices.first().copied().unwrap_or(fallback)
}

/// The node's settings from its pins; a value outside its range is an error naming the pin.
fn settings(cx: &EvalContext<'_>) -> Result<ShadowSettings, NodeError> {
    for pin in [LIGHT_SIZE, BLEEDING, DEPTH_BIAS, NORMAL_BIAS] {
        if let Some(slice) = cx.input(pin).first_non_finite() {
            return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
        }
    }
    let resolution = first(cx.slices::<i64>(RESOLUTION)?, 1024);
    let resolution = u32::try_from(resolution)
        .ok()
        .filter(|r| (16..=spreadlight_render::shadows::MAX_RESOLUTION).contains(r))
        .ok_or_else(|| {
            cx.input_error(
                RESOLUTION,
                format!(
                    "is {resolution}; it must be 16..={}",
                    spreadlight_render::shadows::MAX_RESOLUTION
                ),
            )
        })?;
    let kernel = first(cx.slices::<i64>(KERNEL)?, 3);
    let filter = match cx.enum_slices(FILTER)?.first().map(String::as_str) {
        Some("Raw") => ShadowFilter::Raw,
        Some("PCSS") => ShadowFilter::Pcss {
            light_size: first(cx.slices::<f32>(LIGHT_SIZE)?, 0.2),
            samples: first(cx.slices::<i64>(SAMPLES)?, 16).clamp(1, 64) as u32,
        },
        Some("VSM") => ShadowFilter::Vsm {
            bleeding: first(cx.slices::<f32>(BLEEDING)?, 0.2),
            blur: first(cx.slices::<i64>(BLUR)?, 1).clamp(0, 8) as u32,
        },
        _ => {
            if !(1..=9).contains(&kernel) || kernel % 2 == 0 {
                return Err(cx.input_error(KERNEL, format!("is {kernel}; it must be odd, 1..=9")));
            }
            ShadowFilter::Pcf {
                kernel: kernel as u32,
            }
        }
    };
    Ok(ShadowSettings {
        resolution,
        filter,
        depth_bias: first(cx.slices::<f32>(DEPTH_BIAS)?, 0.02),
        normal_bias: first(cx.slices::<f32>(NORMAL_BIAS)?, 1.5),
        raster: match cx.enum_slices(RASTER)?.first().map(String::as_str) {
            Some("Compute") => RasterChoice::Compute,
            Some("Hardware") => RasterChoice::Hardware,
            _ => RasterChoice::Auto,
        },
    })
}

/// The maps of `lights` as the node's output. A slice given twice names the lights that share it.
fn build(
    cx: &mut EvalContext<'_>,
    lights: ShadowLights,
    ids: &[String],
    slices: impl Iterator<Item = Option<u32>>,
) -> Result<(), NodeError> {
    let renderer = renderer(cx)?;
    let settings = settings(cx)?;
    let casters: Vec<std::sync::Arc<Layer>> = resources::<Layer>(cx, LAYER)?;
    let gbuffer = resources::<GBuffer>(cx, GBUFFER)?
        .into_iter()
        .next()
        .ok_or_else(|| {
            cx.input_error(
                GBUFFER,
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
            cx.input_error(
                LIGHTS,
                format!(
                    "shadow slice {slice} is given to lights `{}`",
                    owners.join("`, `")
                ),
            )
        }
        ShadowError::Resolution(..) => cx.input_error(RESOLUTION, e.to_string()),
        ShadowError::TooManySlices { .. } => cx.input_error(LIGHTS, e.to_string()),
    })?;
    cx.set_output(0, resource_spread(ResourceKind::Shadows, vec![maps]));
    Ok(())
}

//! `EnvironmentProbe`: the scene itself as an environment. A layer is
//! rendered into a cube map from a point (each surface's colour lit by the
//! probe's ambient and sun, the background a colour) and prefiltered like
//! `Environment (Sky)`, so it plugs into Reflection, Sky and the diffuse
//! light wherever an Environment goes. It renders again only when what it
//! sees changed (or every N frames, or once), and with a box or sphere
//! influence volume Reflection corrects each ray for parallax.

use glam::Vec3;
use spreadlight_graph::{
    Color, EnumDef, EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, ProbeLighting, ProbeScene, ProbeSettings,
    ProbeUpdate, ProbeVolume,
};
use spreadlight_render::gbuffer::Layer;

use crate::gpu::{renderer, resource_spread, resources};

pub static PROBE_VOLUME: EnumDef = EnumDef {
    name: "Probe Volume",
    options: &["None", "Box", "Sphere"],
};

pub static PROBE_UPDATE: EnumDef = EnumDef {
    name: "Probe Update",
    options: &["On Change", "Every N Frames", "Once"],
};

// Pin indices.
const LAYER: usize = 0;
const POSITION: usize = 1;
const VOLUME: usize = 2;
const VOLUME_CENTER: usize = 3;
const VOLUME_SIZE: usize = 4;
const VOLUME_RADIUS: usize = 5;
const SUN_DIRECTION: usize = 6;
const SUN_COLOR: usize = 7;
const SUN_INTENSITY: usize = 8;
const AMBIENT: usize = 9;
const BACKGROUND: usize = 10;
const UPDATE: usize = 11;
const EVERY: usize = 12;
const CUBE_SIZE: usize = 13;
const SAMPLES: usize = 14;

/// The probe's defaults: a cube small enough to render often.
pub const DEFAULT_QUALITY: EnvironmentQuality = EnvironmentQuality {
    cube_size: 64,
    samples: 32,
};

fn rgb(c: &Color) -> Vec3 {
    Vec3::new(c.r, c.g, c.b)
}

fn first<T: Clone>(slices: &[T], fallback: T) -> T {
    slices.first().cloned().unwrap_or(fallback)
}

fn settings(cx: &EvalContext<'_>) -> Result<(ProbeSettings, EnvironmentQuality), NodeError> {
    // NaN or infinity anywhere is an error on its pin (a NaN position would
    // put NaN in every texel of the cube).
    for pin in POSITION..=SAMPLES {
        if let Some(slice) = cx.input(pin).first_non_finite() {
            return Err(cx.input_error(pin, format!("slice {slice} is NaN or infinite")));
        }
    }
    let vec3 = |pin: usize, fallback: Vec3| -> Result<Vec3, NodeError> {
        Ok(first(cx.slices::<Vec3>(pin)?, fallback))
    };
    let color = |pin: usize, fallback: Vec3| -> Result<Vec3, NodeError> {
        Ok(cx.slices::<Color>(pin)?.first().map_or(fallback, rgb))
    };
    let size = vec3(VOLUME_SIZE, Vec3::splat(10.0))?;
    if size.min_element() < 0.0 {
        return Err(cx.input_error(
            VOLUME_SIZE,
            format!("is {size}; a size cannot be negative (0: no parallax)"),
        ));
    }
    let radius = first(cx.slices::<f32>(VOLUME_RADIUS)?, 5.0);
    if radius < 0.0 {
        return Err(cx.input_error(
            VOLUME_RADIUS,
            format!("is {radius}; a radius cannot be negative (0: no parallax)"),
        ));
    }
    let center = vec3(VOLUME_CENTER, Vec3::ZERO)?;
    let volume = match cx.enum_slices(VOLUME)?.first().map(String::as_str) {
        Some("Box") => ProbeVolume::Box { center, size },
        Some("Sphere") => ProbeVolume::Sphere { center, radius },
        _ => ProbeVolume::Infinite,
    };
    let int = |pin: usize, fallback: u32| -> Result<u32, NodeError> {
        let v = first(cx.slices::<i64>(pin)?, i64::from(fallback));
        if v < 1 {
            return Err(cx.input_error(pin, format!("must be at least 1, got {v}")));
        }
        Ok(v.min(i64::from(u32::MAX)) as u32)
    };
    let update = match cx.enum_slices(UPDATE)?.first().map(String::as_str) {
        Some("Every N Frames") => ProbeUpdate::EveryNFrames(int(EVERY, 1)?),
        Some("Once") => ProbeUpdate::Once,
        _ => ProbeUpdate::OnChange,
    };
    let d = ProbeLighting::default();
    let intensity = first(cx.slices::<f32>(SUN_INTENSITY)?, 2.0).max(0.0);
    let lighting = ProbeLighting {
        sun_direction: vec3(SUN_DIRECTION, d.sun_direction)?,
        sun_color: color(SUN_COLOR, Vec3::ONE)?.max(Vec3::ZERO) * intensity,
        ambient: color(AMBIENT, d.ambient)?.max(Vec3::ZERO),
        background: color(BACKGROUND, d.background)?.max(Vec3::ZERO),
    };
    let quality = EnvironmentQuality {
        cube_size: int(CUBE_SIZE, DEFAULT_QUALITY.cube_size)?,
        samples: int(SAMPLES, DEFAULT_QUALITY.samples)?,
    };
    let settings = ProbeSettings {
        position: vec3(POSITION, Vec3::new(0.0, 1.0, 0.0))?,
        volume,
        lighting,
        update,
    };
    Ok((settings, quality))
}

pub fn register(r: &mut Registry) {
    let d = ProbeLighting::default();
    let color = |v: Vec3| Color::rgba(v.x, v.y, v.z, 1.0);
    r.add(
        NodeDef::new(
            "EnvironmentProbe",
            super::CATEGORY,
            "The scene as an environment: Layer rendered into a cube map from Position, prefiltered like Environment \
             (Sky), for Reflection, Sky and the diffuse light. What the faces show is a forward shading of the layer: \
             each instance's colour times its layer's Color Texture times (Ambient + Sun Color x Sun Intensity x \
             N.L, the sun travelling along Sun Direction), no shadows; Background where nothing is. Update: On \
             Change renders again only when the layer's instances, colours, meshes or Color Texture, the position \
             or the lighting changed (a moved camera \
             does not); Every N Frames every N-th frame regardless; Once the first frame. `spreadlight stats` counts \
             \"environment probe rendered\" and \"reused\". Volume: with a Box (Volume Center, Volume Size) or Sphere \
             (Volume Radius) around the room, Reflection corrects each ray for parallax (box-projected reflections); \
             None, or a zero size, reads the cube as infinitely far. Cube Size (a power of two, 8..1024) and Samples \
             trade time for accuracy (`spreadlight accuracy probe`).",
        )
        .input_spread("Layer", PinType::Resource(ResourceKind::Layer), Spread::Resource(ResourceKind::Layer, vec![]))
        .input("Position", Vec3::new(0.0, 1.0, 0.0))
        .input_enum("Volume", &PROBE_VOLUME, "None")
        .input("Volume Center", Vec3::ZERO)
        .input("Volume Size", Vec3::splat(10.0))
        .input("Volume Radius", 5.0f32)
        .input("Sun Direction", d.sun_direction)
        .input("Sun Color", Color::WHITE)
        .input("Sun Intensity", 2.0f32)
        .input("Ambient", color(d.ambient))
        .input("Background", color(d.background))
        .input_enum("Update", &PROBE_UPDATE, "On Change")
        .input("Every N", 1i64)
        .input("Cube Size", i64::from(DEFAULT_QUALITY.cube_size))
        .input("Samples", i64::from(DEFAULT_QUALITY.samples))
        .output_typed("Environment", PinType::Resource(ResourceKind::Environment))
        .evaluate(|cx| {
            let (settings, quality) = settings(cx)?;
            let layers = resources::<Layer>(cx, LAYER)?;
            let scene = ProbeScene::new(layers, settings).map_err(|e| cx.input_error(POSITION, e.to_string()))?;
            let renderer = renderer(cx)?;
            let environment =
                Environment::new(&renderer, Some(cx.node_id.0), EnvironmentSource::Probe(std::sync::Arc::new(scene)), quality);
            cx.set_output(0, resource_spread::<Environment>(ResourceKind::Environment, vec![environment]));
            Ok(())
        }),
    );
}

//! `EnvironmentProbe`: the scene itself as an environment. A layer is
//! rendered into a cube map from a point (each surface's colour lit by the
//! probe's ambient and sun, the background a colour) and prefiltered like
//! `Environment (Sky)`, so it plugs into Reflection, Sky and the diffuse
//! light wherever an Environment goes. It renders again only when what it
//! sees changed (or every N frames, or once), and with a box or sphere
//! influence volume Reflection corrects each ray for parallax. Given a
//! ShadowMap (Sun)'s Shadows, its sun is shadowed; a layer's Normal Map
//! perturbs what it lights, and a glTF layer's surface maps colour and shape
//! it. Point and spot light buffers (Lights, shadowed by Light Shadows) add
//! their light to what it sees, as CookTorrance adds it to the G-buffer.

use glam::Vec3;
use spreadlight_graph::{
    Choice, Choices, Color, EvalContext, In, NodeDef, NodeError, Out, Registry, Res, ResourceKind,
};
use spreadlight_render::environment::probe::DEFAULT_MAX_LIGHTS;
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, ProbeLighting, ProbeLights, ProbeScene,
    ProbeSettings, ProbeShadow, ProbeUpdate, ProbeVolume,
};
use spreadlight_render::gbuffer::Layer;
use spreadlight_render::lighting::LightBuffer;
use spreadlight_render::shadows::ShadowMaps;

use crate::gpu::renderer;
use crate::lighting::require_finite;

/// The Volume pin's options (the volume's measures come from other pins).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VolumeKind {
    None,
    Box,
    Sphere,
}

pub static PROBE_VOLUME: Choices<VolumeKind> = Choices::new(
    "Probe Volume",
    &["None", "Box", "Sphere"],
    &[VolumeKind::None, VolumeKind::Box, VolumeKind::Sphere],
);

/// The Update pin's options (Every N Frames takes its N from Every N).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpdateKind {
    OnChange,
    EveryNFrames,
    Once,
}

pub static PROBE_UPDATE: Choices<UpdateKind> = Choices::new(
    "Probe Update",
    &["On Change", "Every N Frames", "Once"],
    &[
        UpdateKind::OnChange,
        UpdateKind::EveryNFrames,
        UpdateKind::Once,
    ],
);

#[derive(Clone, Copy)]
struct ProbePins {
    layer: In<Res<Layer>>,
    position: In<Vec3>,
    volume: In<Choice<VolumeKind>>,
    volume_center: In<Vec3>,
    volume_size: In<Vec3>,
    volume_radius: In<f32>,
    sun_direction: In<Vec3>,
    sun_color: In<Color>,
    sun_intensity: In<f32>,
    ambient: In<Color>,
    background: In<Color>,
    update: In<Choice<UpdateKind>>,
    every: In<i64>,
    cube_size: In<i64>,
    samples: In<i64>,
    shadows: In<Res<ShadowMaps>>,
    shadow_slice: In<i64>,
    lights: In<Res<LightBuffer>>,
    light_shadows: In<Res<ShadowMaps>>,
    max_lights: In<i64>,
    out: Out<Res<Environment>>,
}

/// The probe's defaults: a cube small enough to render often.
pub const DEFAULT_QUALITY: EnvironmentQuality = EnvironmentQuality {
    cube_size: 64,
    samples: 32,
};

fn rgb(c: &Color) -> Vec3 {
    Vec3::new(c.r, c.g, c.b)
}

fn settings(
    cx: &EvalContext<'_>,
    pins: ProbePins,
) -> Result<(ProbeSettings, EnvironmentQuality), NodeError> {
    // NaN or infinity anywhere is an error on its pin (a NaN position would
    // put NaN in every texel of the cube).
    require_finite(cx, pins.position)?;
    for pin in [pins.volume_center, pins.volume_size] {
        require_finite(cx, pin)?;
    }
    require_finite(cx, pins.volume_radius)?;
    require_finite(cx, pins.sun_direction)?;
    require_finite(cx, pins.sun_color)?;
    require_finite(cx, pins.sun_intensity)?;
    for pin in [pins.ambient, pins.background] {
        require_finite(cx, pin)?;
    }
    for pin in [pins.every, pins.cube_size, pins.samples] {
        require_finite(cx, pin)?;
    }
    let color = |pin: In<Color>, fallback: Vec3| -> Result<Vec3, NodeError> {
        Ok(cx.get(pin)?.first().map_or(fallback, rgb))
    };
    let size = cx.first(pins.volume_size, Vec3::splat(10.0))?;
    if size.min_element() < 0.0 {
        return Err(cx.error(
            pins.volume_size,
            format!("is {size}; a size cannot be negative (0: no parallax)"),
        ));
    }
    let radius = cx.first(pins.volume_radius, 5.0)?;
    if radius < 0.0 {
        return Err(cx.error(
            pins.volume_radius,
            format!("is {radius}; a radius cannot be negative (0: no parallax)"),
        ));
    }
    let center = cx.first(pins.volume_center, Vec3::ZERO)?;
    let volume = match cx.choice(pins.volume)? {
        VolumeKind::Box => ProbeVolume::Box { center, size },
        VolumeKind::Sphere => ProbeVolume::Sphere { center, radius },
        VolumeKind::None => ProbeVolume::Infinite,
    };
    let int = |pin: In<i64>, fallback: u32| -> Result<u32, NodeError> {
        let v = cx.first(pin, i64::from(fallback))?;
        if v < 1 {
            return Err(cx.error(pin, format!("must be at least 1, got {v}")));
        }
        Ok(v.min(i64::from(u32::MAX)) as u32)
    };
    let update = match cx.choice(pins.update)? {
        UpdateKind::EveryNFrames => ProbeUpdate::EveryNFrames(int(pins.every, 1)?),
        UpdateKind::Once => ProbeUpdate::Once,
        UpdateKind::OnChange => ProbeUpdate::OnChange,
    };
    let d = ProbeLighting::default();
    let intensity = cx.first(pins.sun_intensity, 2.0)?.max(0.0);
    let lighting = ProbeLighting {
        sun_direction: cx.first(pins.sun_direction, d.sun_direction)?,
        sun_color: color(pins.sun_color, Vec3::ONE)?.max(Vec3::ZERO) * intensity,
        ambient: color(pins.ambient, d.ambient)?.max(Vec3::ZERO),
        background: color(pins.background, d.background)?.max(Vec3::ZERO),
    };
    let quality = EnvironmentQuality {
        cube_size: int(pins.cube_size, DEFAULT_QUALITY.cube_size)?,
        samples: int(pins.samples, DEFAULT_QUALITY.samples)?,
    };
    let settings = ProbeSettings {
        position: cx.first(pins.position, Vec3::new(0.0, 1.0, 0.0))?,
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
             N.L, the sun travelling along Sun Direction), N perturbed by the layer's Normal Map as the G-buffer \
             does; Background where nothing is. Shadows: a ShadowMap (Sun)'s maps shadow the sun, slice Shadow \
             Slice (the AddLight (Sun)'s; give the probe that sun's direction), in the finest cascade that holds \
             each point (cascades follow the camera: beyond them, lit). A glTF layer's surface maps (base colour, \
             normal, metallic-roughness, occlusion, emissive) are read as the G-buffer reads them. Lights: point and \
             spot light buffers (AddLight's) add their Cook-Torrance light to the faces (the surfaces rough \
             dielectrics, roughness 0.5, unless a glTF material says otherwise; the viewer at Position), shadowed by \
             the ShadowMap of their type in Light Shadows; each face adds at most Max Lights of each buffer (its \
             first ones; 0: none). Update: On \
             Change renders again only when the layer's instances, colours, meshes, Color Texture, Normal Map or \
             glTF materials, the position, the lighting, the lights, or the shadows' lights or casters changed (a \
             moved camera does not); Every N Frames every N-th frame regardless; Once the first frame. `spreadlight stats` counts \
             \"environment probe rendered\" and \"reused\". Volume: with a Box (Volume Center, Volume Size) or Sphere \
             (Volume Radius) around the room, Reflection corrects each ray for parallax (box-projected reflections); \
             None, or a zero size, reads the cube as infinitely far. Cube Size (a power of two, 8..1024) and Samples \
             trade time for accuracy (`spreadlight accuracy probe`).",
        )
        .with_pins(|p| {
            let pins = ProbePins {
                layer: p.input_resource::<Layer>("Layer", ResourceKind::Layer),
                position: p.input("Position", Vec3::new(0.0, 1.0, 0.0)),
                volume: p.input_choice("Volume", &PROBE_VOLUME, VolumeKind::None),
                volume_center: p.input("Volume Center", Vec3::ZERO),
                volume_size: p.input("Volume Size", Vec3::splat(10.0)),
                volume_radius: p.input("Volume Radius", 5.0f32),
                sun_direction: p.input("Sun Direction", d.sun_direction),
                sun_color: p.input("Sun Color", Color::WHITE),
                sun_intensity: p.input("Sun Intensity", 2.0f32),
                ambient: p.input("Ambient", color(d.ambient)),
                background: p.input("Background", color(d.background)),
                update: p.input_choice("Update", &PROBE_UPDATE, UpdateKind::OnChange),
                every: p.input("Every N", 1i64),
                cube_size: p.input("Cube Size", i64::from(DEFAULT_QUALITY.cube_size)),
                samples: p.input("Samples", i64::from(DEFAULT_QUALITY.samples)),
                shadows: p.input_resource::<ShadowMaps>("Shadows", ResourceKind::Shadows),
                shadow_slice: p.input("Shadow Slice", 0i64),
                lights: p.input_resource::<LightBuffer>("Lights", ResourceKind::LightWorld),
                light_shadows: p.input_resource::<ShadowMaps>("Light Shadows", ResourceKind::Shadows),
                max_lights: p.input("Max Lights", i64::from(DEFAULT_MAX_LIGHTS)),
                out: p.output_resource::<Environment>("Environment", ResourceKind::Environment),
            };
            move |cx| {
                let (settings, quality) = settings(cx, pins)?;
                let layers = cx.resources(pins.layer)?;
                let scene = ProbeScene::new(layers, settings).map_err(|e| cx.error(pins.position, e.to_string()))?;
                let shadow = match cx.first_resource(pins.shadows)? {
                    Some(maps) => {
                        require_finite(cx, pins.shadow_slice)?;
                        let slice = cx.first(pins.shadow_slice, 0)?;
                        let slice = u32::try_from(slice)
                            .map_err(|_| cx.error(pins.shadow_slice, format!("is {slice}; a slice is 0 or more")))?;
                        Some(ProbeShadow { maps, slice })
                    }
                    None => None,
                };
                let scene = scene.with_sun_shadow(shadow).map_err(|e| cx.error(pins.shadows, e.to_string()))?;
                require_finite(cx, pins.max_lights)?;
                let max_lights = cx.first(pins.max_lights, i64::from(DEFAULT_MAX_LIGHTS))?;
                let max_lights = u32::try_from(max_lights)
                    .map_err(|_| cx.error(pins.max_lights, format!("is {max_lights}; the count is 0 or more")))?;
                let shadows = cx.resources(pins.light_shadows)?;
                // Each light buffer is shadowed by the maps of its type: two of one type would be a guess.
                for (i, s) in shadows.iter().enumerate() {
                    if shadows[..i].iter().any(|other| other.kind == s.kind) {
                        return Err(cx.error(
                            pins.light_shadows,
                            format!("slices hold two shadow maps of {:?} lights: connect one per light type", s.kind),
                        ));
                    }
                }
                let lights = cx
                    .resources(pins.lights)?
                    .into_iter()
                    .map(|lights| ProbeLights {
                        shadows: shadows.iter().find(|s| s.kind == lights.kind).cloned(),
                        lights,
                    })
                    .collect();
                let scene =
                    scene.with_lights(lights, max_lights).map_err(|e| cx.error(pins.lights, e.to_string()))?;
                let renderer = renderer(cx)?;
                let environment =
                    Environment::new(&renderer, Some(cx.node_id.0), EnvironmentSource::Probe(std::sync::Arc::new(scene)), quality);
                cx.put_resources(pins.out, vec![environment]);
                Ok(())
            }
        }),
    );
}

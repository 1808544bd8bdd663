//! `Environment (File)` and `Environment (Sky)`: a prefiltered environment
//! for image-based light (`Reflection`, `SSR`'s fallback through it, `Sky`'s
//! background). Built on the GPU once and kept under the node; rebuilt only
//! when the image, the sky or the quality pins change.

use std::sync::Arc;

use spreadlight_graph::{EvalContext, NodeDef, NodeError, PinType, Registry, ResourceKind};
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, EquirectImage,
};

use super::sky::{read_sky, sky_pins};
use crate::gpu::{renderer, resource_spread};

fn with_quality(def: NodeDef) -> NodeDef {
    let d = EnvironmentQuality::default();
    def.input("Cube Size", i64::from(d.cube_size))
        .input("Samples", i64::from(d.samples))
}

fn quality(cx: &EvalContext<'_>, first: usize) -> Result<EnvironmentQuality, NodeError> {
    let int = |pin: usize, fallback: u32| -> Result<u32, NodeError> {
        let v = cx
            .slices::<i64>(pin)?
            .first()
            .copied()
            .unwrap_or(i64::from(fallback));
        if v < 1 {
            return Err(cx.input_error(pin, format!("must be at least 1, got {v}")));
        }
        Ok(v.min(i64::from(u32::MAX)) as u32)
    };
    let d = EnvironmentQuality::default();
    Ok(EnvironmentQuality {
        cube_size: int(first, d.cube_size)?,
        samples: int(first + 1, d.samples)?,
    })
}

fn output(
    cx: &mut EvalContext<'_>,
    source: EnvironmentSource,
    quality: EnvironmentQuality,
) -> Result<(), NodeError> {
    let renderer = renderer(cx)?;
    let environment = Environment::new(&renderer, Some(cx.node_id.0), source, quality);
    cx.set_output(
        0,
        resource_spread::<Environment>(ResourceKind::Environment, vec![environment]),
    );
    Ok(())
}

pub fn register(r: &mut Registry) {
    r.add(
        with_quality(
            NodeDef::new(
                "Environment (File)",
                super::CATEGORY,
                "An environment from an equirectangular .hdr or .exr image (a relative Filename is relative to the patch's \
                 folder; the image's centre looks along -z, its top straight up): a cube map prefiltered per roughness, its \
                 diffuse irradiance and the split-sum table. Radiance above 65000 is clamped (half floats); NaN reads as 0. \
                 Cube Size: the face size in texels (a power of two, 8..1024); Samples: GGX samples per texel of each rough \
                 level (1..4096); both trade build time for accuracy (`spreadlight accuracy reflection`).",
            )
            .input("Filename", String::new()),
        )
        .output_typed("Environment", PinType::Resource(ResourceKind::Environment))
        .evaluate(|cx| {
            let file = cx.slices::<String>(0)?.first().cloned().unwrap_or_default();
            if file.is_empty() {
                return Err(cx.input_error(0, "no file given"));
            }
            // The file first: its errors name it, with or without a GPU.
            let image = EquirectImage::load(&cx.resolve_path(&file)).map_err(|e| cx.input_error(0, e.to_string()))?;
            let quality = quality(cx, 1)?;
            output(cx, EnvironmentSource::Equirect(Arc::new(image)), quality)
        }),
    );
    r.add(
        with_quality(sky_pins(NodeDef::new(
            "Environment (Sky)",
            super::CATEGORY,
            "The procedural sky of the Sky node (same pins, same look) as an environment: a cube map prefiltered per roughness, \
             its diffuse irradiance and the split-sum table. Connect it to Sky's Environment too and the background matches. \
             Cube Size: the face size in texels (a power of two, 8..1024); Samples: GGX samples per texel of each rough \
             level (1..4096); both trade build time for accuracy (`spreadlight accuracy reflection`).",
        )))
        .output_typed("Environment", PinType::Resource(ResourceKind::Environment))
        .evaluate(|cx| {
            let settings = read_sky(cx, 0)?;
            let quality = quality(cx, 9)?;
            output(cx, EnvironmentSource::Sky(settings), quality)
        }),
    );
}

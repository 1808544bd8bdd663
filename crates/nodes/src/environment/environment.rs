//! `Environment (File)` and `Environment (Sky)`: a prefiltered environment
//! for image-based light (`Reflection`, `SSR`'s fallback through it, `Sky`'s
//! background). Built on the GPU once and kept under the node; rebuilt only
//! when the image, the sky or the quality pins change.

use std::sync::Arc;

use spreadlight_graph::{
    EvalContext, In, NodeDef, NodeError, Out, Pins, Registry, Res, ResourceKind,
};
use spreadlight_render::environment::{
    Environment, EnvironmentQuality, EnvironmentSource, EquirectImage,
};

use super::sky::SkyPins;
use crate::gpu::renderer;

/// The quality pins both nodes end with, and their output.
#[derive(Clone, Copy)]
struct QualityPins {
    cube_size: In<i64>,
    samples: In<i64>,
    out: Out<Res<Environment>>,
}

impl QualityPins {
    fn declare(p: &mut Pins<'_>) -> Self {
        let d = EnvironmentQuality::default();
        QualityPins {
            cube_size: p.input("Cube Size", i64::from(d.cube_size)),
            samples: p.input("Samples", i64::from(d.samples)),
            out: p.output_resource::<Environment>("Environment", ResourceKind::Environment),
        }
    }

    fn quality(self, cx: &EvalContext<'_>) -> Result<EnvironmentQuality, NodeError> {
        let int = |pin: In<i64>, fallback: u32| -> Result<u32, NodeError> {
            let v = cx.first(pin, i64::from(fallback))?;
            if v < 1 {
                return Err(cx.error(pin, format!("must be at least 1, got {v}")));
            }
            Ok(v.min(i64::from(u32::MAX)) as u32)
        };
        let d = EnvironmentQuality::default();
        Ok(EnvironmentQuality {
            cube_size: int(self.cube_size, d.cube_size)?,
            samples: int(self.samples, d.samples)?,
        })
    }

    fn output(
        self,
        cx: &mut EvalContext<'_>,
        source: EnvironmentSource,
        quality: EnvironmentQuality,
    ) -> Result<(), NodeError> {
        let renderer = renderer(cx)?;
        let environment = Environment::new(&renderer, Some(cx.node_id.0), source, quality);
        cx.put_resources(self.out, vec![environment]);
        Ok(())
    }
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Environment (File)",
            super::CATEGORY,
            "An environment from an equirectangular .hdr or .exr image (a relative Filename is relative to the patch's \
             folder; the image's centre looks along -z, its top straight up): a cube map prefiltered per roughness, its \
             diffuse irradiance and the split-sum table. Radiance above 65000 is clamped (half floats); NaN reads as 0. \
             Cube Size: the face size in texels (a power of two, 8..1024); Samples: GGX samples per texel of each rough \
             level (1..4096); both trade build time for accuracy (`spreadlight accuracy reflection`).",
        )
        .with_pins(|p| {
            let filename = p.input("Filename", String::new());
            let quality = QualityPins::declare(p);
            move |cx| {
                let file = cx.get(filename)?.first().cloned().unwrap_or_default();
                if file.is_empty() {
                    return Err(cx.error(filename, "no file given"));
                }
                // The file first: its errors name it, with or without a GPU.
                let image = EquirectImage::load(&cx.resolve_path(&file)).map_err(|e| cx.error(filename, e.to_string()))?;
                let settings = quality.quality(cx)?;
                quality.output(cx, EnvironmentSource::Equirect(Arc::new(image)), settings)
            }
        }),
    );
    r.add(
        NodeDef::new(
            "Environment (Sky)",
            super::CATEGORY,
            "The procedural sky of the Sky node (same pins, same look) as an environment: a cube map prefiltered per roughness, \
             its diffuse irradiance and the split-sum table. Connect it to Sky's Environment too and the background matches. \
             Cube Size: the face size in texels (a power of two, 8..1024); Samples: GGX samples per texel of each rough \
             level (1..4096); both trade build time for accuracy (`spreadlight accuracy reflection`).",
        )
        .with_pins(|p| {
            let sky = SkyPins::declare(p);
            let quality = QualityPins::declare(p);
            move |cx| {
                let settings = sky.read(cx)?;
                let q = quality.quality(cx)?;
                quality.output(cx, EnvironmentSource::Sky(settings), q)
            }
        }),
    );
}

//! `VectorField`: a cube of Resolution³ vectors (x fastest, then y, then z)
//! uploaded as a 3D texture, for the `Particles` node's Field Texture pin.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::particles::FieldTexture;

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "VectorField",
            super::CATEGORY,
            "A 3D vector field from a spread of Resolution³ vectors (x fastest, then y, then z), uploaded once as a \
             texture. Particles sample it trilinearly over Field Min..Field Max; NaN or infinite vectors act as no force.",
        )
        .input_spread("Vectors", PinType::Vec3, Spread::Vec3(vec![Vec3::Y; 8]))
        .input("Resolution", 2i64)
        .output_typed("Field", PinType::Resource(ResourceKind::Buffer))
        .evaluate(|cx| {
            let vectors = cx.slices::<Vec3>(0)?.to_vec();
            let resolution = cx.slices::<i64>(1)?.first().copied().unwrap_or(2);
            if !(2..=256).contains(&resolution) {
                return Err(cx.input_error(1, format!("{resolution} is not within 2..256")));
            }
            let renderer = renderer(cx)?;
            let field = FieldTexture::new(&renderer, resolution as u32, &vectors)
                .map_err(|e| cx.input_error(0, e.to_string()))?;
            cx.set_output(0, resource_spread(ResourceKind::Buffer, vec![Arc::new(field)]));
            Ok(())
        }),
    );
}

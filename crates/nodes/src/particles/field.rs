//! `VectorField`: a cube of Resolution³ vectors (x fastest, then y, then z)
//! uploaded as a 3D texture, for the `Particles` node's Field Texture pin.

use std::sync::Arc;

use glam::Vec3;
use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::particles::FieldTexture;

use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "VectorField",
            super::CATEGORY,
            "A 3D vector field from a spread of Resolution³ vectors (x fastest, then y, then z), uploaded once as a \
             texture. Particles sample it trilinearly over Field Min..Field Max; NaN or infinite vectors act as no force.",
        )
        .with_pins(|p| {
            let vectors_in = p.input_spread("Vectors", vec![Vec3::Y; 8]);
            let resolution_in = p.input("Resolution", 2i64);
            let out = p.output_resource::<FieldTexture>("Field", ResourceKind::Buffer);
            move |cx| {
                let vectors = cx.get(vectors_in)?.to_vec();
                let resolution = cx.first(resolution_in, 2)?;
                if !(2..=256).contains(&resolution) {
                    return Err(cx.error(resolution_in, format!("{resolution} is not within 2..256")));
                }
                let renderer = renderer(cx)?;
                let field = FieldTexture::new(&renderer, resolution as u32, &vectors)
                    .map_err(|e| cx.error(vectors_in, e.to_string()))?;
                cx.put_resources(out, vec![Arc::new(field)]);
                Ok(())
            }
        }),
    );
}

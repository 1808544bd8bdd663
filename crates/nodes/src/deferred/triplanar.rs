//! `Triplanar (Layer)`: how sharply a triplanar layer blends its three
//! projections. A node of its own on the way from DeferredBase to MRE, so
//! DeferredBase keeps its pins (and every patch its layout).

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::gbuffer::{Layer, TRIPLANAR_SHARPNESS};
use std::sync::Arc;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Triplanar (Layer)",
            super::CATEGORY,
            "Sets how sharply each layer's triplanar mapping (DeferredBase's Triplanar) blends its three planar \
             projections of the Color and Normal Textures: each weighs the normal's component along its axis to the \
             power Sharpness (1..32, default 4), so the blend is continuous and shows no seam; larger values narrow \
             it towards one projection per pixel. Layers without Triplanar pass unchanged. Slice i of Sharpness goes \
             to layer i (wrapping).",
        )
        .with_pins(|p| {
            let layer_in = p.input_resource::<Layer>("Layer", ResourceKind::Layer);
            let sharpness_in = p.input("Sharpness", i64::from(TRIPLANAR_SHARPNESS));
            p.range(1.0, 32.0);
            let out_pin = p.output_resource::<Layer>("Layer", ResourceKind::Layer);
            move |cx| {
            let layers = cx.resources(layer_in)?;
            let sharpness = cx.get(sharpness_in)?.to_vec();
            let n = if sharpness.is_empty() { 0 } else { layers.len() };
            let out = (0..n)
                .map(|i| {
                    let mut layer = Layer::clone(&layers[i]);
                    // Held to 1..=32: 0 would weigh every axis alike, and
                    // beyond 32 the blend is narrower than a pixel.
                    layer.features.triplanar_sharpness = sharpness[i % sharpness.len()].clamp(1, 32) as u32;
                    Arc::new(layer)
                })
                .collect();
            cx.put_resources(out_pin, out);
            Ok(())
            }
        }),
    );
}

#[cfg(test)]
mod tests {
    use spreadlight_graph::{Resource, ResourceKind, Spread};
    use spreadlight_render::gbuffer::{Layer, TRIPLANAR_SHARPNESS};
    use std::sync::Arc;

    use crate::testing::{eval, ints};

    fn layers(n: usize) -> Spread {
        Spread::Resource(
            ResourceKind::Layer,
            (0..n)
                .map(|_| Resource::from_arc(Arc::new(Layer::plain(Vec::new()))))
                .collect(),
        )
    }

    fn sharpness_of(out: &Spread) -> Vec<u32> {
        match out {
            Spread::Resource(ResourceKind::Layer, handles) => handles
                .iter()
                .map(|h| {
                    h.downcast_arc::<Layer>()
                        .expect("a Layer")
                        .features
                        .triplanar_sharpness
                })
                .collect(),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn sets_each_layers_sharpness_held_to_its_range() {
        assert_eq!(
            Layer::plain(Vec::new()).features.triplanar_sharpness,
            TRIPLANAR_SHARPNESS
        );
        let out = eval(
            "Triplanar (Layer)",
            &[("Layer", layers(3)), ("Sharpness", ints(&[8, 0, 100]))],
        )
        .expect("evaluates");
        assert_eq!(sharpness_of(&out[0]), [8, 1, 32]);
        let none = eval(
            "Triplanar (Layer)",
            &[("Layer", layers(2)), ("Sharpness", ints(&[]))],
        )
        .expect("evaluates");
        assert_eq!(sharpness_of(&none[0]), Vec::<u32>::new());
    }
}

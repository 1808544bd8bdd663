//! `PointLightBuffer`: uploads the point lights that `AddLight (Point)` nodes
//! gathered, once when they change, as the light world a `CookTorrance` shades with.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::lighting::{LightBuffer, PointLight};

use super::add_light::LightList;
use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    let kind = ResourceKind::PointLights;
    r.add(
        NodeDef::new(
            "PointLightBuffer",
            super::CATEGORY,
            "The point lights from AddLight (Point) nodes as one GPU buffer, uploaded when they \
             change. Several light buffers (several light worlds) may coexist.",
        )
        .input_spread(
            "Lights",
            PinType::Resource(kind),
            Spread::Resource(kind, Vec::new()),
        )
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .output::<i64>("Count")
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let list = LightList::<PointLight>::gather(cx, 0)?;
            let buffer = LightBuffer::points_of(&renderer, Some(cx.node_id.0), &list.lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![buffer]));
            cx.set_output(1, Spread::Int(vec![list.lights.len() as i64]));
            Ok(())
        }),
    );
}

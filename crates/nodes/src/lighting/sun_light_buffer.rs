//! `SunLightBuffer`: uploads the parallel lights that `AddLight (Sun)` nodes gathered.

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::lighting::{LightBuffer, SunLight};

use super::add_light::LightList;
use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    let kind = ResourceKind::SunLights;
    r.add(
        NodeDef::new(
            "SunLightBuffer",
            super::CATEGORY,
            "The sun lights from AddLight (Sun) nodes as one GPU buffer, uploaded when they change.",
        )
        .input_spread("Lights", PinType::Resource(kind), Spread::Resource(kind, Vec::new()))
        .output_typed("Lights", PinType::Resource(ResourceKind::LightWorld))
        .output::<i64>("Count")
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let list = LightList::<SunLight>::gather(cx, 0)?;
            let buffer = LightBuffer::suns_of(&renderer, Some(cx.node_id.0), &list.lights);
            cx.set_output(0, resource_spread(ResourceKind::LightWorld, vec![buffer]));
            cx.set_output(1, Spread::Int(vec![list.lights.len() as i64]));
            Ok(())
        }),
    );
}

//! `SunLightBuffer`: uploads the parallel lights that `AddLight (Sun)` nodes gathered.

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::lighting::{LightBuffer, SunLight};

use super::add_light::LightList;
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let kind = ResourceKind::SunLights;
    r.add(
        NodeDef::new(
            "SunLightBuffer",
            super::CATEGORY,
            "The sun lights from AddLight (Sun) nodes as one GPU buffer, uploaded when they change.",
        )
        .with_pins(|p| {
            let lights = LightList::<SunLight>::input(p, kind);
            let out = p.output_resource::<LightBuffer>("Lights", ResourceKind::LightWorld);
            let count = p.output::<i64>("Count");
            move |cx| {
                let renderer = renderer(cx)?;
                let list = LightList::<SunLight>::gather(cx, lights)?;
                let buffer = LightBuffer::suns_of(&renderer, Some(cx.node_id.0), &list.lights);
                cx.put_resources(out, vec![buffer]);
                cx.put(count, vec![list.lights.len() as i64]);
                Ok(())
            }
        }),
    );
}

//! `PointLightBuffer`: uploads the point lights that `AddLight (Point)` nodes
//! gathered, once when they change, as the light world a `CookTorrance` shades with.

use spreadlight_graph::{NodeDef, Registry, ResourceKind};
use spreadlight_render::lighting::{LightBuffer, PointLight};

use super::add_light::LightList;
use crate::gpu::renderer;

pub fn register(r: &mut Registry) {
    let kind = ResourceKind::PointLights;
    r.add(
        NodeDef::new(
            "PointLightBuffer",
            super::CATEGORY,
            "The point lights from AddLight (Point) nodes as one GPU buffer, uploaded when they \
             change. Several light buffers (several light worlds) may coexist.",
        )
        .with_pins(|p| {
            let lights = LightList::<PointLight>::input(p, kind);
            let out = p.output_resource::<LightBuffer>("Lights", ResourceKind::LightWorld);
            let count = p.output::<i64>("Count");
            move |cx| {
                let renderer = renderer(cx)?;
                let list = LightList::<PointLight>::gather(cx, lights)?;
                let buffer = LightBuffer::points_of(&renderer, Some(cx.node_id.0), &list.lights);
                cx.put_resources(out, vec![buffer]);
                cx.put(count, vec![list.lights.len() as i64]);
                Ok(())
            }
        }),
    );
}

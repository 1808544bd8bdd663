//! Lights and shading nodes (category "Lighting"): `PointLightBuffer`,
//! `CookTorrance`, `CompositeLight`.

pub mod composite_light;
pub mod cook_torrance;
pub mod point_light_buffer;

use spreadlight_graph::Registry;

pub const CATEGORY: &str = "Lighting";

pub fn register(r: &mut Registry) {
    point_light_buffer::register(r);
    cook_torrance::register(r);
    composite_light::register(r);
}

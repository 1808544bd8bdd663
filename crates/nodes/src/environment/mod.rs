//! The environment around a scene (category "Environment"): `Sky`, `Fog`.

pub mod fog;
pub mod sky;

use spreadlight_graph::Registry;

pub const CATEGORY: &str = "Environment";

pub fn register(r: &mut Registry) {
    sky::register(r);
    fog::register(r);
}

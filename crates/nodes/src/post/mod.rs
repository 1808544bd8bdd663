//! Post-processing nodes (category "Post"): texture in, texture out.

pub mod eye_adaptation;
pub mod fxaa;
pub mod tonemap;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    eye_adaptation::register(r);
    tonemap::register(r);
    fxaa::register(r);
}

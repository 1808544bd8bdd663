//! Post-processing nodes (category "Post"): texture in, texture out.

pub mod tonemap;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    tonemap::register(r);
}

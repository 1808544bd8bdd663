//! Texture nodes (category "Texture").

pub mod file_texture;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    file_texture::register(r);
}

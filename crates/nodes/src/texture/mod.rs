//! Texture nodes (category "Texture").

pub mod file_texture;
pub mod file_texture_array;

use spreadlight_graph::Registry;

pub fn register(r: &mut Registry) {
    file_texture::register(r);
    file_texture_array::register(r);
}

//! A texture that exists before any frame, as a recipe: how image files and
//! glTF textures travel between nodes like rendered ones. Apart from
//! `texture.rs` (the GPU texture itself), which `recipe.rs` needs and so
//! must not need recipes back.

use crate::texture::GpuTexture;

/// A texture that exists before the frame (an image file, a glTF texture):
/// as a recipe it imports itself into the frame graph under its name, so it
/// travels between nodes like any rendered texture.
pub struct StaticTexture {
    id: u64,
    name: String,
    pub texture: GpuTexture,
}

impl StaticTexture {
    pub fn new(texture: GpuTexture) -> std::sync::Arc<Self> {
        let id = crate::recipe::next_recipe_id();
        std::sync::Arc::new(StaticTexture {
            id,
            name: format!("static{id}"),
            texture,
        })
    }

    pub fn texture_ref(self: &std::sync::Arc<Self>) -> crate::recipe::TextureRef {
        crate::recipe::TextureRef {
            recipe: self.clone(),
            name: self.name.clone(),
        }
    }
}

impl crate::recipe::Recipe for StaticTexture {
    fn declare<'a>(
        &'a self,
        _: &'a crate::renderer::Renderer,
        fg: &mut crate::frame_graph::FrameGraph<'a>,
    ) {
        if fg.include(self.id) {
            fg.import(&self.name, self.texture.texture.clone());
        }
    }

    fn static_texture(&self) -> Option<&GpuTexture> {
        Some(&self.texture)
    }
}

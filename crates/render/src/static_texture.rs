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

    /// A texture of linear RGBA 32-bit float `pixels` (row by row) at
    /// `width` x `height`, ready to import into a frame graph: the one way a
    /// made-up image (a test's lit image or source) is handed to a pass, so
    /// callers do not each spell out the upload and the wrapping.
    pub fn from_rgba32f(
        gpu: &crate::context::GpuContext,
        width: u32,
        height: u32,
        pixels: &[[f32; 4]],
        label: &str,
    ) -> std::sync::Arc<Self> {
        Self::new(GpuTexture::from_rgba32f(gpu, width, height, pixels, label))
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

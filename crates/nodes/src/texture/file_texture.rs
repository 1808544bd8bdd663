//! `FileTexture`: an image file (PNG, JPEG, EXR, ...) as a texture that any
//! texture pin takes: a normal map for `DeferredBase`, a picture for `Output`.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;

use crate::gpu::{renderer, resource_spread};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FileTexture",
            "Texture",
            "Loads an image file as a texture (a relative Filename is relative to the patch's folder). sRGB for colour images; switch it off for data such as normal maps. HDR and EXR files are linear floats (Rgba32Float) whatever sRGB says.",
        )
        .input("Filename", String::new())
        .input("sRGB", true)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let files = cx.slices::<String>(0)?.to_vec();
            let srgb = cx.slices::<bool>(1)?.first().copied().unwrap_or(true);
            let mut textures = Vec::new();
            for file in files.iter().filter(|f| !f.is_empty()) {
                let image = image::open(cx.resolve_path(file)).map_err(|e| cx.input_error(0, format!("{file}: {e}")))?;
                let texture = if is_float(image.color()) {
                    // HDR and EXR files hold linear values: kept as they are.
                    // Cut to 8 bits they were taken as sRGB-encoded and
                    // showed darker than they are (0.5 as 0.21).
                    let pixels: Vec<[f32; 4]> = image.to_rgba32f().pixels().map(|p| p.0).collect();
                    GpuTexture::from_rgba32f(&renderer.gpu, image.width(), image.height(), &pixels, file)
                } else {
                    let image = image.to_rgba8();
                    GpuTexture::from_rgba8(&renderer.gpu, image.width(), image.height(), &image, srgb, file)
                };
                textures.push(Arc::new(StaticTexture::new(texture).texture_ref()));
            }
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, textures));
            Ok(())
        }),
    );
}

/// Whether an image file holds float (linear) values: HDR and EXR files.
fn is_float(color: image::ColorType) -> bool {
    matches!(color, image::ColorType::Rgb32F | image::ColorType::Rgba32F)
}

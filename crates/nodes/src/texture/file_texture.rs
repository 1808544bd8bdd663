//! `FileTexture`: an image file (PNG, JPEG, EXR, ...) as a texture that any
//! texture pin takes: a normal map for `DeferredBase`, a picture for `Output`.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;

use crate::gpu::renderer;
use crate::post::texture_output;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FileTexture",
            "Texture",
            "Loads an image file as a texture (a relative Filename is relative to the patch's folder). sRGB for colour images; switch it off for data such as normal maps. HDR and EXR files are linear floats (Rgba32Float) whatever sRGB says.",
        )
        .with_pins(|p| {
            let filename = p.input("Filename", String::new());
            let srgb_in = p.input("sRGB", true);
            let out = texture_output(p, "Texture");
            move |cx| {
            let renderer = renderer(cx)?;
            let files = cx.get(filename)?.to_vec();
            let srgb = cx.first(srgb_in, true)?;
            let mut textures = Vec::new();
            for file in files.iter().filter(|f| !f.is_empty()) {
                let image = image::open(cx.resolve_path(file)).map_err(|e| cx.error(filename, format!("{file}: {e}")))?;
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
            cx.put_resources(out, textures);
            Ok(())
            }
        }),
    );
}

/// Whether an image file holds float (linear) values: HDR and EXR files.
fn is_float(color: image::ColorType) -> bool {
    matches!(color, image::ColorType::Rgb32F | image::ColorType::Rgba32F)
}

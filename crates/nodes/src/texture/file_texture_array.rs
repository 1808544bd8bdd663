//! `FileTexture (Array)`: image files as the layers of one 2D texture array,
//! for spots' projected textures and material textures. Every image is
//! resampled to the first one's size, so files of mixed sizes still make one array.

use std::sync::Arc;

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::static_texture::StaticTexture;
use spreadlight_render::texture::GpuTexture;

use crate::gpu::renderer;
use crate::post::texture_output;

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "FileTexture (Array)",
            "Texture",
            "Loads image files as the layers of one texture array (layer k is file k), resampled to \
             the first file's size; relative names are relative to the patch's folder. sRGB for colour images; switch it off for data. Outputs one texture \
             and its layer count.",
        )
        .with_pins(|p| {
            let filenames = p.input_spread::<String>("Filenames", Vec::new());
            let srgb_in = p.input("sRGB", true);
            let out = texture_output(p, "Texture");
            let layer_count = p.output::<i64>("Layers");
            move |cx| {
            let renderer = renderer(cx)?;
            let files: Vec<String> = cx.get(filenames)?.iter().filter(|f| !f.is_empty()).cloned().collect();
            let srgb = cx.first(srgb_in, true)?;
            if files.is_empty() {
                cx.put_resources(out, Vec::new());
                cx.put(layer_count, vec![0]);
                return Ok(());
            }
            let mut layers = Vec::with_capacity(files.len());
            let mut size = None;
            for (slice, file) in files.iter().enumerate() {
                let image = image::open(cx.resolve_path(file))
                    .map_err(|e| cx.error(filenames, format!("slice {slice}, {file}: {e}")))?
                    .to_rgba8();
                let (w, h) = *size.get_or_insert(image.dimensions());
                let image = if image.dimensions() == (w, h) {
                    image
                } else {
                    image::imageops::resize(&image, w, h, image::imageops::FilterType::Triangle)
                };
                layers.push(image.into_raw());
            }
            let (w, h) = size.unwrap_or((1, 1));
            let texture = GpuTexture::array_from_rgba8(&renderer.gpu, w, h, &layers, srgb, "texture array");
            let texture = Arc::new(StaticTexture::new(texture).texture_ref());
            cx.put_resources(out, vec![texture]);
            cx.put(layer_count, vec![layers.len() as i64]);
            Ok(())
            }
        }),
    );
}

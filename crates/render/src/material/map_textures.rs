//! A world's surface-map textures: one 2D texture array per size class and
//! colour space, so hundreds of maps of mixed sizes are sampled in one
//! dispatch without binding arrays (lavapipe has no
//! `TEXTURE_BINDING_ARRAY`, and arrays per class cost one binding each on
//! every adapter). An image goes to the smallest class at least as large as
//! its larger side (the largest class holds everything bigger) and is
//! resized to that square; every layer has its full mip chain, sampled
//! trilinear with 16x anisotropy. Classes with no image are bound to a
//! 1x1 array. Each distinct image (same `Arc`) is uploaded once per world.

use std::collections::HashMap;
use std::sync::Arc;

use image::imageops::FilterType;

use super::maps::{MapImage, MapLocation, MapRef, MapSlot};
use crate::context::GpuContext;
use crate::texture::GpuTexture;

/// The square sizes of the classes, smallest first.
pub const CLASS_SIZES: [u32; 6] = [16, 64, 256, 512, 1024, 2048];
/// Arrays bound: a linear and an sRGB one per class (array = class * 2 + srgb).
pub const ARRAY_COUNT: usize = CLASS_SIZES.len() * 2;

/// The class an image of `width` x `height` goes to.
pub fn size_class(width: u32, height: u32) -> usize {
    let side = width.max(height);
    CLASS_SIZES
        .iter()
        .position(|&s| s >= side)
        .unwrap_or(CLASS_SIZES.len() - 1)
}

/// Where each map image goes, before upload: decided on the CPU so packing
/// the material parameters and uploading agree.
#[derive(Default)]
pub struct MapLayout {
    /// (image pointer, sRGB) -> location.
    locations: HashMap<(usize, bool), MapLocation>,
    /// Per array: the images in layer order.
    layers: Layers,
    /// Maps past an array's layer limit, not placed.
    pub dropped: usize,
}

impl MapLayout {
    pub fn new() -> Self {
        Self {
            locations: HashMap::new(),
            layers: vec![Vec::new(); ARRAY_COUNT],
            dropped: 0,
        }
    }

    /// Give `map` (in `slot`) a location, reusing the image's if it has one.
    pub fn place(&mut self, map: &MapRef, slot: MapSlot, max_layers: u32) -> Option<MapLocation> {
        let key = (Arc::as_ptr(&map.image) as usize, slot.srgb());
        if let Some(at) = self.locations.get(&key) {
            return Some(*at);
        }
        let array = size_class(map.image.width, map.image.height) * 2 + usize::from(slot.srgb());
        let layers = &mut self.layers[array];
        if layers.len() as u32 >= max_layers {
            self.dropped += 1;
            return None;
        }
        let at = MapLocation {
            array: array as u32,
            layer: layers.len() as u32,
        };
        layers.push(map.image.clone());
        self.locations.insert(key, at);
        Some(at)
    }

    /// Where `map` in `slot` was placed.
    pub fn location(&self, map: &MapRef, slot: MapSlot) -> Option<MapLocation> {
        self.locations
            .get(&(Arc::as_ptr(&map.image) as usize, slot.srgb()))
            .copied()
    }

    pub fn is_empty(&self) -> bool {
        self.locations.is_empty()
    }

    /// The arrays for this layout: the renderer's last upload when it holds
    /// the same images in the same places (a MaterialBuffer re-evaluated for
    /// a changed factor re-uploads nothing), else a new upload, kept.
    pub fn upload_cached(&self, renderer: &crate::renderer::Renderer) -> Arc<MapTextures> {
        let cache = renderer.state::<MapCache>(0);
        let mut last = cache.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((images, textures)) = last.as_ref()
            && same_images(images, &self.layers)
        {
            return textures.clone();
        }
        let textures = Arc::new(self.upload(&renderer.gpu));
        // The cache holds the images, so their addresses cannot be reused by others.
        *last = Some((self.layers.clone(), textures.clone()));
        textures
    }

    /// Upload every array (a 1x1 white one for empty classes).
    pub fn upload(&self, gpu: &GpuContext) -> MapTextures {
        let arrays = self
            .layers
            .iter()
            .enumerate()
            .map(|(array, images)| {
                let srgb = array % 2 == 1;
                if images.is_empty() {
                    return GpuTexture::upload_rgba8(gpu, (1, 1), &[vec![255; 4]], srgb, "no maps");
                }
                let side = CLASS_SIZES[array / 2];
                let pixels: Vec<Vec<u8>> = images.iter().map(|i| fit(i, side)).collect();
                GpuTexture::upload_rgba8(
                    gpu,
                    (side, side),
                    &pixels,
                    srgb,
                    &format!("material maps {side}"),
                )
            })
            // Always viewed as an array, even with one layer.
            .map(|t| {
                let view = t.texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                });
                GpuTexture {
                    texture: t.texture,
                    view,
                }
            })
            .collect();
        MapTextures { arrays }
    }
}

/// The last map upload of a renderer and the images it holds.
#[derive(Default)]
struct MapCache(std::sync::Mutex<Option<(Layers, Arc<MapTextures>)>>);

/// Per array, its images in layer order.
type Layers = Vec<Vec<Arc<MapImage>>>;

fn same_images(a: &[Vec<Arc<MapImage>>], b: &[Vec<Arc<MapImage>>]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.len() == y.len() && x.iter().zip(y).all(|(i, j)| Arc::ptr_eq(i, j)))
}

/// `image` resized to `side` x `side` (nothing to do when it already is).
fn fit(image: &MapImage, side: u32) -> Vec<u8> {
    let (w, h) = (image.width.max(1), image.height.max(1));
    let mut bytes = image.rgba8.clone();
    bytes.resize((w * h * 4) as usize, 255);
    if (w, h) == (side, side) {
        return bytes;
    }
    let Some(buffer) = image::RgbaImage::from_raw(w, h, bytes) else {
        return vec![255; (side * side * 4) as usize];
    };
    image::imageops::resize(&buffer, side, side, FilterType::Triangle).into_raw()
}

/// The uploaded arrays, `ARRAY_COUNT` of them, in array order.
pub struct MapTextures {
    pub arrays: Vec<GpuTexture>,
}

/// A world's map textures on the GPU, with what binds them.
pub struct WorldMaps {
    pub textures: Arc<MapTextures>,
    samplers: [wgpu::Sampler; 2],
    /// Maps past a size class's layer limit, drawn without their map.
    pub dropped: usize,
}

impl WorldMaps {
    pub(crate) fn new(
        renderer: &crate::renderer::Renderer,
        layout: &MapLayout,
        filtering: MapFiltering,
    ) -> Self {
        WorldMaps {
            textures: layout.upload_cached(renderer),
            samplers: samplers(&renderer.gpu.device, filtering),
            dropped: layout.dropped,
        }
    }

    /// The arrays and the two samplers, by the names `material_maps.wgsl` gives them.
    pub(crate) fn bindings(&self) -> crate::frame_graph::Bindings<'static> {
        const ARRAYS: [&str; 12] = [
            "maps_0", "maps_1", "maps_2", "maps_3", "maps_4", "maps_5", "maps_6", "maps_7",
            "maps_8", "maps_9", "maps_10", "maps_11",
        ];
        let [linear, nearest] = self.samplers.clone();
        self.textures
            .arrays
            .iter()
            .zip(ARRAYS)
            .fold(crate::frame_graph::Bindings::new(), |b, (t, name)| {
                b.view(name, t.view.clone())
            })
            .sampler_object("maps_linear", linear)
            .sampler_object("maps_nearest", nearest)
    }
}

/// How a world's maps are filtered. Every world renders with the default;
/// the others exist so `spreadlight accuracy gltf` can show what filtering
/// costs against the aliasing it removes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum MapFiltering {
    /// The nearest texel of the full-size image: no mips, no anisotropy
    /// (what a CPU reference point-sampling the image sees; aliases when
    /// a texel is smaller than a pixel).
    Point,
    /// Bilinear on the full-size image (no mips).
    Bilinear,
    /// Trilinear through the mip chain, no anisotropy.
    Trilinear,
    /// Trilinear + 16x anisotropic.
    #[default]
    Anisotropic,
}

impl MapFiltering {
    pub const ALL: [MapFiltering; 4] = [
        MapFiltering::Point,
        MapFiltering::Bilinear,
        MapFiltering::Trilinear,
        MapFiltering::Anisotropic,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MapFiltering::Point => "point (mip 0)",
            MapFiltering::Bilinear => "bilinear (mip 0)",
            MapFiltering::Trilinear => "trilinear",
            MapFiltering::Anisotropic => "trilinear + 16x anisotropic",
        }
    }
}

/// The samplers maps are read with: `filtering` (the default: trilinear +
/// 16x anisotropic), and nearest (glTF's NEAREST magnification filter).
/// Without mips, the level of detail is clamped to 0.
pub fn samplers(device: &wgpu::Device, filtering: MapFiltering) -> [wgpu::Sampler; 2] {
    let (filter, mipmap_filter, anisotropy_clamp, lod_max_clamp) = match filtering {
        MapFiltering::Point => (
            wgpu::FilterMode::Nearest,
            wgpu::MipmapFilterMode::Nearest,
            1,
            0.0,
        ),
        MapFiltering::Bilinear => (
            wgpu::FilterMode::Linear,
            wgpu::MipmapFilterMode::Nearest,
            1,
            0.0,
        ),
        MapFiltering::Trilinear => (
            wgpu::FilterMode::Linear,
            wgpu::MipmapFilterMode::Linear,
            1,
            32.0,
        ),
        MapFiltering::Anisotropic => (
            wgpu::FilterMode::Linear,
            wgpu::MipmapFilterMode::Linear,
            16,
            32.0,
        ),
    };
    let linear = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material maps: filtered"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: filter,
        min_filter: filter,
        mipmap_filter,
        anisotropy_clamp,
        lod_max_clamp,
        ..Default::default()
    });
    let nearest = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("material maps: nearest"),
        address_mode_u: wgpu::AddressMode::Repeat,
        address_mode_v: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Nearest,
        min_filter: wgpu::FilterMode::Nearest,
        mipmap_filter: wgpu::MipmapFilterMode::Nearest,
        lod_max_clamp: if lod_max_clamp == 0.0 { 0.0 } else { 32.0 },
        ..Default::default()
    });
    [linear, nearest]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32) -> Arc<MapImage> {
        Arc::new(MapImage {
            width: w,
            height: h,
            rgba8: vec![255; (w * h * 4) as usize],
        })
    }

    #[test]
    fn classes_by_larger_side() {
        assert_eq!(size_class(1, 1), 0);
        assert_eq!(size_class(16, 16), 0);
        assert_eq!(size_class(17, 4), 1);
        assert_eq!(size_class(300, 40), 3);
        assert_eq!(size_class(8192, 8192), CLASS_SIZES.len() - 1);
    }

    #[test]
    fn an_image_is_placed_once_per_colour_space() {
        let mut layout = MapLayout::new();
        let shared = MapRef::new(image(64, 64));
        let a = layout.place(&shared, MapSlot::BaseColor, 256).unwrap();
        let b = layout.place(&shared, MapSlot::Emissive, 256).unwrap();
        let c = layout.place(&shared, MapSlot::Normal, 256).unwrap();
        assert_eq!(a, b, "both sRGB: one layer");
        assert_eq!(a, MapLocation { array: 3, layer: 0 });
        assert_eq!(c, MapLocation { array: 2, layer: 0 });
        let other = MapRef::new(image(40, 64));
        let d = layout.place(&other, MapSlot::BaseColor, 256).unwrap();
        assert_eq!(d, MapLocation { array: 3, layer: 1 });
        // Past the layer limit a map is dropped, not wrapped onto another.
        assert_eq!(
            layout.place(&MapRef::new(image(2, 2)), MapSlot::Normal, 0),
            None
        );
        assert_eq!(layout.dropped, 1);
    }
}

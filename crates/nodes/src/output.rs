//! `Output`: the sink that renders. It builds the frame graph from the
//! texture it is given (the graph culls every pass that does not lead to
//! it), executes it at the renderer's output size, reads the image back
//! (stretched to the output size when the texture has another, as the show
//! window draws it), and writes it to its file (PNG, or EXR by extension)
//! and to the host's [`RenderedImages`].

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use spreadlight_graph::{Choices, NodeDef, NodeError, Registry, ResourceKind};
use spreadlight_render::accumulate::{PendingSum, Sums};
use spreadlight_render::image_io::{Encoding, write_image};
use spreadlight_render::readback::{
    ImageF32, PendingImage, read_texture, readback_layout, start_read_texture,
};
use spreadlight_render::{FrameGraph, GpuContext, RenderError, TextureRef};

use crate::gpu::renderer;

pub static ENCODING: Choices<Encoding> = Choices::new(
    "Encoding",
    &["sRGB", "Linear"],
    &[Encoding::Srgb, Encoding::Linear],
);

/// Images the `Output` nodes rendered, by their Name: the CLI and tests read them here.
#[derive(Default)]
pub struct RenderedImages {
    images: Mutex<BTreeMap<String, (ImageF32, Encoding)>>,
    /// The size of the texture each Output was given, before it was stretched.
    sources: Mutex<BTreeMap<String, (u32, u32)>>,
    /// Whether the host takes copies still on their way ([`RenderedImages::take_pending`])
    /// instead of images: a sequence keeps several frames in flight this way.
    deferred: AtomicBool,
    pending: Mutex<BTreeMap<String, (PendingImage, Encoding)>>,
    /// Whether a deferred `Output` adds its image into a sum on the GPU
    /// ([`RenderedImages::take_sum`]) instead of starting its copy: the
    /// sub-frames of `spreadlight render --samples`.
    accumulating: AtomicBool,
    sums: Mutex<Sums>,
    sum_encodings: Mutex<BTreeMap<String, Encoding>>,
}

impl RenderedImages {
    /// From now on, an `Output` that only hands its image to the host (no
    /// file of its own) starts the copy and leaves it here unwaited: the
    /// host takes it with [`RenderedImages::take_pending`], waits for it
    /// where it likes and stretches it to the output size when its size
    /// differs (as [`ImageF32::resized`]).
    pub fn set_deferred(&self, deferred: bool) {
        self.deferred.store(deferred, Ordering::Relaxed);
    }

    /// The copy an `Output` named `name` started in the last evaluation,
    /// taken (a second call returns `None`).
    pub fn take_pending(&self, name: &str) -> Option<(PendingImage, Encoding)> {
        self.pending
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(name)
    }

    /// From now on, a deferred `Output` (see [`RenderedImages::set_deferred`])
    /// adds each image it renders into a sum on the GPU, read back once by
    /// [`RenderedImages::take_sum`]; where the device cannot hold the sum it
    /// starts its copy as before.
    pub fn set_accumulating(&self, accumulating: bool) {
        self.accumulating.store(accumulating, Ordering::Relaxed);
    }

    /// Forget every sum begun (a frame that failed half way).
    pub fn restart_sums(&self) {
        self.sums
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .restart();
    }

    /// How many images the `Output` named `name` added into its sum since
    /// the sums were taken or restarted.
    pub fn sum_count(&self, name: &str) -> u32 {
        self.sums
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .count(name)
    }

    /// The sum of the images the `Output` named `name` added since the
    /// last call, its copy to the CPU started (`None` when it added none).
    pub fn take_sum(
        &self,
        name: &str,
        gpu: &GpuContext,
    ) -> Option<Result<(PendingSum, Encoding), RenderError>> {
        let pending = self
            .sums
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .start_read(name, gpu)?;
        let encoding = self
            .sum_encodings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(name)
            .copied()
            .unwrap_or(Encoding::Srgb);
        Some(pending.map(|p| (p, encoding)))
    }

    /// What an `Output` that added into its sum tells the host: the size it summed, its encoding.
    fn note_sum(&self, name: &str, size: Option<(u32, u32)>, encoding: Encoding) {
        if let Some(size) = size {
            self.sources
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .insert(name.to_owned(), size);
        }
        self.sum_encodings
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_owned(), encoding);
    }

    fn put_pending(&self, name: &str, image: PendingImage, encoding: Encoding) {
        self.sources
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_owned(), image.size());
        self.pending
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_owned(), (image, encoding));
    }

    /// The last image an `Output` named `name` rendered, with the encoding it asks for.
    pub fn get(&self, name: &str) -> Option<(ImageF32, Encoding)> {
        self.images
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(name)
            .cloned()
    }

    pub fn names(&self) -> Vec<String> {
        self.images
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .keys()
            .cloned()
            .collect()
    }

    /// The size of the texture the `Output` named `name` was given (its
    /// image is stretched to the output size when this differs).
    pub fn source_size(&self, name: &str) -> Option<(u32, u32)> {
        self.sources
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(name)
            .copied()
    }

    fn put(&self, name: &str, image: ImageF32, encoding: Encoding, source: (u32, u32)) {
        self.images
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_owned(), (image, encoding));
        self.sources
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_owned(), source);
    }
}

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "Output",
            "Output",
            "Renders its texture at the output size and writes it to Filename (PNG 8-bit, or 32-bit float EXR when \
             the name ends in .exr) when Write is on. A texture of another size (a 1x1 luminance, a half-resolution \
             buffer) is stretched to the output size with bilinear filtering, as the show window draws it. Only the passes its texture depends on run. Name names \
             the sequence `spreadlight render` writes for it; Preroll declares how many frames its temporal \
             effects and simulations need to settle, which a render of a chunk of frames evaluates first (0: \
             none declared; a render then prerolls from frame 0 when a node keeps state). \
             Monitor (-1 or 0 and up) picks the monitor its show window opens on: `spreadlight play`, and \
             in the editor (F11 or the toolbar's Show window) when fullscreen; -1 leaves it to the window system.",
        )
        .sink()
        .with_pins(|p| {
            let texture_in = p.input_resource::<TextureRef>("Texture", ResourceKind::Texture);
            let filename_in = p.input("Filename", String::new());
            let name_in = p.input("Name", "output".to_owned());
            let encoding_in = p.input_choice("Encoding", &ENCODING, Encoding::Srgb);
            let write_in = p.input("Write", true);
            // Read by the hosts (`spreadlight render`, the show window), not here.
            p.input("Preroll", 0i64);
            p.input("Monitor", -1i64);
            move |cx| {
                let renderer = renderer(cx)?;
                let Some(texture) = cx.first_resource(texture_in)? else {
                    return Err(cx.error(texture_in, "no texture connected"));
                };
                let filename = cx.get(filename_in)?.first().cloned().unwrap_or_default();
                let name = cx.get(name_in)?.first().cloned().unwrap_or_else(|| "output".to_owned());
                let encoding = cx.choice(encoding_in)?;
                let write = cx.first(write_in, true)?;

                let mut graph = FrameGraph::new(renderer.output_size());
                texture.recipe.declare(&renderer, &mut graph);
                graph.request(&texture.name);
                // Read back only when someone takes the image: a benchmark renders without the copy.
                let to_file = write && !filename.is_empty();
                let store = cx.service::<RenderedImages>();
                // An image that could not be read back (a buffer past the adapter's
                // largest) is refused before a frame is rendered for it.
                if let (true, Some(planned)) = (to_file || store.is_some(), graph.planned(&texture.name)) {
                    readback_layout(&renderer.gpu, &planned, "the Output's texture")
                        .map_err(|e| NodeError::Other(e.to_string()))?;
                }
                let (_, outputs) = graph.execute(&renderer).map_err(|e| NodeError::Other(e.to_string()))?;
                let target = outputs
                    .get(&texture.name)
                    .ok_or_else(|| NodeError::Other(format!("the frame produced no `{}`", texture.name)))?;
                if !to_file && store.is_none() {
                    return Ok(());
                }
                if let Some(store) = store.as_ref().filter(|s| !to_file && s.deferred.load(Ordering::Relaxed)) {
                    if store.accumulating.load(Ordering::Relaxed) {
                        let mut sums = store.sums.lock().unwrap_or_else(|e| e.into_inner());
                        let added = sums
                            .add(&name, &renderer, target)
                            .map_err(|e| NodeError::Other(format!("the Output named `{name}`: {e}")))?;
                        if added {
                            store.note_sum(&name, sums.size(&name), encoding);
                            return Ok(());
                        }
                    }
                    let pending = start_read_texture(&renderer.gpu, target).map_err(|e| NodeError::Other(e.to_string()))?;
                    store.put_pending(&name, pending, encoding);
                    return Ok(());
                }
                let image = read_texture(&renderer.gpu, target).map_err(|e| NodeError::Other(e.to_string()))?;
                // Hosts ask for an image of the output size (`render --size` writes files of that size and
                // checks it): a texture of another size is drawn over it, as the show window draws it.
                let source = (image.width, image.height);
                let size = renderer.output_size();
                let image = if source == size { image } else { image.resized(size) };
                if to_file {
                    write_image(&image, Path::new(&filename), encoding).map_err(|e| cx.error(filename_in, e.to_string()))?;
                }
                if let Some(store) = store {
                    store.put(&name, image, encoding, source);
                }
                Ok(())
            }
        }),
    );
}

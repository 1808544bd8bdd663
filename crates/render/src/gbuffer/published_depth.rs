//! Depth a G-buffer publishes under a name for the next frame: what
//! `Particles` collide with (screen-space depth collision) without a cycle
//! in the patch (their G-buffer is drawn from the particles themselves).
//!
//! Why a name and last frame: the runtime evaluates nodes in link order and
//! refuses cycles; the particles step (a compute dispatch, when their node
//! evaluates) comes before the G-buffer's frame graph runs, so the freshest
//! depth they can read is last frame's, kept by the renderer across frames.
//! The MRE's raster writes it after the meshes and before the particles
//! (procedural draws), so particles never collide with themselves.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use glam::Mat4;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext};
use crate::renderer::Renderer;
use crate::shaders::Permutation;

pub use super::published_depth_key::PublishedDepthKey;

/// A published depth: reversed-Z R32Float, 0 where no mesh was drawn.
#[derive(Clone, Debug)]
pub struct PublishedDepth {
    pub texture: wgpu::Texture,
    pub view_projection: Mat4,
    pub size: (u32, u32),
    /// Frames this depth has been written (0: made, not written yet).
    pub writes: u64,
}

/// The renderer's published depths, by name.
#[derive(Default)]
pub struct PublishedDepths(Mutex<HashMap<String, PublishedDepth>>);

/// Key of the renderer state that holds them (one per renderer).
const STATE_KEY: u64 = u64::MAX - 17;

impl PublishedDepths {
    pub fn of(renderer: &Renderer) -> Arc<Self> {
        renderer.state::<Self>(STATE_KEY)
    }

    /// The depth published under `name`, once some frame has written it.
    pub fn get(&self, name: &str) -> Option<PublishedDepth> {
        self.0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get(name)
            .filter(|d| d.writes > 0)
            .cloned()
    }

    /// The names published so far (for error messages).
    pub fn names(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .keys()
            .cloned()
            .collect();
        names.sort();
        names
    }

    /// The texture to write `name` into this frame at `size` (kept while the size holds).
    fn target(&self, device: &wgpu::Device, name: &str, size: (u32, u32)) -> wgpu::Texture {
        let mut map = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let entry = map
            .entry(name.to_owned())
            .or_insert_with(|| PublishedDepth {
                texture: make(device, size),
                view_projection: Mat4::IDENTITY,
                size,
                writes: 0,
            });
        if entry.size != size {
            *entry = PublishedDepth {
                texture: make(device, size),
                view_projection: Mat4::IDENTITY,
                size,
                writes: 0,
            };
        }
        entry.texture.clone()
    }

    fn written(&self, name: &str, view_projection: Mat4) {
        if let Some(d) = self
            .0
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .get_mut(name)
        {
            d.view_projection = view_projection;
            d.writes += 1;
        }
    }
}

fn make(device: &wgpu::Device, size: (u32, u32)) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("published depth"),
        size: wgpu::Extent3d {
            width: size.0.max(1),
            height: size.1.max(1),
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::R32Float,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
        view_formats: &[],
    })
}

/// Where the depth to publish is now: the compute rasterizer's 64-bit
/// buffer (depth in each word's high half) or the hardware depth attachment.
pub(crate) enum DepthSource<'s> {
    Compute(&'s wgpu::Buffer),
    Hardware(&'s wgpu::TextureView),
}

/// Copies `source` (a G-buffer's depth so far) into the depth published as
/// `name`, seen through `view_projection`: one small compute pass.
pub(crate) fn publish(
    renderer: &Renderer,
    cx: &mut PassContext<'_>,
    name: &str,
    source: DepthSource<'_>,
    size: (u32, u32),
    view_projection: Mat4,
) -> Result<(), RenderError> {
    let device = cx.gpu.device.clone();
    let depths = PublishedDepths::of(renderer);
    let target = depths.target(&device, name, size);
    // A kept view and a cached group: the target lives across frames, so
    // the group binding it (and the same source) is made once.
    let out = cx.view_of(&target, crate::texture_pool::ViewSpec::default());
    let compute = matches!(source, DepthSource::Compute(_));
    let key = PublishedDepthKey {
        compute_raster: compute,
    }
    .key();
    let b = match source {
        DepthSource::Compute(buffer) => Bindings::new().buffer("visibility", buffer),
        DepthSource::Hardware(view) => Bindings::new().view("depth", view.clone()),
    };
    cx.dispatch_shader(
        "published depth",
        &key,
        "main",
        b.view("out_depth", out),
        (size.0.div_ceil(8), size.1.div_ceil(8), 1),
    )?;
    depths.written(name, view_projection);
    Ok(())
}

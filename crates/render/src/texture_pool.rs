//! The textures the renderer keeps between frame graphs: temporaries pooled
//! by [`TextureKey`] (format, size, usage) for reuse, persistent textures by
//! name (histories), and last frame's outputs lent to the caller.

use rustc_hash::FxHashMap;

/// The concrete size and format a [`TextureDesc`] resolves to in one frame: the pool's key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TextureKey {
    pub format: wgpu::TextureFormat,
    pub width: u32,
    pub height: u32,
    pub usage: wgpu::TextureUsages,
}

/// Which view of a texture a pass binds: the default view, or one mip level,
/// one layer, an array over the layers, one aspect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ViewSpec {
    pub dimension: Option<wgpu::TextureViewDimension>,
    pub aspect: wgpu::TextureAspect,
    pub base_mip_level: u32,
    pub mip_level_count: Option<u32>,
    pub base_array_layer: u32,
    pub array_layer_count: Option<u32>,
}

impl ViewSpec {
    /// Mip level `level` alone (a down-sampling chain's steps).
    pub fn mip(level: u32) -> Self {
        ViewSpec {
            base_mip_level: level,
            mip_level_count: Some(1),
            ..Default::default()
        }
    }

    /// Layer `layer` of an array alone, as a 2D texture (a shadow map's slice).
    pub fn layer(layer: u32) -> Self {
        ViewSpec {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        }
    }

    /// Every layer as a 2D array (shadow maps, texture arrays).
    pub fn array() -> Self {
        ViewSpec {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        }
    }

    /// Six layers as a cube (environment maps).
    pub fn cube() -> Self {
        ViewSpec {
            dimension: Some(wgpu::TextureViewDimension::Cube),
            ..Default::default()
        }
    }

    pub(crate) fn descriptor(&self) -> wgpu::TextureViewDescriptor<'static> {
        wgpu::TextureViewDescriptor {
            dimension: self.dimension,
            aspect: self.aspect,
            base_mip_level: self.base_mip_level,
            mip_level_count: self.mip_level_count,
            base_array_layer: self.base_array_layer,
            array_layer_count: self.array_layer_count,
            ..Default::default()
        }
    }
}

/// Graph runs a view, or an output's last texture, is kept while no graph
/// asks for it. A patch with several Outputs runs one graph per Output each
/// frame, and each graph must find next frame what it used this frame: when
/// each run dropped what it did not use itself, the graphs of a patch with
/// seven Outputs made their views, and so their bind groups, again every
/// frame. The kept bind groups keep plans as long (`kept_bindings.rs`).
pub(crate) const IDLE_GRAPHS: u64 = 8;

/// Drop the entries of `map` (each with the graph run that last asked for
/// it) that no graph asked for in the last [`IDLE_GRAPHS`] runs, and count
/// the run `graphs` ended.
fn end_graph_run<K: Eq + std::hash::Hash, V>(map: &mut FxHashMap<K, (V, u64)>, graphs: &mut u64) {
    let now = *graphs;
    map.retain(|_, (_, used)| now - *used <= IDLE_GRAPHS);
    *graphs += 1;
}

/// Each texture's views, made once: views are what passes bind, and making
/// one per pass per frame was most of a frame's recording time on the H100's
/// driver (and a new view is a new bind group). A view no graph asked for in
/// the last [`IDLE_GRAPHS`] runs is dropped (with the texture it keeps alive).
#[derive(Default)]
pub(crate) struct ViewCache {
    /// Each view and the graph run that last asked for it.
    views: FxHashMap<(wgpu::Texture, ViewSpec), (wgpu::TextureView, u64)>,
    /// Graph runs ended.
    graphs: u64,
    pub created: u64,
    pub reused: u64,
}

impl ViewCache {
    pub fn view(&mut self, texture: &wgpu::Texture) -> wgpu::TextureView {
        self.view_of(texture, ViewSpec::default())
    }

    pub fn view_of(&mut self, texture: &wgpu::Texture, spec: ViewSpec) -> wgpu::TextureView {
        let key = (texture.clone(), spec);
        if let Some((view, used)) = self.views.get_mut(&key) {
            *used = self.graphs;
            self.reused += 1;
            return view.clone();
        }
        let view = texture.create_view(&spec.descriptor());
        self.created += 1;
        self.views.insert(key, (view.clone(), self.graphs));
        view
    }

    /// Drop `texture`'s views now: the frame graph let it go (a history
    /// replaced at another size, dropped, or reset), and a kept view would
    /// keep it alive for [`IDLE_GRAPHS`] more runs, one size after another
    /// while a window is resized.
    pub fn forget(&mut self, texture: &wgpu::Texture) {
        self.views.retain(|(t, _), _| t != texture);
    }

    /// Drop what no graph used lately; the rest waits for the next frame.
    pub fn end_frame(&mut self) {
        end_graph_run(&mut self.views, &mut self.graphs);
    }
}

#[derive(Default)]
pub(crate) struct TexturePool {
    pub pool: FxHashMap<TextureKey, Vec<wgpu::Texture>>,
    pub persistent: FxHashMap<String, (TextureKey, wgpu::Texture)>,
    /// Per persistent texture: frame graphs run since a pass last wrote it.
    pub idle: FxHashMap<String, u32>,
    /// Last frame's requested outputs: handed to the caller, back to the pool next frame.
    pub lent: Vec<(TextureKey, wgpu::Texture)>,
    pub views: ViewCache,
    /// The texture each pass output ([`slot`]) was given last, and the graph
    /// run that asked for it (kept [`IDLE_GRAPHS`] runs). An output gets the same texture again
    /// while it is free: a stack alone hands textures of one key out in a
    /// different order each frame (those returned last are taken first), and
    /// a pass that binds other textures than last frame makes new bind groups.
    last: FxHashMap<u64, (wgpu::Texture, u64)>,
    /// Graph runs ended.
    graphs: u64,
    /// Textures kept out of the pool until the frame ends (see [`Self::hold_for`]).
    held: Vec<(TextureKey, wgpu::Texture)>,
}

impl TexturePool {
    /// A pooled texture of `key` for output `slot` ([`slot`]) named `name`
    /// (the texture the slot had last frame if that is free), or a new one
    /// (`created` counts it).
    pub fn take(
        &mut self,
        device: &wgpu::Device,
        key: &TextureKey,
        (slot, name): (u64, &str),
        created: &mut u64,
    ) -> wgpu::Texture {
        let last = self.last.get_mut(&slot);
        let free = self.pool.get_mut(key).and_then(|free| {
            let i = last
                .as_ref()
                .and_then(|(t, _)| free.iter().position(|f| f == t))
                .or_else(|| free.len().checked_sub(1))?;
            Some(free.swap_remove(i))
        });
        let texture = free.unwrap_or_else(|| {
            *created += 1;
            create_texture(device, key, name)
        });
        match last {
            Some(last) => *last = (texture.clone(), self.graphs),
            None => {
                self.last.insert(slot, (texture.clone(), self.graphs));
            }
        }
        texture
    }

    /// Output `slot` gives `texture` back instead of the one it took (a
    /// history took that one), and takes it again next frame: it stays out
    /// of the pool until the frame ends, so no later pass of this frame
    /// takes it. Then a history and its twin alternate between the same two
    /// textures, and the passes between the same two bind groups, however
    /// many histories share a format and size (three sharing one pool would
    /// otherwise rotate through three textures, past the bind-group cache).
    pub fn hold_for(&mut self, slot: u64, key: TextureKey, texture: wgpu::Texture) {
        if let Some(last) = self.last.get_mut(&slot) {
            last.0 = texture.clone();
        }
        self.held.push((key, texture));
    }

    pub fn give_back(&mut self, key: TextureKey, texture: wgpu::Texture) {
        self.pool.entry(key).or_default().push(texture);
    }

    /// Forget the outputs no graph used lately (a node deleted, an effect
    /// switched off): their textures stay pooled, unclaimed.
    pub fn end_frame(&mut self) {
        for (key, texture) in std::mem::take(&mut self.held) {
            self.give_back(key, texture);
        }
        end_graph_run(&mut self.last, &mut self.graphs);
    }
}

/// What names a pass output from frame to frame: its pass's name (the node
/// type and id, "Tonemap #12: blur"), which of the passes of that name it is
/// in declaration order, and which of its outputs. Texture names cannot: a
/// recipe made again (a jittered camera re-makes most each frame) names its
/// outputs after its new recipe id. Hashed: a collision costs only a preference.
pub(crate) fn slot(pass: &str, occurrence: u32, output: usize) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    (pass, occurrence, output).hash(&mut hasher);
    hasher.finish()
}

pub(crate) fn create_texture(
    device: &wgpu::Device,
    key: &TextureKey,
    label: &str,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: key.width,
            height: key.height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: key.format,
        usage: key.usage,
        view_formats: &[],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texture(device: &wgpu::Device, width: u32) -> wgpu::Texture {
        let key = TextureKey {
            format: wgpu::TextureFormat::Rgba8Unorm,
            width,
            height: 4,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
        };
        create_texture(device, &key, "view cache test")
    }

    #[test]
    fn a_view_stays_for_idle_graph_runs_unless_its_texture_is_let_go() {
        let renderer = crate::renderer::test_renderer();
        let device = &renderer.gpu.device;
        let (kept, forgotten) = (texture(device, 4), texture(device, 8));
        let mut views = ViewCache::default();
        views.view(&kept);
        views.view_of(&forgotten, ViewSpec::default());
        views.view_of(&forgotten, ViewSpec::array());
        views.forget(&forgotten);
        assert_eq!(
            views.views.len(),
            1,
            "both of its views go, the other stays"
        );
        // Another graph's runs, which ask for nothing: the view waits for them.
        for _ in 0..IDLE_GRAPHS {
            views.end_frame();
        }
        views.view(&kept);
        assert_eq!((views.created, views.reused), (3, 1));
        // The run that asked for it ends, then IDLE_GRAPHS runs that did
        // not: it is kept; one more, and it goes.
        for _ in 0..=IDLE_GRAPHS {
            views.end_frame();
        }
        assert_eq!(views.views.len(), 1, "unused for IDLE_GRAPHS runs: kept");
        views.end_frame();
        assert!(views.views.is_empty(), "unused past IDLE_GRAPHS runs");
    }
}

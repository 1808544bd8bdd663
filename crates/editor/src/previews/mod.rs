//! Previews of what flows: a live thumbnail on every texture (and G-buffer)
//! output of a node, a larger live preview when a texture, G-buffer or mesh
//! pin or a wire is hovered, with the texture's size, format and the value
//! under the pointer.
//!
//! The canvas asks only for what it draws on screen ([`CanvasPreviews`]:
//! a node off screen asks for nothing, so it costs nothing); the app sends
//! the list to the worker with each frame's request; the worker
//! ([`engine`]) evaluates those pins too ([`spreadlight_graph::Runtime::demand_also`]:
//! a branch that feeds no sink runs for its preview alone, the patch's own
//! demand, which `render` runs, is unchanged), declares their textures in
//! the first viewport's frame graph (a pass both need runs once), and
//! scales each into a small texture registered with egui: GPU to GPU, no
//! readback but the one texel under the pointer.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};
use spreadlight_graph::{NodeId, PinType, ResourceKind};
pub use spreadlight_render::gbuffer::Channel;

pub mod draw;
pub mod engine;
pub mod schedule;

/// A thumbnail's width on the canvas, in canvas points.
pub const THUMB_POINTS: f32 = 96.0;
/// A hover preview's width on screen, in points.
pub const LARGE_POINTS: f32 = 256.0;
/// Pixel widths the worker scales previews to (about 1.3 pixels a point at
/// real size; thumbnails are drawn smaller than real size most of the time).
pub const THUMB_PIXELS: u32 = 128;
pub const LARGE_PIXELS: u32 = 320;

/// One preview: a node's output pin (its path from the top patch), the
/// G-buffer channel when the pin is a G-buffer, and whether it is the large one.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct PreviewKey {
    pub path: Vec<NodeId>,
    pub pin: String,
    pub channel: Option<ChannelName>,
    pub large: bool,
}

/// A G-buffer channel by its name (`Channel` itself is not `Hash`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ChannelName(pub usize);

impl ChannelName {
    pub fn channel(self) -> Channel {
        Channel::ALL[self.0.min(Channel::ALL.len() - 1)]
    }

    pub fn of(channel: Channel) -> Self {
        ChannelName(Channel::ALL.iter().position(|c| *c == channel).unwrap_or(0))
    }
}

/// What the canvas asks the worker for: a preview, and the texel under the
/// pointer (as a fraction of the image, 0..1 from the top left) when the
/// pointer is over it.
#[derive(Clone, Debug, PartialEq)]
pub struct PreviewRequest {
    pub key: PreviewKey,
    pub probe: Option<(f32, f32)>,
}

/// A mesh's counts, for its preview.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshCounts {
    pub meshes: usize,
    pub vertices: u64,
    pub triangles: u64,
}

/// What the worker made of a preview.
#[derive(Clone, Default)]
pub struct PreviewOut {
    /// The scaled image, registered with egui.
    pub target: Option<crate::viewport::ViewTarget>,
    /// The texture it shows: its size in pixels and its format.
    pub source: Option<((u32, u32), wgpu::TextureFormat)>,
    /// The texel probed and its value (linear, unclamped).
    pub value: Option<((u32, u32), [f32; 4])>,
    pub mesh: Option<MeshCounts>,
    pub error: Option<String>,
    /// How it is refreshed, when not with every frame that changes it (a
    /// texture the patch's frame merges away: engine::MERGED_NOTE).
    pub note: Option<String>,
}

/// The previews of one finished frame, by key.
pub type PreviewOuts = Arc<HashMap<PreviewKey, PreviewOut>>;

/// What a pin of type `ty` previews as, if anything.
pub fn previewable(ty: PinType) -> bool {
    matches!(
        ty,
        PinType::Resource(ResourceKind::Texture | ResourceKind::GBuffer | ResourceKind::Mesh)
    )
}

/// Whether a pin of type `ty` gets a thumbnail on its node.
pub fn has_thumbnail(ty: PinType) -> bool {
    matches!(
        ty,
        PinType::Resource(ResourceKind::Texture | ResourceKind::GBuffer)
    )
}

/// The previews' settings, kept in the editor's config directory
/// (`previews.ron`): thumbnails on or off for all, and the nodes whose
/// thumbnail is hidden, per patch file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PreviewSettings {
    /// Thumbnails on nodes at all (Ctrl+T).
    #[serde(default = "yes")]
    pub thumbnails: bool,
    /// Per patch file: node paths (ids from the top patch) with no thumbnail (Shift+T).
    #[serde(default)]
    pub hidden: BTreeMap<PathBuf, BTreeSet<Vec<u32>>>,
}

fn yes() -> bool {
    true
}

const SETTINGS_FILE: &str = "previews.ron";

impl Default for PreviewSettings {
    fn default() -> Self {
        Self::new()
    }
}

impl PreviewSettings {
    pub fn new() -> Self {
        PreviewSettings {
            thumbnails: true,
            hidden: BTreeMap::new(),
        }
    }

    /// The settings saved in `config_dir`; defaults when there are none or
    /// they cannot be read (said on standard error: a bad settings file
    /// must not keep the editor from starting).
    pub fn load(config_dir: &Path) -> Self {
        let path = config_dir.join(SETTINGS_FILE);
        match std::fs::read_to_string(&path) {
            Ok(text) => ron::from_str(&text).unwrap_or_else(|e| {
                eprintln!(
                    "warning: {}: {e}; previews use their defaults",
                    path.display()
                );
                Self::new()
            }),
            Err(_) => Self::new(),
        }
    }

    pub fn save(&self, config_dir: &Path) -> Result<(), String> {
        let path = config_dir.join(SETTINGS_FILE);
        let text = ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .map_err(|e| e.to_string())?;
        std::fs::create_dir_all(config_dir)
            .and_then(|()| std::fs::write(&path, text))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    }

    /// Whether the node at `path` of patch `file` shows its thumbnails.
    pub fn shows(&self, file: Option<&Path>, path: &[NodeId]) -> bool {
        self.thumbnails && !self.is_hidden(file, path)
    }

    pub fn is_hidden(&self, file: Option<&Path>, path: &[NodeId]) -> bool {
        let key: Vec<u32> = path.iter().map(|n| n.0).collect();
        self.hidden
            .get(file.unwrap_or(Path::new("")))
            .is_some_and(|set| set.contains(&key))
    }

    /// Hide or show the thumbnail of the node at `path`.
    pub fn set_hidden(&mut self, file: Option<&Path>, path: &[NodeId], hidden: bool) {
        let key: Vec<u32> = path.iter().map(|n| n.0).collect();
        let file = file.unwrap_or(Path::new("")).to_owned();
        let set = self.hidden.entry(file.clone()).or_default();
        if hidden {
            set.insert(key);
        } else {
            set.remove(&key);
            if set.is_empty() {
                self.hidden.remove(&file);
            }
        }
    }
}

/// The canvas's side of the previews for one UI frame: what the last
/// finished frame made, and what this frame draws (and so asks for next).
#[derive(Default)]
pub struct CanvasPreviews {
    pub settings: PreviewSettings,
    /// The open patch's file (hidden thumbnails are per file).
    pub file: Option<PathBuf>,
    /// The latest finished frame's previews.
    pub outputs: PreviewOuts,
    /// Asked for while drawing this frame.
    pub wanted: Vec<PreviewRequest>,
    /// The list last sent to the worker.
    pub sent: Vec<PreviewRequest>,
    /// The G-buffer channel each node's thumbnail shows (by node path), when not Albedo.
    pub channels: HashMap<Vec<NodeId>, ChannelName>,
    /// Where this frame drew each thumbnail, in screen points.
    pub drawn: Vec<(PreviewKey, egui::Rect)>,
}

impl CanvasPreviews {
    pub fn new(settings: PreviewSettings) -> Self {
        CanvasPreviews {
            settings,
            ..Default::default()
        }
    }

    /// Start a UI frame on the latest finished frame's previews.
    pub fn begin(&mut self, outputs: PreviewOuts, file: Option<&Path>) {
        self.outputs = outputs;
        self.file = file.map(Path::to_owned);
        self.wanted.clear();
        self.drawn.clear();
    }

    /// Ask for a preview (once per key; a probe asked for later wins).
    pub fn want(&mut self, key: PreviewKey, probe: Option<(f32, f32)>) {
        match self.wanted.iter_mut().find(|w| w.key == key) {
            Some(w) => w.probe = probe.or(w.probe),
            None => self.wanted.push(PreviewRequest { key, probe }),
        }
    }

    pub fn channel_of(&self, path: &[NodeId]) -> ChannelName {
        self.channels.get(path).copied().unwrap_or(ChannelName(0))
    }

    /// What to send the worker when this frame's wishes differ from the last sent.
    pub fn take_request(&mut self) -> Option<Vec<PreviewRequest>> {
        let mut wanted = self.wanted.clone();
        wanted.sort_by(|a, b| a.key.cmp(&b.key));
        (wanted != self.sent).then(|| {
            self.sent = wanted.clone();
            wanted
        })
    }
}

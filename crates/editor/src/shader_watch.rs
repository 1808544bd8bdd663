//! Hot reload of shader nodes in the editor and in `spreadlight play` (the
//! show window alone): the shader folders of the open patch (its `shaders/`
//! and the user library) are polled a few times a second; a saved file
//! replaces its node type in the registry and the patch is recompiled,
//! keeping links and values (docs/shader-nodes.md). The polling and the
//! reload are the nodes crate's [`ShaderLibrary`]; this adds the pace.

use std::path::Path;

use spreadlight_graph::Registry;
use spreadlight_nodes::shader_nodes::{Changes, ShaderLibrary};

/// Seconds between looks at the folders: well within the second a save may take to show.
pub const POLL_SECS: f64 = 0.25;

pub struct ShaderWatch {
    library: ShaderLibrary,
    last_poll: f64,
}

impl ShaderWatch {
    /// Watch the folders of the patch at `path` (or only the user library).
    pub fn new(path: Option<&Path>) -> Self {
        ShaderWatch {
            library: ShaderLibrary::for_patch(path),
            last_poll: f64::NEG_INFINITY,
        }
    }

    /// Whether there is anything to watch, so the editor keeps waking up for
    /// it: a folder that exists (one made later is seen at the next repaint).
    pub fn is_watching(&self) -> bool {
        self.library.folders().iter().any(|f| f.is_dir())
    }

    /// Poll when due (`now` in seconds); what changed, if anything.
    pub fn poll(&mut self, now: f64, registry: &mut Registry) -> Option<Changes> {
        if now - self.last_poll < POLL_SECS {
            return None;
        }
        self.last_poll = now;
        self.poll_now(registry)
    }

    /// Poll now, whenever the last poll was (a patch just opened).
    pub fn poll_now(&mut self, registry: &mut Registry) -> Option<Changes> {
        let changes = self.library.poll(registry);
        (!changes.is_empty()).then_some(changes)
    }

    /// A status line for the last changes: the errors of broken files, or what reloaded.
    pub fn describe(&self, changes: &Changes) -> String {
        match self.library.errors().values().next() {
            Some(error) => format!("shader error: {error}"),
            None => format!("shaders reloaded: {}", changes.updated.join(", ")),
        }
    }
}

//! Recipes: how GPU results travel between nodes.
//!
//! A render node does not run its passes when it is evaluated; it outputs a
//! recipe (its buffers already uploaded, its passes ready to declare). A sink
//! builds a frame graph from the recipes it reaches, requests what it shows,
//! and the graph culls every pass that does not lead there.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::frame_graph::FrameGraph;
use crate::renderer::Renderer;

static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// A fresh id for a recipe: frame graphs declare each recipe once, by id.
pub fn next_recipe_id() -> u64 {
    NEXT_ID.fetch_add(1, Ordering::Relaxed)
}

/// What kind of recipe another is, for one that can work with its input
/// recipe's passes (an [`crate::environment::ImagePass`] over another runs
/// as one pass): `<dyn Recipe as AsAny>::as_any(&*recipe).downcast_ref()`.
pub trait AsAny {
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

pub trait Recipe: AsAny + Send + Sync {
    /// Declare this recipe's passes, after its inputs'. Must call `fg.include(id)` first and stop when it returns false.
    fn declare<'a>(&'a self, renderer: &'a Renderer, fg: &mut FrameGraph<'a>);

    /// The texture itself when it exists before any frame (an image file): GPU
    /// geometry runs as its node evaluates, outside the frame graph, and can
    /// read only such textures.
    fn static_texture(&self) -> Option<&crate::texture::GpuTexture> {
        None
    }
}

/// A texture some recipe produces, by its frame-graph name.
#[derive(Clone)]
pub struct TextureRef {
    pub recipe: Arc<dyn Recipe>,
    pub name: String,
}

impl TextureRef {
    /// Texture `name` of `recipe`: what a recipe hands on as its output.
    pub fn of<R: Recipe + 'static>(recipe: &Arc<R>, name: &str) -> Self {
        TextureRef {
            recipe: recipe.clone(),
            name: name.to_owned(),
        }
    }
}

/// The name of an optional input, for [`crate::frame_graph::PassBuilder::input_opt`].
pub fn name_of(input: &Option<TextureRef>) -> Option<&str> {
    input.as_ref().map(|t| t.name.as_str())
}

/// Declare the recipes a pass reads from, before the pass itself (every
/// recipe declares its inputs' passes first).
pub fn declare_inputs<'a>(
    renderer: &'a Renderer,
    fg: &mut FrameGraph<'a>,
    inputs: impl IntoIterator<Item = &'a TextureRef>,
) {
    for input in inputs {
        input.recipe.declare(renderer, fg);
    }
}

impl std::fmt::Debug for TextureRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "TextureRef({})", self.name)
    }
}

//! What GPU nodes share: getting the renderer, and moving GPU objects
//! through spreads as resource handles.

use std::sync::Arc;

use spreadlight_graph::{
    AfterEvaluate, EvalContext, NodeError, Resource, ResourceKind, Runtime, Spread,
};
use spreadlight_render::Renderer;

/// The node categories whose nodes need a GPU; hosts provide a renderer when a patch has one.
pub const GPU_CATEGORIES: &[&str] = &[
    "Geometry",
    "DeferredBase",
    "Texture",
    "Output",
    "Lighting",
    "Post",
    "Material",
    "Environment",
    "Particles",
];

/// Give a running patch its renderer, and the check after each node that
/// turns a device error no error scope caught while the node ran into that
/// node's error (`render::uncaptured`): what every host should call.
pub fn provide_renderer(runtime: &mut Runtime, renderer: Arc<Renderer>) {
    let gpu = renderer.gpu.clone();
    runtime.provide(Arc::new(AfterEvaluate(Box::new(move || {
        let errors = gpu.take_uncaptured_errors();
        (!errors.is_empty()).then(|| format!("GPU error: {}", errors.join("; ")))
    }))));
    runtime.provide(renderer);
}

/// The renderer the host provided, or an error that says how to get one.
pub fn renderer(cx: &EvalContext<'_>) -> Result<Arc<Renderer>, NodeError> {
    cx.service::<Renderer>().ok_or_else(|| {
        NodeError::Other(
            "no GPU renderer: evaluate this patch with `spreadlight render` (or the editor), which opens one".to_owned(),
        )
    })
}

/// The `T`s in a resource input. A handle of another type is an input error naming the pin.
pub fn resources<T: std::any::Any + Send + Sync>(
    cx: &EvalContext<'_>,
    pin: usize,
) -> Result<Vec<Arc<T>>, NodeError> {
    cx.resources_at(pin)
}

/// A spread of resources of `kind`.
pub fn resource_spread<T: std::any::Any + Send + Sync>(
    kind: ResourceKind,
    values: Vec<Arc<T>>,
) -> Spread {
    Spread::Resource(kind, values.into_iter().map(Resource::from_arc).collect())
}

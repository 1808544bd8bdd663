//! What every GPU geometry node keeps between evaluations: per slice, its
//! last output mesh (the source of the next output's previous positions) and
//! a signature of what made it. A run whose signature changed moved the
//! geometry, so the node asks to be evaluated once more next frame: that run
//! writes the same positions with themselves as previous, and velocity
//! settles to zero. Unchanged inputs after that: the runtime reuses the node
//! and no pass runs.

use std::hash::{DefaultHasher, Hash, Hasher};
use std::sync::Arc;

use spreadlight_graph::{EvalContext, NodeError};
use spreadlight_render::RenderError;
use spreadlight_render::mesh_arena::GpuMesh;

#[derive(Default)]
pub(crate) struct Continuity {
    last: Vec<(Arc<GpuMesh>, u64)>,
}

/// A signature of a slice's inputs: the input mesh (by identity) and the pins' bits.
pub(crate) fn signature(mesh: Option<&Arc<GpuMesh>>, values: &[f32]) -> u64 {
    let mut h = DefaultHasher::new();
    mesh.map(|m| Arc::as_ptr(m) as usize).hash(&mut h);
    for v in values {
        v.to_bits().hash(&mut h);
    }
    h.finish()
}

/// `signature` folded with another input's identity (a texture's address).
pub(crate) fn with_identity(signature: u64, identity: usize) -> u64 {
    let mut h = DefaultHasher::new();
    (signature, identity).hash(&mut h);
    h.finish()
}

impl Continuity {
    /// Makes `n` slices with `make(slice, last output)`, given each slice's
    /// signature, and asks for a settling run next frame when any moved.
    pub(crate) fn run(
        &mut self,
        cx: &mut EvalContext<'_>,
        signatures: Vec<u64>,
        mut make: impl FnMut(usize, Option<&GpuMesh>) -> Result<Arc<GpuMesh>, RenderError>,
    ) -> Result<Vec<Arc<GpuMesh>>, NodeError> {
        let mut moved = signatures.len() != self.last.len();
        let mut next = Vec::with_capacity(signatures.len());
        for (i, sig) in signatures.into_iter().enumerate() {
            let last = self.last.get(i);
            moved |= last.is_none_or(|(_, s)| *s != sig);
            let mesh = make(i, last.map(|(m, _)| m.as_ref()))
                .map_err(|e| NodeError::Other(format!("slice {i}: {e}")))?;
            next.push((mesh, sig));
        }
        self.last = next;
        if moved {
            cx.reevaluate_next_frame();
        }
        Ok(self.last.iter().map(|(m, _)| m.clone()).collect())
    }
}

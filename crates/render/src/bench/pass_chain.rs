//! `PassChain`: a chain of passes that do almost nothing on the GPU (a
//! 64x64 texture each, read from the one before: shaders/bench/pass_chain.wgsl),
//! so that with hundreds of them a frame's CPU time is the frame graph's own
//! cost per pass: declaring, scheduling, resolving names and handles,
//! binding, recording (`patches/bench-pass-chain.ron`, docs/benchmarks.md).
//!
//! Each pass is written as a real effect's pass is: it declares what it
//! reads and writes by name, binds a kept uniform and the graph's textures
//! by WGSL name, and dispatches through the shader cache.

use std::sync::Arc;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, FrameGraph, PassContext, SizeRule, Tex, TextureDesc};
use crate::recipe::{Recipe, TextureRef, next_recipe_id};
use crate::renderer::Renderer;
use crate::report::PassName;
use crate::shaders::Permutation;

pub use super::pass_chain_key::PassChainKey;

const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Each pass's texture: small, so that the GPU's share stays negligible.
pub const SIDE: u32 = 64;
/// More passes than a frame should ever hold; beyond it a typo.
pub const MAX_PASSES: u32 = 10_000;

pub struct PassChain {
    id: u64,
    owner: Option<u32>,
    /// Per pass: the texture it writes (made once, not per frame).
    names: Vec<String>,
    /// Per pass after the first: its step uniform (kept under the node).
    steps: Vec<wgpu::Buffer>,
}

impl PassChain {
    /// A chain of `passes` passes (1..=[`MAX_PASSES`]; clamped).
    pub fn new(renderer: &Renderer, owner: Option<u32>, passes: u32) -> Arc<Self> {
        let id = next_recipe_id();
        let passes = passes.clamp(1, MAX_PASSES);
        let names = (0..passes).map(|i| format!("pass chain{id}/{i}")).collect();
        let steps = (1..passes)
            .map(|i| {
                renderer.kept_init_at(
                    owner,
                    "pass chain step",
                    i,
                    bytemuck::cast_slice(&[i, passes - 1, 0, 0]),
                    wgpu::BufferUsages::UNIFORM,
                )
            })
            .collect();
        Arc::new(PassChain {
            id,
            owner,
            names,
            steps,
        })
    }

    /// The last pass's texture.
    pub fn texture(self: &Arc<Self>) -> TextureRef {
        TextureRef {
            recipe: self.clone(),
            name: self.names.last().cloned().unwrap_or_default(),
        }
    }

    fn desc() -> TextureDesc {
        TextureDesc::storage(FORMAT).size(SizeRule::Absolute {
            width: SIDE,
            height: SIDE,
        })
    }

    fn run(
        &self,
        cx: &mut PassContext<'_>,
        step: usize,
        source: Option<Tex>,
        output: Tex,
    ) -> Result<(), RenderError> {
        let key = PassChainKey.key();
        let groups = (SIDE.div_ceil(8), SIDE.div_ceil(8), 1);
        match (source, step.checked_sub(1).and_then(|k| self.steps.get(k))) {
            (Some(source), Some(uniform)) => cx.dispatch_shader(
                "pass chain step",
                &key,
                "next",
                Bindings::new()
                    .buffer("step", uniform)
                    .texture("source", source)
                    .texture("output", output),
                groups,
            ),
            _ => cx.dispatch_shader(
                "pass chain start",
                &key,
                "start",
                Bindings::new().texture("output", output),
                groups,
            ),
        }
    }
}

impl Recipe for PassChain {
    fn declare<'a>(&'a self, _: &'a Renderer, fg: &mut FrameGraph<'a>) {
        if !fg.include(self.id) {
            return;
        }
        for (step, name) in self.names.iter().enumerate() {
            let mut pass = fg.pass(PassName::new("PassChain").step("step"), self.owner);
            let source = step
                .checked_sub(1)
                .map(|previous| pass.read(&self.names[previous]));
            let output = pass.write(name, Self::desc());
            pass.run(move |cx| self.run(cx, step, source, output));
        }
    }
}

//! A DeferredBase layer's shader node material, as the G-buffer sees it:
//! the file's text (spliced into the surface resolve in place of
//! `spreadlight::custom_surface`), what its group-1 bindings are, and one
//! slice's uniform block and textures. The node library makes it from a
//! compiled material file (crates/render/src/shader_nodes/material.rs);
//! the G-buffer needs nothing else of shader nodes.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::recipe::TextureRef;

/// The library a material's file takes the place of in the resolve.
pub const SURFACE_MODULE: &str = "spreadlight::custom_surface";

/// What one group-1 binding of a material is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceBinding {
    /// The uniform block (the pins).
    Uniform,
    /// Texture input `i` (in `@input` order).
    Texture(usize),
    /// A linear sampler, repeating or clamping at the edge.
    Sampler { repeat: bool },
}

/// A material applied to a layer: one slice of a material node.
#[derive(Debug)]
pub struct SurfaceShader {
    /// The node and type, for pass names and errors (`Marble (Shader) #4`).
    pub label: String,
    /// The file as errors name it.
    pub file: String,
    /// Its text with the switches resolved: the module spliced into the resolve.
    pub text: String,
    /// Changes with the text (pipelines are cached under it).
    pub key: u64,
    pub bindings: Vec<(u32, SurfaceBinding)>,
    /// The uniform block with the pins written (empty without one).
    pub params: Vec<u8>,
    pub textures: Vec<TextureRef>,
    /// Permutations compiled to make it (counted once in the frame report).
    pub compiled: u64,
    /// It imports `spreadlight::materials`: the resolve binds the layer's
    /// material world in group 3 ([`SurfaceShader::reading_materials`]).
    pub reads_materials: bool,
    counted: AtomicBool,
}

impl SurfaceShader {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        label: String,
        file: String,
        text: String,
        key: u64,
        bindings: Vec<(u32, SurfaceBinding)>,
        params: Vec<u8>,
        textures: Vec<TextureRef>,
        compiled: u64,
    ) -> Self {
        SurfaceShader {
            label,
            file,
            text,
            key,
            bindings,
            params,
            textures,
            compiled,
            reads_materials: false,
            counted: AtomicBool::new(false),
        }
    }

    /// The material, reading its layer's material world (`spreadlight::materials`).
    pub fn reading_materials(mut self, reads: bool) -> Self {
        self.reads_materials = reads;
        self
    }

    /// The permutations compiled for it, the first time a frame asks.
    pub(crate) fn take_compiled(&self) -> u64 {
        if self.counted.swap(true, Ordering::Relaxed) {
            0
        } else {
            self.compiled
        }
    }
}

//! The typed key of `SSR`, [`SsrKey`] (`environment/ssr.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `environment/ssr/mod.rs` re-exports
//! it.

use crate::shaders::permutation::Permutation;

/// `environment/ssr.wgsl`'s permutations: what the trace reads of the
/// surfaces and where its result goes. The other entries (the hi-z, the
/// temporal resolve, the clear) read no material and take [`SsrKey::PLAIN`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SsrKey {
    /// Some material's CookTorrance parameters read a texture.
    pub material_textures: bool,
    /// The G-buffer has a surface target (surface maps, shader node
    /// materials), read in place of the materials' parameters.
    pub surface_target: bool,
    /// Some material has a clear coat (CLEARCOAT): a coated pixel also
    /// traces the coat's lobe, over the base dimmed by what it reflects.
    pub clearcoat: bool,
    pub target: SsrTarget,
}

/// Where the trace's result goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsrTarget {
    /// A full-size target: the output, or the temporal resolve's input.
    Full,
    /// Full size, with the history blended in the same pass (no resolve).
    FullTemporal,
    /// A half-size target, upsampled (and blended) by later passes.
    Half,
}

impl SsrKey {
    /// No switch on: the entries that read no material, and the plainest trace.
    pub const PLAIN: SsrKey = SsrKey {
        material_textures: false,
        surface_target: false,
        clearcoat: false,
        target: SsrTarget::Full,
    };
}

impl Permutation for SsrKey {
    crate::shader_file!("environment/ssr.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "MATERIAL_TEXTURES",
        "HALF",
        "SURFACE_TARGET",
        "TEMPORAL",
        "CLEARCOAT",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let target = match self.target {
            SsrTarget::Full => None,
            SsrTarget::FullTemporal => Some("TEMPORAL"),
            SsrTarget::Half => Some("HALF"),
        };
        self.material_textures
            .then_some("MATERIAL_TEXTURES")
            .into_iter()
            .chain(self.surface_target.then_some("SURFACE_TARGET"))
            .chain(self.clearcoat.then_some("CLEARCOAT"))
            .chain(target)
    }

    fn all() -> Vec<Self> {
        let both = [false, true];
        let targets = [SsrTarget::Full, SsrTarget::FullTemporal, SsrTarget::Half];
        both.into_iter()
            .flat_map(|material_textures| {
                both.into_iter().flat_map(move |surface_target| {
                    both.into_iter().flat_map(move |clearcoat| {
                        targets.map(|target| SsrKey {
                            material_textures,
                            surface_target,
                            clearcoat,
                            target,
                        })
                    })
                })
            })
            .collect()
    }
}

//! The typed key of `SSGI`, [`SsgiKey`] (`lighting/ssgi.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssgi.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `lighting/ssgi.wgsl`'s permutations: the gather (at full or half
/// resolution), the temporal blend (with the gather in the same pass at full
/// resolution), or a blur pass (adding the ambient light in the last one).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsgiKey {
    Gather { half: bool },
    Temporal { gather: bool },
    Blur { ambient: bool },
}

impl Permutation for SsgiKey {
    crate::shader_file!("lighting/ssgi.wgsl");
    const FEATURES: &'static [&'static str] = &["TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let on: &[&'static str] = match self {
            SsgiKey::Gather { half: false } => &[],
            SsgiKey::Gather { half: true } => &["HALF"],
            SsgiKey::Temporal { gather: false } => &["TEMPORAL"],
            SsgiKey::Temporal { gather: true } => &["TEMPORAL", "GATHER"],
            SsgiKey::Blur { ambient: false } => &["BLUR"],
            SsgiKey::Blur { ambient: true } => &["BLUR", "AMBIENT"],
        };
        on.iter().copied()
    }

    fn all() -> Vec<Self> {
        vec![
            SsgiKey::Gather { half: false },
            SsgiKey::Temporal { gather: false },
            SsgiKey::Temporal { gather: true },
            SsgiKey::Blur { ambient: false },
            SsgiKey::Blur { ambient: true },
            SsgiKey::Gather { half: true },
        ]
    }
}

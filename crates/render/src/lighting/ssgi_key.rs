//! The typed key of `SSGI`, [`SsgiKey`] (`lighting/ssgi.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssgi.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `lighting/ssgi.wgsl`'s permutations: the gather (at full or half
/// resolution), the temporal blend (with the gather in the same pass at full
/// resolution), or a blur pass (adding the ambient light in the last one;
/// `packed`: its taps read the G-buffer's packed surface, crate::packed_surface).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsgiKey {
    Gather { half: bool },
    Temporal { gather: bool },
    Blur { ambient: bool, packed: bool },
}

impl Permutation for SsgiKey {
    crate::shader_file!("lighting/ssgi.wgsl");
    const FEATURES: &'static [&'static str] =
        &["TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF", "PACKED"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let on: &[&'static str] = match self {
            SsgiKey::Gather { half: false } => &[],
            SsgiKey::Gather { half: true } => &["HALF"],
            SsgiKey::Temporal { gather: false } => &["TEMPORAL"],
            SsgiKey::Temporal { gather: true } => &["TEMPORAL", "GATHER"],
            SsgiKey::Blur {
                ambient: false,
                packed: false,
            } => &["BLUR"],
            SsgiKey::Blur {
                ambient: true,
                packed: false,
            } => &["BLUR", "AMBIENT"],
            SsgiKey::Blur {
                ambient: false,
                packed: true,
            } => &["BLUR", "PACKED"],
            SsgiKey::Blur {
                ambient: true,
                packed: true,
            } => &["BLUR", "AMBIENT", "PACKED"],
        };
        on.iter().copied()
    }

    fn all() -> Vec<Self> {
        vec![
            SsgiKey::Gather { half: false },
            SsgiKey::Temporal { gather: false },
            SsgiKey::Temporal { gather: true },
            SsgiKey::Blur {
                ambient: false,
                packed: false,
            },
            SsgiKey::Blur {
                ambient: true,
                packed: false,
            },
            SsgiKey::Gather { half: true },
            SsgiKey::Blur {
                ambient: false,
                packed: true,
            },
            SsgiKey::Blur {
                ambient: true,
                packed: true,
            },
        ]
    }
}

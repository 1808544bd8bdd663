//! The typed key of `SSGI`, [`SsgiKey`] (`lighting/ssgi.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssgi.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `lighting/ssgi.wgsl`'s permutations: the gather (at full or half
/// resolution), the temporal blend (with the gather in the same pass at full
/// resolution), or a blur pass (adding the ambient light in the last one).
/// `packed`: a gather's rays read the G-buffer's packed view z, a blur's
/// taps its packed surface (crate::packed_surface); a temporal blend alone
/// reads neither.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsgiKey {
    Gather { half: bool, packed: bool },
    Temporal { gather: bool, packed: bool },
    Blur { ambient: bool, packed: bool },
}

impl Permutation for SsgiKey {
    crate::shader_file!("lighting/ssgi.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF", "PACKED", "PACKED_Z",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let (on, packed): (&[&'static str], _) = match self {
            SsgiKey::Gather { half, packed } => (
                if half { &["HALF"] } else { &[] },
                packed.then_some("PACKED_Z"),
            ),
            SsgiKey::Temporal { gather, packed } => (
                if gather {
                    &["TEMPORAL", "GATHER"]
                } else {
                    &["TEMPORAL"]
                },
                packed.then_some("PACKED_Z"),
            ),
            SsgiKey::Blur { ambient, packed } => (
                if ambient {
                    &["BLUR", "AMBIENT"]
                } else {
                    &["BLUR"]
                },
                packed.then_some("PACKED"),
            ),
        };
        on.iter().copied().chain(packed)
    }

    fn all() -> Vec<Self> {
        use SsgiKey::{Blur, Gather, Temporal};
        // In the order of the feature sets as bits of FEATURES (the
        // permutation tests hold the enumeration to it). A blend alone never
        // reads the view z: its packed twin is valid and unused, kept so the
        // rules stay two (PACKED with BLUR, PACKED_Z without).
        let plain = [
            Gather {
                half: false,
                packed: false,
            },
            Temporal {
                gather: false,
                packed: false,
            },
            Temporal {
                gather: true,
                packed: false,
            },
            Blur {
                ambient: false,
                packed: false,
            },
            Blur {
                ambient: true,
                packed: false,
            },
            Gather {
                half: true,
                packed: false,
            },
        ];
        let packed = [
            Blur {
                ambient: false,
                packed: true,
            },
            Blur {
                ambient: true,
                packed: true,
            },
            Gather {
                half: false,
                packed: true,
            },
            Temporal {
                gather: false,
                packed: true,
            },
            Temporal {
                gather: true,
                packed: true,
            },
            Gather {
                half: true,
                packed: true,
            },
        ];
        plain.into_iter().chain(packed).collect()
    }
}

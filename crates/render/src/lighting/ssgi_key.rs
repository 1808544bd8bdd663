//! The typed key of `SSGI`, [`SsgiKey`] (`lighting/ssgi.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `lighting/ssgi.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `lighting/ssgi.wgsl`'s permutations: the gather (at full or half
/// resolution), the temporal blend (with the gather in the same pass at full
/// resolution), or a blur pass (adding the ambient light in the last one).
/// `packed`: a gather's rays read the G-buffer's packed view z, a blur's
/// taps its packed surface (crate::packed_surface); a temporal blend alone
/// reads neither. `half`: SSGI's half-resolution chain (crate::resolution),
/// whose blend and blurs run on the half-size image (a half blur never adds
/// the ambient nor reads the packed surface: the upsample after it adds it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SsgiKey {
    Gather {
        half: bool,
        packed: bool,
    },
    Temporal {
        gather: bool,
        packed: bool,
        half: bool,
    },
    Blur {
        ambient: bool,
        packed: bool,
        half: bool,
    },
}

impl Permutation for SsgiKey {
    crate::shader_file!("lighting/ssgi.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "TEMPORAL", "GATHER", "BLUR", "AMBIENT", "HALF", "PACKED", "PACKED_Z",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let (on, half, packed): (&[&'static str], _, _) = match self {
            SsgiKey::Gather { half, packed } => (&[], half, packed.then_some("PACKED_Z")),
            SsgiKey::Temporal {
                gather,
                packed,
                half,
            } => (
                if gather {
                    &["TEMPORAL", "GATHER"]
                } else {
                    &["TEMPORAL"]
                },
                half,
                packed.then_some("PACKED_Z"),
            ),
            SsgiKey::Blur {
                ambient,
                packed,
                half,
            } => (
                if ambient {
                    &["BLUR", "AMBIENT"]
                } else {
                    &["BLUR"]
                },
                half,
                packed.then_some("PACKED"),
            ),
        };
        on.iter()
            .copied()
            .chain(half.then_some("HALF"))
            .chain(packed)
    }

    fn all() -> Vec<Self> {
        use SsgiKey::{Blur, Gather, Temporal};
        // In the order of the feature sets as bits of FEATURES (the
        // permutation tests hold the enumeration to it). A blend alone never
        // reads the view z: its packed twins are valid and unused, kept so the
        // rules stay few (PACKED with BLUR, PACKED_Z without).
        let gather = |half, packed| Gather { half, packed };
        let temporal = |gather, packed, half| Temporal {
            gather,
            packed,
            half,
        };
        let blur = |ambient, packed, half| Blur {
            ambient,
            packed,
            half,
        };
        vec![
            gather(false, false),
            temporal(false, false, false),
            temporal(true, false, false),
            blur(false, false, false),
            blur(true, false, false),
            gather(true, false),
            temporal(false, false, true),
            blur(false, false, true),
            blur(false, true, false),
            blur(true, true, false),
            gather(false, true),
            temporal(false, true, false),
            temporal(true, true, false),
            gather(true, true),
            temporal(false, true, true),
        ]
    }
}

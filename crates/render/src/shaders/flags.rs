//! Typed keys for the common shader: independent switches, every subset a
//! permutation. [`flag_key!`](crate::flag_key) writes the struct of bools and
//! its [`Permutation`](super::Permutation) once, so an effect names its
//! switches as fields (`TonemapKey { eye_adaptation: true }`), not strings:
//!
//! ```ignore
//! crate::flag_key! {
//!     /// `post/tonemap.wgsl`.
//!     pub struct TonemapKey("post/tonemap.wgsl") {
//!         /// Exposure from the adapted luminance.
//!         eye_adaptation: "EYE_ADAPTATION",
//!     }
//! }
//! ```
//!
//! A shader whose switches are a choice of at most one gets an enum from
//! [`choice_key!`](crate::choice_key), its first variant the permutation with
//! none. Switches that constrain each other otherwise (one needing another)
//! are a key written by hand, an enum or struct whose values are exactly the
//! supported sets (`ssao/key.rs`).

/// A struct of one `bool` per feature switch of shader `$path`, with its
/// `Permutation`: every subset, enumerated in the order of the rule-based
/// enumeration (bit `i` of the mask is the `i`th feature).
#[macro_export]
macro_rules! flag_key {
    // A shader with no switches: one permutation, a unit struct.
    ($(#[$meta:meta])* $vis:vis struct $name:ident($path:literal);) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        $vis struct $name;

        impl $crate::shaders::permutation::Permutation for $name {
            $crate::shader_file!($path);
            const FEATURES: &'static [&'static str] = &[];

            fn features(self) -> impl Iterator<Item = &'static str> {
                std::iter::empty()
            }

            fn all() -> Vec<Self> {
                vec![$name]
            }
        }
    };
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident($path:literal) {
            $($(#[$field_meta:meta])* $field:ident: $feature:literal),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        $vis struct $name {
            $($(#[$field_meta])* pub $field: bool),*
        }

        impl $crate::shaders::permutation::Permutation for $name {
            $crate::shader_file!($path);
            const FEATURES: &'static [&'static str] = &[$($feature),*];

            fn features(self) -> impl Iterator<Item = &'static str> {
                <Self as $crate::shaders::permutation::Permutation>::FEATURES
                    .iter()
                    .copied()
                    .filter(move |_feature| false $(|| (*_feature == $feature && self.$field))*)
            }

            fn all() -> Vec<Self> {
                let features = <Self as $crate::shaders::permutation::Permutation>::FEATURES;
                (0u32..1 << features.len())
                    .map(|_mask| {
                        let _on = |feature: &str| {
                            features
                                .iter()
                                .position(|f| *f == feature)
                                .is_some_and(|i| _mask & (1 << i) != 0)
                        };
                        $name { $($field: _on($feature)),* }
                    })
                    .collect()
            }
        }
    };
}

/// An enum of the permutations of shader `$path` whose switches are a
/// choice of at most one: `$none` switches none on, each other variant its
/// feature. Enumerated as the rule `AtMostOne` enumerated them.
#[macro_export]
macro_rules! choice_key {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident($path:literal) {
            $(#[$none_meta:meta])* $none:ident,
            $($(#[$variant_meta:meta])* $variant:ident: $feature:literal),+ $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        $vis enum $name {
            $(#[$none_meta])* $none,
            $($(#[$variant_meta])* $variant),+
        }

        impl $crate::shaders::permutation::Permutation for $name {
            $crate::shader_file!($path);
            const FEATURES: &'static [&'static str] = &[$($feature),+];

            fn features(self) -> impl Iterator<Item = &'static str> {
                match self {
                    $name::$none => None,
                    $($name::$variant => Some($feature)),+
                }
                .into_iter()
            }

            fn all() -> Vec<Self> {
                vec![$name::$none, $($name::$variant),+]
            }
        }
    };
}

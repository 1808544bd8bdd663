//! What a permutation is: a shader file's description ([`ShaderFile`]), its
//! feature rules ([`Rule`]), the key of one permutation ([`ShaderKey`]) and
//! the typed keys' trait ([`Permutation`]). The bottom of the shader layer:
//! an effect's typed key (`ssao/key.rs`) implements [`Permutation`] from
//! here, and the table of files (`SHADERS` in `shaders/mod.rs`) names the
//! keys, so that neither needs the other's neighbours (the passes, the cache).

use std::collections::BTreeSet;

/// One WGSL file of `shaders/`.
pub struct ShaderFile {
    /// Path below `shaders/`, e.g. `gbuffer/visibility.wgsl`.
    pub path: &'static str,
    pub source: &'static str,
    /// The feature switches the file reacts to; every subset is a valid permutation.
    pub features: &'static [&'static str],
    /// Libraries are imported by other shaders; they have no entry points.
    pub library: bool,
    /// Which subsets make sense: a permutation that breaks a rule is refused
    /// and never compiled, and the permutation test skips it.
    pub rules: &'static [Rule],
    /// For a shader with a typed key ([`Permutation`]): its permutations,
    /// which replace the rules (every other subset is refused).
    pub keyed: Option<fn() -> Vec<ShaderKey>>,
}

/// A shader's permutations as a Rust type, beside the effect that runs it
/// (SSAO's `AoKey` in `ssao/key.rs`): each value is one permutation, and a
/// combination the shader does not support cannot be written, so the
/// effect's code says `AoKey { estimator, target }`, not a list of strings.
pub trait Permutation: Copy + 'static {
    /// The shader, below `shaders/`.
    const PATH: &'static str;
    /// Every feature switch the shader reacts to.
    const FEATURES: &'static [&'static str];
    /// The switches this permutation turns on.
    fn features(self) -> impl Iterator<Item = &'static str>;
    /// Every permutation the shader supports.
    fn all() -> Vec<Self>;

    fn key(self) -> ShaderKey {
        ShaderKey::new(Self::PATH, self.features())
    }

    /// The keys of [`Permutation::all`], for `SHADERS`.
    fn all_keys() -> Vec<ShaderKey> {
        Self::all().into_iter().map(Self::key).collect()
    }
}

/// A constraint between the features of one shader.
#[derive(Clone, Copy, Debug)]
pub enum Rule {
    /// The first feature only with the second (a third light pair only with a second).
    Requires(&'static str, &'static str),
    /// At most one of these (a choice, such as GBufferView's channel).
    AtMostOne(&'static [&'static str]),
}

impl Rule {
    pub(super) fn check(&self, features: &BTreeSet<&'static str>) -> Result<(), String> {
        match *self {
            Rule::Requires(a, b) if features.contains(a) && !features.contains(b) => {
                Err(format!("`{a}` needs `{b}`"))
            }
            Rule::AtMostOne(set) if set.iter().filter(|f| features.contains(*f)).count() > 1 => {
                Err(format!(
                    "these features are a choice, set at most one: {}",
                    set.join(", ")
                ))
            }
            _ => Ok(()),
        }
    }
}

/// Which permutation of which shader: its path and the set of switched-on features.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ShaderKey {
    pub path: &'static str,
    pub features: BTreeSet<&'static str>,
}

impl ShaderKey {
    pub fn new(path: &'static str, features: impl IntoIterator<Item = &'static str>) -> Self {
        ShaderKey {
            path,
            features: features.into_iter().collect(),
        }
    }

    pub(super) fn describe_defs(&self) -> String {
        if self.features.is_empty() {
            String::new()
        } else {
            format!(
                " [{}]",
                self.features.iter().copied().collect::<Vec<_>>().join(", ")
            )
        }
    }
}

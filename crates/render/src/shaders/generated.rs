//! Shaders generated over the embedded sources instead of written as a file
//! (the fused light loop, `lighting::light_sets`), named so that the cold
//! start's lists can hold them like any permutation.
//!
//! A generated shader is a function of its generator's code and of the
//! permutations it is made from ([`GeneratedKey`]): the light loop of each
//! set, renamed and composed together. So the last run's list names the
//! generator and the parts (never the code, as for a permutation), and a new
//! process generates and composes it again on a thread from those names
//! (`crate::precompose`), then creates its pipeline on another
//! (`crate::shaders::pipelines_ahead`), before the frame asks; a first
//! run's frame announces it where its pass is declared. Generated again from
//! this binary's sources, a list can never bring back a stale shader: a
//! part this build lacks is skipped, and a group the generator refuses is
//! left to the frame, which reports the error where it shades.

use super::{ShaderComposer, ShaderFile, ShaderKey};
use crate::error::RenderError;

/// Generate and compose a shader from its parts and options: a label for
/// messages and captures, and the validated module.
pub type Compose =
    fn(&mut ShaderComposer, &[ShaderKey], &[String]) -> Result<(String, naga::Module), RenderError>;

/// A kind of generated shader (its one value a `static` beside the code
/// that generates it, listed in `crate::permutations::GENERATORS`).
pub struct Generator {
    /// Its name in a permutation list (letters and underscores).
    pub name: &'static str,
    /// The file whose permutations the parts are.
    pub file: &'static ShaderFile,
    /// The compute entry point of what it generates.
    pub entry: &'static str,
    pub compose: Compose,
}

/// Which generated shader: its generator, the permutations it is made of,
/// in order, and the generator's own switches for the whole (`options`:
/// e.g. the summed light sets' `LIGHT_SUM` and which outputs each set still
/// writes; empty for most). Compared and hashed by the generator's name,
/// the parts and the options.
#[derive(Clone)]
pub struct GeneratedKey {
    pub generator: &'static Generator,
    pub parts: Vec<ShaderKey>,
    pub options: Vec<String>,
}

impl GeneratedKey {
    /// What is compared and hashed.
    fn id(&self) -> (&'static str, &[ShaderKey], &[String]) {
        (self.generator.name, &self.parts, &self.options)
    }

    /// Generate and compose it with `composer` (no sharing: see
    /// [`ShaderComposer::generate`]).
    pub(super) fn compose_with(
        &self,
        composer: &mut ShaderComposer,
    ) -> Result<(String, naga::Module), RenderError> {
        (self.generator.compose)(composer, &self.parts, &self.options)
    }
}

impl PartialEq for GeneratedKey {
    fn eq(&self, other: &Self) -> bool {
        self.id() == other.id()
    }
}

impl Eq for GeneratedKey {}

impl std::hash::Hash for GeneratedKey {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.id().hash(state);
    }
}

impl std::fmt::Debug for GeneratedKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GeneratedKey")
            .field("generator", &self.generator.name)
            .field("parts", &self.parts)
            .field("options", &self.options)
            .finish()
    }
}

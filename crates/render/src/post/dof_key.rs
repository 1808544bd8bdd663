//! The typed key of `DOF`, [`DofKey`] (`post/dof.wgsl`). It declares its shader file
//! (`shader_file!`), so no table below the effects names it; `post/dof.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// `post/dof.wgsl`'s permutations, one key for every entry of a DOF (circle
/// of confusion, tiles, blur).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DofKey {
    /// The focus distance read from a texture (the Autofocus pass's), not the parameters.
    pub autofocus: bool,
    /// The lens blur's shape read from a bokeh texture, not a disc.
    pub bokeh: bool,
    /// The blur at half resolution (`HALF`): the upsample reads the circle
    /// of confusion, so a pass writes it. At full resolution no pass does:
    /// the tiles and the blur make it from the depth where they read it
    /// (`INLINE_COC`). A DOF always takes one of the two.
    pub half: bool,
}

impl Permutation for DofKey {
    crate::shader_file!("post/dof.wgsl");
    const FEATURES: &'static [&'static str] = &["AUTOFOCUS", "BOKEH", "HALF", "INLINE_COC"];

    fn features(self) -> impl Iterator<Item = &'static str> {
        let coc = if self.half { "HALF" } else { "INLINE_COC" };
        self.autofocus
            .then_some("AUTOFOCUS")
            .into_iter()
            .chain(self.bokeh.then_some("BOKEH"))
            .chain([coc])
    }

    fn all() -> Vec<Self> {
        let both = [false, true];
        both.into_iter()
            .flat_map(|half| {
                both.into_iter().flat_map(move |bokeh| {
                    both.map(|autofocus| DofKey {
                        autofocus,
                        bokeh,
                        half,
                    })
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The string rule this key replaced (at most one of `HALF` and
    /// `INLINE_COC`) also allowed neither, a permutation no DOF built: its
    /// blur would read a CoC target no pass wrote at full resolution. The
    /// key has the 8 of the rule's 12 that DOF runs.
    #[test]
    fn every_key_takes_its_circle_of_confusion_one_way() {
        let all = DofKey::all();
        assert_eq!(all.len(), 8);
        let sets: std::collections::HashSet<_> = all.iter().map(|k| k.key().features).collect();
        assert_eq!(sets.len(), 8, "each key a permutation of its own");
        for key in all {
            let features = key.key().features;
            assert!(
                features.contains("HALF") != features.contains("INLINE_COC"),
                "{key:?}"
            );
            assert_eq!(features.contains("HALF"), key.half);
        }
    }
}

//! Light sets that CompositeLight reads as one pair of sums (issue 33,
//! GPU per frame).
//!
//! Fused, the light sets still each wrote their own diffuse and specular
//! targets (two RGBA16F images a set: 33 MB at 1080p), and every
//! CompositeLight read them all back: emeshe-frame.ron's three sets wrote
//! six targets that two CompositeLights read, 300 MB of memory traffic a
//! frame. Summed, the sets add their terms to two sums in registers, the
//! fused pass writes those once (`lightsums/<ids>/diffuse`, `/specular`,
//! named by the sets' recipe ids so that every CompositeLight with those
//! sets finds them), and a CompositeLight whose components include all the
//! sets reads the pair in their place. The sets' own targets are declared
//! [`TextureDesc::only_if_read`](crate::frame_graph::TextureDesc::only_if_read):
//! where nothing else reads them they are not made (counted under
//! [`TARGETS_NOT_MADE`](crate::frame_graph::TARGETS_NOT_MADE)); where
//! something does (a node declared later than the CompositeLight), the
//! fused pass writes them as well, as before.
//!
//! The image changes by rounding only: CompositeLight added each set's
//! terms rounded to half floats one by one, it now adds their sum rounded
//! once, and before the GI term rather than around it
//! (`tests/patches.rs::summed_light_sets_render_within_rounding_of_separate_passes`
//! states the error). The switch: [`LightSums`], `SPREADLIGHT_LIGHT_SUMS`,
//! `bench --light-sums`; it applies where light sets fuse ([`super::LightFusion`]).

use super::cook_torrance;
use crate::recipe::TextureRef;
use crate::renderer::Renderer;

/// Whether fused light sets write one pair of sums for CompositeLight.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSums {
    /// One pair of sums where a CompositeLight reads them (this module).
    /// Not the default: measured slower on the H200 (emeshe-frame's frame
    /// span 1.516 ms against 1.481 with the sums off, session 21,
    /// docs/benchmarks.md "Session 21 on the H200").
    On,
    /// Each set writes its own targets, CompositeLight reads them all (the
    /// fused pass of session 20: the same pictures as separate passes, bit
    /// for bit).
    #[default]
    Off,
}

/// The environment variable that picks [`LightSums`] for a process (`on`
/// or `off`); `set_light_sums` (`bench --light-sums`) overrides it.
pub const LIGHT_SUMS_VAR: &str = "SPREADLIGHT_LIGHT_SUMS";

/// Counted each frame: the light sets a fused pass summed into one pair.
pub const SUMMED_LIGHT_SETS: &str = "light sets summed";

/// Counted each frame: the CompositeLights that read a pair of sums in
/// place of their sets' own targets.
pub const LIGHT_SUMS_READ: &str = "light sums read by CompositeLight";

impl LightSums {
    /// The setting a value of [`LIGHT_SUMS_VAR`] names, `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "on" => Some(LightSums::On),
            "off" => Some(LightSums::Off),
            _ => None,
        }
    }

    /// What [`LIGHT_SUMS_VAR`] asks for; unset, the default. A value it
    /// does not know is an error naming the variable and the value.
    pub fn from_env() -> Result<Self, String> {
        crate::setting::from_env(LIGHT_SUMS_VAR, Self::parse, "`on` or `off`")
    }
}

/// The renderer's [`LightSums`]: as set, else the environment's (an unknown
/// value there counts as the default; `bench` refuses it first).
pub fn light_sums(renderer: &Renderer) -> LightSums {
    renderer.setting(0, || LightSums::from_env().unwrap_or_default())
}

/// Set the renderer's [`LightSums`] (from the next frame graph declared on).
pub fn set_light_sums(renderer: &Renderer, sums: LightSums) {
    renderer.set_setting(0, sums);
}

/// The sums' texture names (diffuse, specular) for the sets of recipes
/// `ids`, whatever their order: any CompositeLight of the same sets names
/// the same pair.
pub(crate) fn sum_names(ids: &mut [u64]) -> [String; 2] {
    ids.sort_unstable();
    let joined = ids.iter().map(u64::to_string).collect::<Vec<_>>().join("+");
    [
        format!("lightsums/{joined}/diffuse"),
        format!("lightsums/{joined}/specular"),
    ]
}

/// A pair of sums a CompositeLight could read: the components it stands
/// for (bit k: component k) and its texture names.
#[derive(Clone, Debug)]
pub(crate) struct SumCandidate {
    pub members: u8,
    pub diffuse: String,
    pub specular: String,
}

/// The pairs of sums that could stand for two or more of `components`,
/// most components first: made once per CompositeLight, looked up each
/// frame by name (a frame that summed those sets declared them). A
/// component counts only when it is one CookTorrance's outputs whole
/// (its diffuse, its specular and its subsurface term, if any). The
/// components are CompositeLight's (diffuse, specular, subsurface), up to
/// eight (a bit each; CompositeLight takes four): passed as textures so
/// that this module needs nothing of CompositeLight's, which reads it.
pub(crate) fn candidates(
    components: &[(&TextureRef, &TextureRef, Option<&TextureRef>)],
) -> Vec<SumCandidate> {
    let ids: Vec<Option<u64>> = components
        .iter()
        .map(|(diffuse, specular, sss)| {
            let recipe = cook_torrance(diffuse)?;
            let whole = diffuse.name == recipe.diffuse
                && specular.name == recipe.specular
                && sss.map(|t| &t.name) == recipe.sss.as_ref();
            whole.then(|| recipe.id())
        })
        .collect();
    let n = components.len().min(u8::BITS as usize);
    let mut masks: Vec<u8> = (1u8..1 << n)
        .filter(|m| m.count_ones() >= 2)
        .filter(|m| {
            let chosen: Vec<u64> = (0..n)
                .filter(|k| m & (1 << k) != 0)
                .filter_map(|k| ids[k])
                .collect();
            // Every chosen component a whole recipe, none twice.
            let mut unique = chosen.clone();
            unique.sort_unstable();
            unique.dedup();
            chosen.len() == m.count_ones() as usize && unique.len() == chosen.len()
        })
        .collect();
    masks.sort_by_key(|m| std::cmp::Reverse(m.count_ones()));
    masks
        .into_iter()
        .map(|members| {
            let mut chosen: Vec<u64> = (0..n)
                .filter(|k| members & (1 << k) != 0)
                .filter_map(|k| ids[k])
                .collect();
            let [diffuse, specular] = sum_names(&mut chosen);
            SumCandidate {
                members,
                diffuse,
                specular,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_setting_parses_and_the_names_ignore_order() {
        assert_eq!(LightSums::parse(" On "), Some(LightSums::On));
        assert_eq!(LightSums::parse("off"), Some(LightSums::Off));
        assert_eq!(LightSums::parse("yes"), None);
        assert_eq!(LightSums::default(), LightSums::Off);
        let a = sum_names(&mut [12, 3, 7]);
        let b = sum_names(&mut [7, 12, 3]);
        assert_eq!(a, b);
        assert_eq!(a[0], "lightsums/3+7+12/diffuse");
        assert_eq!(a[1], "lightsums/3+7+12/specular");
    }
}

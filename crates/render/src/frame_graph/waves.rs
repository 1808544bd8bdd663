//! Passes ordered in waves, so that the GPU may run independent passes side
//! by side (`PassOrder::Waves`; issue 33, the idle time between passes).
//!
//! By default the graph runs its passes in declaration order wherever the
//! reads allow (Kahn's order, the lowest index first): a recipe's passes
//! follow each other, and a pass that reads nothing made this frame (a light
//! assignment, a shadow map) waits for the passes declared before it. On a
//! GPU every dependency between two dispatches is a pipeline barrier, and a
//! Vulkan barrier waits for *all* the compute work before it, not only the
//! writer it is for: so in declaration order a barrier before each pass that
//! reads something new drains every pass before it, and the GPU runs about
//! one pass at a time, idle at every pass's start and tail (emeshe-frame.ron
//! on the H200: 0.10 ms of idle between its 24 passes, and most passes a
//! short full-screen dispatch whose last wave leaves most of the GPU idle).
//!
//! Waves: each pass's wave is one more than the latest wave of the passes
//! it reads from (0 for a pass that reads nothing made this frame), and the
//! passes run wave by wave, in the declaration order within a wave. Every
//! pass of a wave reads only what earlier waves made, so no two passes of a
//! wave depend on each other: in emeshe-frame the SSAO estimate, the three
//! CookTorrance shades, Reflection and SSR's hierarchical depth all read only
//! the G-buffer and become one wave.
//!
//! What makes them overlap is where wgpu-core 30 puts the barriers: a
//! compute pass prepares the first use of each resource *before* the pass
//! (its "pre pass" command buffer, one barrier for all of them) and records
//! a barrier before a dispatch only for a resource whose use changes inside
//! the pass (`command/compute.rs`, `flush_bindings` and `insert_barriers_from_tracker`).
//! So the executor ends the open compute pass before a wave of two or more
//! passes: every resource the wave reads or writes is then first used inside
//! the wave's compute pass, is transitioned once before it, and no barrier
//! separates the wave's dispatches. Between waves the barriers stay (they
//! are the real dependencies). A temporary read in a wave goes back to the
//! texture pool only after the wave's last pass, so no later pass of the
//! same wave is handed the memory a pass beside it still reads (wgpu would
//! put a barrier there, correct but no longer side by side).
//!
//! A pass that asks for the encoder itself (a render pass, a copy, a
//! clear: `PassContext::encoder`) ends the open compute pass, and the
//! barriers before it wait for everything before it. The executor remembers
//! by name which passes did in their last run, and such passes go first in
//! their wave: their barriers then wait only for earlier waves, and the
//! wave's dispatches after them stay in one compute pass.
//!
//! The images are the same in either order: each pass reads the same
//! textures, written by the same passes, and wgpu orders what depends. Only
//! when the passes start on the GPU changes, and the texture pool's
//! lifetimes (a pass early in the frame may keep its output longer).

/// The order the frame graph runs its passes in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PassOrder {
    /// Declaration order wherever the reads allow (the order of every
    /// session before issue 33's waves).
    Declared,
    /// Wave by wave: passes that depend on nothing of each other next to
    /// each other, with no barrier between them (this module).
    Waves,
    /// Waves on a GPU, declaration order on a CPU adapter (lavapipe runs
    /// one dispatch at a time whatever the barriers, so waves only cost it
    /// compute passes): the default, since on the H200 waves shortened the
    /// frame span of emeshe-frame, post and emeshe-heavy by 2-4%
    /// (docs/benchmarks.md, "Passes in waves") ([`PassOrder::on`]).
    #[default]
    Auto,
}

/// The environment variable that picks the order for a process
/// (`declared`, `waves` or `auto`), for benchmarking both in one call
/// (docs/benchmarks.md); a renderer's `set_pass_order` overrides it.
pub const PASS_ORDER_VAR: &str = "SPREADLIGHT_PASS_ORDER";

/// Counted each frame: the waves of two or more passes (each begins a compute pass).
pub const PASS_WAVES: &str = "pass waves";

impl PassOrder {
    /// The order a value of [`PASS_ORDER_VAR`] names, `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "declared" => Some(PassOrder::Declared),
            "waves" => Some(PassOrder::Waves),
            "auto" => Some(PassOrder::Auto),
            _ => None,
        }
    }

    /// The order taken on an adapter of `class`: `Auto` resolved, the others as they are.
    pub fn on(self, class: crate::adapter_class::AdapterClass) -> Self {
        use crate::adapter_class::AdapterClass;
        match (self, class) {
            (PassOrder::Auto, AdapterClass::Gpu) => PassOrder::Waves,
            (PassOrder::Auto, AdapterClass::Cpu) => PassOrder::Declared,
            (order, _) => order,
        }
    }

    /// The order [`PASS_ORDER_VAR`] asks for; unset, the default (`Auto`). A value it
    /// does not know is an error naming the variable and the value (a
    /// benchmark must not measure another order than the one it was asked).
    pub fn from_env() -> Result<Self, String> {
        crate::setting::from_env(PASS_ORDER_VAR, Self::parse, "`declared`, `waves` or `auto`")
    }
}

/// `order` (a valid order of the passes: each after the passes it reads
/// from) re-ordered wave by wave, and for each step of the new order the
/// last step of its wave. Within a wave the passes for which `first` holds
/// come first (those that used the encoder itself last frame: a render
/// pass's or a copy's barriers then wait only for the waves before, and the
/// wave's dispatches stay in one compute pass after them), then the rest,
/// each group in the order given. `reads` and `writes` are by pass; a read
/// that no pass of `order` writes (imported, persistent from the last
/// frame) puts the reader in no later wave.
pub(crate) fn in_waves<W>(
    order: &[usize],
    reads: &[Vec<String>],
    writes: &[Vec<(String, W)>],
    first: &dyn Fn(usize) -> bool,
) -> (Vec<usize>, Vec<usize>) {
    let mut wave_of_name: rustc_hash::FxHashMap<&str, u32> =
        rustc_hash::FxHashMap::with_capacity_and_hasher(order.len() * 2, Default::default());
    let mut waves: Vec<(u32, usize)> = Vec::with_capacity(order.len());
    for &p in order {
        // Producers come before their readers in `order`, so their waves are known.
        let wave = reads[p]
            .iter()
            .filter_map(|r| wave_of_name.get(r.as_str()))
            .map(|w| w + 1)
            .max()
            .unwrap_or(0);
        for (name, _) in &writes[p] {
            wave_of_name.insert(name.as_str(), wave);
        }
        waves.push((wave, p));
    }
    // Stable: within a wave and group, the order given.
    waves.sort_by_key(|&(wave, p)| (wave, !first(p)));
    let mut ends = vec![0; waves.len()];
    let mut start = 0;
    while start < waves.len() {
        let wave = waves[start].0;
        let end = start + waves[start..].iter().take_while(|w| w.0 == wave).count() - 1;
        ends[start..=end].fill(end);
        start = end + 1;
    }
    (waves.into_iter().map(|(_, p)| p).collect(), ends)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn passes_go_wave_by_wave_in_their_order_within_a_wave() {
        // 0: a (reads the import), 1: b <- a, 2: c (reads nothing made),
        // 3: d <- b, c, 4: e <- the persistent history only.
        let reads = vec![
            names(&["import"]),
            names(&["a"]),
            names(&[]),
            names(&["b", "c"]),
            names(&["history"]),
        ];
        let writes: Vec<Vec<(String, ())>> = ["a", "b", "c", "d", "e"]
            .iter()
            .map(|w| vec![(w.to_string(), ())])
            .collect();
        let none = |_: usize| false;
        let (order, ends) = in_waves(&[0, 1, 2, 3, 4], &reads, &writes, &none);
        assert_eq!(order, vec![0, 2, 4, 1, 3]);
        // Wave 0 is steps 0..=2, wave 1 step 3, wave 2 step 4.
        assert_eq!(ends, vec![2, 2, 2, 3, 4]);
        // A pass that used the encoder goes first in its wave, and only there.
        let (order, ends) = in_waves(&[0, 1, 2, 3, 4], &reads, &writes, &|p| p == 4 || p == 3);
        assert_eq!(order, vec![4, 0, 2, 1, 3]);
        assert_eq!(ends, vec![2, 2, 2, 3, 4]);
        // A chain stays a chain, one pass a wave.
        let chain: Vec<Vec<String>> = vec![names(&[]), names(&["a"]), names(&["b"])];
        let (order, ends) = in_waves(&[0, 1, 2], &chain, &writes[..3], &none);
        assert_eq!((order, ends), (vec![0, 1, 2], vec![0, 1, 2]));
    }

    #[test]
    fn the_order_is_named_by_the_environment_value() {
        assert_eq!(PassOrder::parse("waves"), Some(PassOrder::Waves));
        assert_eq!(PassOrder::parse(" Declared "), Some(PassOrder::Declared));
        assert_eq!(PassOrder::parse("auto"), Some(PassOrder::Auto));
        assert_eq!(PassOrder::parse("fast"), None);
        assert_eq!(PassOrder::default(), PassOrder::Auto);
    }

    #[test]
    fn auto_takes_waves_on_a_gpu_and_declaration_order_on_a_cpu_adapter() {
        use crate::adapter_class::AdapterClass::{Cpu, Gpu};
        assert_eq!(PassOrder::Auto.on(Gpu), PassOrder::Waves);
        assert_eq!(PassOrder::Auto.on(Cpu), PassOrder::Declared);
        for order in [PassOrder::Declared, PassOrder::Waves] {
            assert_eq!(order.on(Gpu), order);
            assert_eq!(order.on(Cpu), order);
        }
    }
}

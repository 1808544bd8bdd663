//! The typed key of the accumulator, [`AccumulateKey`] (`accumulate/add.wgsl`), in a file of its own
//! that imports no pass, so that `shaders::SHADERS` names it without a circle through the renderer
//! (docs/architecture.md, "Layers inside render").

crate::flag_key! {
    /// `accumulate/add.wgsl`: one permutation.
    pub struct AccumulateKey("accumulate/add.wgsl");
}

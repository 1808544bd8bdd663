//! The typed key of the accumulator, [`AccumulateKey`] (`accumulate/add.wgsl`), in a file of its own
//! that imports no pass; it declares its shader file (`shader_file!`).

crate::flag_key! {
    /// `accumulate/add.wgsl`: one permutation.
    pub struct AccumulateKey("accumulate/add.wgsl");
}

//! Recipes that exist to be measured: synthetic work that isolates one cost
//! of the renderer (`spreadlight bench`, docs/benchmarks.md).

pub mod pass_chain;
pub(crate) mod pass_chain_key;

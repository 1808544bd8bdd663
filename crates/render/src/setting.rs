//! A renderer's switches (light fusion and sums, shadow layers, what
//! Resolution Auto resolves to, the pass order, submission, the packed
//! surface): each read from its environment variable, so one binary
//! measures both ways, and kept as the renderer's state so a test can set
//! one renderer without a variable that would reach every renderer of the
//! process.

use std::sync::Mutex;

use crate::renderer::Renderer;

/// What the environment variable `var` asks for, parsed by `parse`; unset,
/// `T`'s default. A value `parse` does not know is an error naming the
/// variable and the value, with `values` (what it takes, for the message):
/// a benchmark must not measure another setting than the one it was asked.
pub(crate) fn from_env<T: Default>(
    var: &str,
    parse: impl FnOnce(&str) -> Option<T>,
    values: &str,
) -> Result<T, String> {
    match std::env::var(var) {
        Err(std::env::VarError::NotPresent) => Ok(T::default()),
        Err(e) => Err(format!("{var}: {e}")),
        Ok(value) => parse(&value).ok_or_else(|| format!("{var} is `{value}`: it takes {values}")),
    }
}

/// A renderer's `T`, once set or read.
struct Kept<T>(Mutex<Option<T>>);

impl<T> Default for Kept<T> {
    fn default() -> Self {
        Kept(Mutex::new(None))
    }
}

/// The renderer's `T` under `key`: as set ([`set`]), else `read()` the first
/// time (the environment's, which decides what an unknown value counts as).
pub(crate) fn get<T: Copy + Send + Sync + 'static>(
    renderer: &Renderer,
    key: u64,
    read: impl FnOnce() -> T,
) -> T {
    let kept = renderer.state::<Kept<T>>(key);
    let mut chosen = kept.0.lock().unwrap_or_else(|e| e.into_inner());
    *chosen.get_or_insert_with(read)
}

/// Set the renderer's `T` under `key` (for what is declared from now on).
pub(crate) fn set<T: Copy + Send + Sync + 'static>(renderer: &Renderer, key: u64, value: T) {
    let kept = renderer.state::<Kept<T>>(key);
    *kept.0.lock().unwrap_or_else(|e| e.into_inner()) = Some(value);
}

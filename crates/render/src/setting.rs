//! A renderer's switches (light fusion and sums, shadow layers, what
//! Resolution Auto resolves to, the pass order, submission, the packed
//! surface): each read from its environment variable, so one binary
//! measures both ways, and kept by the renderer ([`Renderer::setting`]) so
//! a test can set one renderer without a variable that would reach every
//! renderer of the process.
//!
//! [`Renderer::setting`]: crate::renderer::Renderer::setting

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

//! Whether the compute rasterizer draws a shadow node's layers one at a
//! time or together (raster_layered.rs), picked per process by
//! [`SHADOW_LAYERS_VAR`] or per renderer by [`set_shadow_layers`], so one
//! binary measures both.

use crate::renderer::Renderer;

/// How the compute rasterizer draws the layers a frame renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShadowLayers {
    /// A raster chain per layer (and per strip of a scrolled cascade):
    /// clear, tile reset, the batches' and the tiles' dispatches and a
    /// resolve each, then the moments a dispatch per region.
    Each,
    /// One chain for every layer drawn from one set of casters into one
    /// target: the layer a dispatch dimension, one clear, one resolve
    /// writing every layer, and VSM's moments in one dispatch. The same
    /// atomics on the same words per layer, so the same depth bit for bit
    /// (tests/shadow_layers.rs). The default: it records a fraction of the
    /// commands and runs the same work with fewer barriers between.
    #[default]
    Together,
}

/// The environment variable that picks [`ShadowLayers`] for a process
/// (`each` or `together`); [`set_shadow_layers`] overrides it.
pub const SHADOW_LAYERS_VAR: &str = "SPREADLIGHT_SHADOW_LAYERS";

/// Counted each frame: the layers (or strips) rasterized in a shared chain.
pub const LAYERS_TOGETHER: &str = "shadow layers rasterized together";
/// Counted each frame: the shared chains (one per caster set and target).
pub const LAYER_CHAINS: &str = "shadow raster chains";

impl ShadowLayers {
    /// The setting a value of [`SHADOW_LAYERS_VAR`] names, `None` for any other.
    pub fn parse(value: &str) -> Option<Self> {
        match value.trim().to_ascii_lowercase().as_str() {
            "each" => Some(ShadowLayers::Each),
            "together" => Some(ShadowLayers::Together),
            _ => None,
        }
    }

    /// What [`SHADOW_LAYERS_VAR`] asks for; unset, the default. A value it
    /// does not know is an error naming the variable and the value.
    pub fn from_env() -> Result<Self, String> {
        crate::setting::from_env(SHADOW_LAYERS_VAR, Self::parse, "`each` or `together`")
    }
}

/// The renderer's [`ShadowLayers`]: as set, else the environment's (an
/// unknown value there counts as the default).
pub fn shadow_layers(renderer: &Renderer) -> ShadowLayers {
    renderer.setting(0, || ShadowLayers::from_env().unwrap_or_default())
}

/// Set the renderer's [`ShadowLayers`] (for shadow recipes made from now on).
pub fn set_shadow_layers(renderer: &Renderer, layers: ShadowLayers) {
    renderer.set_setting(0, layers);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_variable_names_each_or_together() {
        assert_eq!(ShadowLayers::parse("each"), Some(ShadowLayers::Each));
        assert_eq!(
            ShadowLayers::parse(" Together "),
            Some(ShadowLayers::Together)
        );
        assert_eq!(ShadowLayers::parse("both"), None);
        assert_eq!(ShadowLayers::default(), ShadowLayers::Together);
    }
}

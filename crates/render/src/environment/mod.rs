//! The environment around a scene: what is seen where no geometry is, and
//! the light it sends. `Sky` fills the G-buffer's empty depth with a
//! procedural sky (or an environment); `Fog` veils what is far or low;
//! [`Environment`] is a prefiltered cube for image-based light, which
//! `Reflection` reads; `EnvironmentProbe` makes one from the scene itself
//! ([`probe`]); `SSR` traces reflections in screen space.

pub mod environment_map;
pub mod fog;
pub(crate) mod fog_key;
mod pass;
mod prefilter;
pub(crate) mod prefilter_key;
pub mod probe;
pub mod reflection;
pub(crate) mod reflection_key;
pub mod sky;
pub(crate) mod sky_key;
mod source;
pub mod ssr;

pub use environment_map::{Environment, PROBE_RENDERED, PROBE_REUSED};
pub use fog::{Fog, FogSettings};
pub use pass::{FOG_AND_SKY, ImageKind, ImagePass};
pub use probe::{
    ProbeError, ProbeLighting, ProbeLights, ProbeScene, ProbeSettings, ProbeShadow, ProbeUpdate,
    ProbeVolume,
};
pub use reflection::{BOTH_IN_ONE_PASS as REFLECTION_BOTH_IN_ONE_PASS, Reflection, ReflectionMode};
pub use sky::Sky;
pub use source::{
    EnvironmentError, EnvironmentMaps, EnvironmentQuality, EnvironmentSource, EquirectImage,
    SkySettings,
};
pub use ssr::{HIZ_DISPATCHES as SSR_HIZ_DISPATCHES, Ssr, SsrSettings, TRACE_TEMPORAL};

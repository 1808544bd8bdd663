//! The environment around a scene (category "Environment"): `Sky`, `Fog`,
//! `Environment (File)`, `Environment (Sky)`, `EnvironmentProbe`, `Reflection`, `SSR`.

#[allow(clippy::module_inception)]
pub mod environment;
pub mod environment_probe;
pub mod fog;
pub mod reflection;
pub mod sky;
pub mod ssr;
#[cfg(test)]
mod tests;

use spreadlight_graph::Registry;

pub const CATEGORY: &str = "Environment";

pub fn register(r: &mut Registry) {
    sky::register(r);
    fog::register(r);
    environment::register(r);
    environment_probe::register(r);
    reflection::register(r);
    ssr::register(r);
}

//! Spreadlight's node library. Each family lives in its own module, named
//! for what its nodes do, and registers its node types in its `register`
//! function; [`registry`] gathers the families.
//!
//! To find a node from its name: `Add (Value)` is in `value.rs`,
//! `LinearSpread` in `spreads.rs`, `Translate` in `transform.rs`, `Camera` in
//! `camera.rs`, `LFO` in `animation.rs`, IOBoxes, `Probe` and `Switch` in `io.rs`,
//! `Sphere` in `geometry/primitives.rs`, `glTF` in `geometry/gltf.rs`,
//! `DeferredBase`, `MRE` and `GBufferView` in `deferred/`, `Output` in `output.rs`,
//! `FileTexture` and `FileTexture (Array)` in `texture/`, the `AddLight`s, light
//! buffers, `ShadowMap`s, `CookTorrance` and `CompositeLight` in `lighting/`, `Sky` and
//! `Fog` in `environment/`, `Tonemap`, `EyeAdaptation` and `FXAA` in `post/`, the material nodes
//! in `material/`, `Perspective (Transform)` in `transform.rs`, `BenchLights` in `bench.rs`.

use spreadlight_graph::Registry;

pub mod animation;
pub mod bench;
pub mod camera;
pub mod deferred;
pub mod environment;
pub mod geometry;
pub mod gpu;
pub mod io;
pub mod lighting;
pub mod material;
pub mod output;
pub mod particles;
pub mod post;
pub mod spreads;
pub mod texture;
pub mod transform;
pub mod value;
pub mod vector;

#[cfg(test)]
mod testing;

/// Every node type this build knows.
pub fn registry() -> Registry {
    let mut r = Registry::new();
    value::register(&mut r);
    vector::register(&mut r);
    spreads::register(&mut r);
    animation::register(&mut r);
    transform::register(&mut r);
    camera::register(&mut r);
    io::register(&mut r);
    geometry::register(&mut r);
    deferred::register(&mut r);
    output::register(&mut r);
    texture::register(&mut r);
    lighting::register(&mut r);
    environment::register(&mut r);
    material::register(&mut r);
    post::register(&mut r);
    bench::register(&mut r);
    particles::register(&mut r);
    r
}

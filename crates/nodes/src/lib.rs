//! Spreadlight's node library. Each family lives in its own module, named
//! for what its nodes do, and registers its node types in its `register`
//! function; [`registry`] gathers the families.
//!
//! To find a node from its name: `Add (Value)` is in `value.rs`,
//! `LinearSpread` in `spreads.rs`, `Translate` in `transform.rs`, `Camera` in
//! `camera.rs`, `LFO` in `animation.rs`, IOBoxes, `Probe` and `Switch` in `io.rs`,
//! `Sphere` in `geometry/primitives.rs`, `glTF` in `geometry/gltf.rs`,
//! `DeferredBase`, `MRE` and `GBufferView` in `deferred/`, `Output` in `output.rs`,
//! `FileTexture` and `FileTexture (Array)` in `texture/`, `VideoFile` in `media/`, the `AddLight`s, light
//! buffers, `ShadowMap`s, `CookTorrance` and `CompositeLight` in `lighting/`, `Sky` and
//! `Fog` in `environment/`, `Tonemap`, `EyeAdaptation` and `FXAA` in `post/`, the material nodes
//! in `material/`, `Perspective (Transform)` in `transform.rs`, `BenchLights` in `bench.rs`;
//! shader nodes (`Blur (Shader)`, files in `shaders/nodes/`) in `shader_nodes/`.
//!
//! The core library vvvv patchers reach for: spread operations (`GetSlice`,
//! `Queue`, `Stallone`, bin sizes, ...) in `spreads/`, comparisons and boolean
//! logic in `logic.rs`, `Counter`, `FlipFlop`, `TogEdge` and friends in
//! `logic/signals.rs`, `Damper`, `LinearFilter`, `Oscillator`, `Decay` in
//! `filters.rs`, easing and `Keyframes`, Perlin noise and `Time` in
//! `animation/`, colour in `color.rs`, strings in `strings/`, `Expr` in
//! `expr/`, more value and vector maths in `value/` and `vector/`, `Mouse`,
//! `Keyboard` and `WindowSize` (over the host's [`input::HostInput`]) in
//! `input/`, OSC in `osc.rs`, sound and MIDI (`AudioFile`, `Spectrum`, `MidiIn`, ...) in
//! `media/`. Variants per slice type come from `typed.rs`.
//! `docs.rs` turns the registry into `spreadlight nodes --help NAME` and
//! `docs/nodes.md`.

use spreadlight_graph::Registry;

#[macro_use]
mod typed;

pub mod animation;
pub mod bench;
pub mod camera;
pub mod color;
pub mod deferred;
pub mod docs;
pub mod environment;
pub mod expr;
pub mod filters;
pub mod geometry;
pub mod gpu;
pub mod help;
pub mod input;
pub mod io;
pub mod lighting;
pub mod logic;
pub mod material;
pub mod media;
pub mod osc;
pub mod output;
pub mod particles;
pub mod post;
pub mod resolution;
pub mod shader_nodes;
pub mod spreads;
pub mod strings;
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
    logic::register(&mut r);
    filters::register(&mut r);
    color::register(&mut r);
    strings::register(&mut r);
    input::register(&mut r);
    osc::register(&mut r);
    expr::register(&mut r);
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
    media::register(&mut r);
    post::register(&mut r);
    bench::register(&mut r);
    shader_nodes::register(&mut r);
    // The IOBoxes that make a subpatch's pins (spreadlight_graph::subpatch).
    spreadlight_graph::subpatch::register(&mut r);
    particles::register(&mut r);
    r
}

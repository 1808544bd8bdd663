//! Emeshe's forward part (category "DeferredBase"): `DeferredBase` draws
//! instanced meshes into a layer, `MRE` writes layers into the G-buffer,
//! `GBufferView` shows one of its channels.

pub mod deferred_base;
pub mod gbuffer_view;
pub mod group;
pub mod mre;
pub mod triplanar;

use spreadlight_graph::Registry;

pub const CATEGORY: &str = "DeferredBase";

pub fn register(r: &mut Registry) {
    deferred_base::register(r);
    group::register(r);
    mre::register(r);
    gbuffer_view::register(r);
    triplanar::register(r);
}

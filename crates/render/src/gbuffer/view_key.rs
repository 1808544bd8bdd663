//! The G-buffer channel a GBufferView shows, [`Channel`], which is also
//! `gbuffer/view.wgsl`'s permutation: one switch per channel. It declares
//! its shader file (`shader_file!`), so no table below the effects names
//! it; `gbuffer/view.rs` re-exports it.

use crate::shaders::permutation::Permutation;

/// A G-buffer channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    Albedo,
    Normals,
    Velocity,
    Uv,
    Depth,
    MaterialId,
    ObjectId,
}

impl Channel {
    pub const ALL: [Channel; 7] = [
        Channel::Albedo,
        Channel::Normals,
        Channel::Velocity,
        Channel::Uv,
        Channel::Depth,
        Channel::MaterialId,
        Channel::ObjectId,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Channel::Albedo => "Albedo",
            Channel::Normals => "Normals",
            Channel::Velocity => "Velocity",
            Channel::Uv => "UV",
            Channel::Depth => "Depth",
            Channel::MaterialId => "Material ID",
            Channel::ObjectId => "Object ID",
        }
    }

    fn feature(self) -> &'static str {
        match self {
            Channel::Albedo => "ALBEDO",
            Channel::Normals => "NORMALS",
            Channel::Velocity => "VELOCITY",
            Channel::Uv => "UV",
            Channel::Depth => "DEPTH",
            Channel::MaterialId => "MATERIAL_ID",
            Channel::ObjectId => "OBJECT_ID",
        }
    }
}

/// Every view shows one channel: the string rule's empty choice (no
/// channel at all) was never built, and is no permutation.
impl Permutation for Channel {
    crate::shader_file!("gbuffer/view.wgsl");
    const FEATURES: &'static [&'static str] = &[
        "ALBEDO",
        "NORMALS",
        "VELOCITY",
        "UV",
        "DEPTH",
        "MATERIAL_ID",
        "OBJECT_ID",
    ];

    fn features(self) -> impl Iterator<Item = &'static str> {
        std::iter::once(self.feature())
    }

    fn all() -> Vec<Self> {
        Channel::ALL.to_vec()
    }
}

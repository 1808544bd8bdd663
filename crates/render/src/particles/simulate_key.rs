//! The typed key of the particle simulation step, [`SimulateKey`] (`particles/simulate.wgsl`). It
//! declares its shader file (`shader_file!`), so no table below the effects names it;
//! `particles/simulate.rs` re-exports it.

crate::flag_key! {
    /// `particles/simulate.wgsl`.
    pub struct SimulateKey("particles/simulate.wgsl") {
        /// The force field is a texture (else analytic).
        field_texture: "FIELD_TEXTURE",
        /// Particles are born on a mesh's surface.
        mesh_emitter: "MESH_EMITTER",
        /// Particles bounce off the G-buffer's depth.
        depth_collision: "DEPTH_COLLISION",
    }
}

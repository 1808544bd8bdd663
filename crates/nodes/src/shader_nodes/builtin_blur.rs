//! `BlurBuiltin`: the `Blur (Shader)` example as a built-in pass, for
//! benchmarking the shader node against hand-written Rust
//! (`spreadlight bench patches/bench-builtin-blur.ron` beside `bench-shader-blur.ron`).

use spreadlight_graph::{NodeDef, Registry};
use spreadlight_render::shader_nodes::builtin_blur::BuiltinBlur;

use crate::post::{set_texture, texture, texture_input, texture_output};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "BlurBuiltin",
            "Post",
            "The separable blur of Blur (Shader) (shaders/nodes/blur.wgsl) as a built-in pass: the baseline the \
             shader node is benchmarked against. Radius 0..32 pixels.",
        )
        .with_pins(|p| {
            let texture_in = texture_input(p, "Texture");
            let radius = p.input("Radius", 4.0f32);
            let out = texture_output(p, "Texture");
            move |cx| {
                let source = texture(cx, texture_in)?;
                let radius = cx.first(radius, 4.0)?;
                let blur = BuiltinBlur::new(Some(cx.node_id.0), source, radius);
                set_texture(cx, out, blur.texture());
                Ok(())
            }
        }),
    );
}

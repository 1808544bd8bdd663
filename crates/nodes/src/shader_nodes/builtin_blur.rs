//! `BlurBuiltin`: the `Blur (Shader)` example as a built-in pass, for
//! benchmarking the shader node against hand-written Rust
//! (`spreadlight bench patches/bench-builtin-blur.ron` beside `bench-shader-blur.ron`).

use std::sync::Arc;

use spreadlight_graph::{NodeDef, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::shader_nodes::builtin_blur::BuiltinBlur;

use crate::gpu::{resource_spread, resources};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "BlurBuiltin",
            "Post",
            "The separable blur of Blur (Shader) (shaders/nodes/blur.wgsl) as a built-in pass: the baseline the \
             shader node is benchmarked against. Radius 0..32 pixels.",
        )
        .input_spread(
            "Texture",
            PinType::Resource(ResourceKind::Texture),
            Spread::Resource(ResourceKind::Texture, vec![]),
        )
        .input("Radius", 4.0f32)
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let source = resources::<TextureRef>(cx, 0)?
                .into_iter()
                .next()
                .ok_or_else(|| cx.input_error(0, "no texture connected"))?;
            let radius = cx.slices::<f32>(1)?.first().copied().unwrap_or(4.0);
            let blur = BuiltinBlur::new(Some(cx.node_id.0), (*source).clone(), radius);
            cx.set_output(
                0,
                resource_spread(ResourceKind::Texture, vec![Arc::new(blur.texture())]),
            );
            Ok(())
        }),
    );
}

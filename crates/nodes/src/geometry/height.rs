//! The texture pin of `Displace` and `Extrude`: heights come from a texture
//! that exists before the frame (a `FileTexture`), because GPU geometry runs
//! as its node evaluates, before any frame renders.

use std::sync::Arc;

use spreadlight_graph::{EvalContext, In, NodeError, Res};
use spreadlight_render::TextureRef;

/// The first texture on `pin`, if any; one rendered by the frame (a
/// post-processing output, say) is an error that says so.
pub(crate) fn height_texture(
    cx: &EvalContext<'_>,
    pin: In<Res<TextureRef>>,
) -> Result<Option<Arc<TextureRef>>, NodeError> {
    let Some(texture) = cx.first_resource(pin)? else {
        return Ok(None);
    };
    if texture.recipe.static_texture().is_none() {
        return Err(cx.error(
            pin,
            format!(
                "`{}` is rendered by the frame; geometry runs before the frame and needs a texture that exists \
                 already (a FileTexture)",
                texture.name
            ),
        ));
    }
    Ok(Some(texture))
}

/// The texture's identity (its recipe's address), for slice signatures.
pub(crate) fn identity(texture: Option<&Arc<TextureRef>>) -> usize {
    texture.map_or(0, |t| Arc::as_ptr(&t.recipe) as *const u8 as usize)
}

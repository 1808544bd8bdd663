//! `CompositeLight`: the lit HDR image from CookTorrance's components, one
//! diffuse/specular pair per light type (join them with `Group (Texture)`).

use spreadlight_graph::{Color, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{
    CompositeInputs, CompositeLight, LightComponents, MAX_COMPONENTS,
};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::{renderer, resource_spread, resources};

pub fn register(r: &mut Registry) {
    let texture = || Spread::Resource(ResourceKind::Texture, vec![]);
    r.add(
        NodeDef::new(
            "CompositeLight",
            super::CATEGORY,
            "Adds CookTorrance's diffuse, specular and SSS (slice i of each: one light type; up to four; SSS \
             may be empty) and an \
             ambient term (Ambient x albedo), plus each material's Emission from the Material World, into one HDR image. AO (optional, visibility \
             in R) darkens the ambient term, weighted by each material's AmbientOcclusion strength when a \
             Material World has that feature. GI (optional): indirect diffuse light (SSGI, an environment's \
             diffuse light), times albedo (not darkened by AO: SSGI occludes the environment light itself). Reflection (optional): specular reflection (Reflection, \
             SSR), times each material's Reflection strength; not rendered at all when no material reflects.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Diffuse", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("Specular", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("SSS", PinType::Resource(ResourceKind::Texture), texture())
        .input("Ambient", Color::rgba(0.0, 0.0, 0.0, 1.0))
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input_spread("AO", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("GI", PinType::Resource(ResourceKind::Texture), texture())
        .input_spread("Reflection", PinType::Resource(ResourceKind::Texture), texture())
        .output_typed("Texture", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let gbuffer = resources::<GBuffer>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            let diffuse = resources::<TextureRef>(cx, 1)?;
            let specular = resources::<TextureRef>(cx, 2)?;
            if diffuse.is_empty() || diffuse.len() != specular.len() || diffuse.len() > MAX_COMPONENTS {
                return Err(NodeError::Other(format!(
                    "Diffuse and Specular need the same number of slices, 1 to {MAX_COMPONENTS} (got {} and {})",
                    diffuse.len(),
                    specular.len()
                )));
            }
            super::require_finite(cx, 4..5)?;
            let ambient: Color = cx.slices::<Color>(4)?.first().copied().unwrap_or(Color::BLACK);
            let materials = resources::<MaterialWorld>(cx, 5)?.into_iter().next();
            let sss = resources::<TextureRef>(cx, 3)?;
            if !sss.is_empty() && sss.len() != diffuse.len() {
                return Err(cx.input_error(3, format!("needs one slice per light type ({}) or none", diffuse.len())));
            }
            let components = diffuse
                .iter()
                .zip(&specular)
                .enumerate()
                .map(|(k, (d, s))| LightComponents {
                    diffuse: (**d).clone(),
                    specular: (**s).clone(),
                    sss: sss.get(k).map(|t| (**t).clone()),
                })
                .collect();
            let occlusion = resources::<TextureRef>(cx, 6)?.into_iter().next().map(|t| (*t).clone());
            let gi = resources::<TextureRef>(cx, 7)?.into_iter().next().map(|t| (*t).clone());
            let reflection = resources::<TextureRef>(cx, 8)?.into_iter().next().map(|t| (*t).clone());
            let inputs =
                CompositeInputs { components, ambient: [ambient.r, ambient.g, ambient.b], materials, occlusion, gi, reflection };
            let composite = CompositeLight::new(&renderer, Some(cx.node_id.0), gbuffer, inputs)
                .map_err(|e| NodeError::Other(e.to_string()))?;
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(composite.texture())]));
            Ok(())
        }),
    );
}

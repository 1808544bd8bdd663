//! `CompositeLight`: the lit HDR image from CookTorrance's components, one
//! diffuse/specular pair per light type (join them with `Group (Texture)`).

use std::sync::Arc;

use spreadlight_graph::{Color, NodeDef, NodeError, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::lighting::{
    CompositeInputs, CompositeLight, LightComponents, MAX_COMPONENTS,
};
use spreadlight_render::material::MaterialWorld;

use crate::gpu::renderer;
use crate::post::{gbuffer_input, optional_texture, set_texture, texture_input, texture_output};

pub fn register(r: &mut Registry) {
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
        .with_pins(|p| {
            let g_buffer = gbuffer_input(p);
            let diffuse = texture_input(p, "Diffuse");
            let specular = texture_input(p, "Specular");
            let sss = texture_input(p, "SSS");
            let ambient = p.input("Ambient", Color::rgba(0.0, 0.0, 0.0, 1.0));
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let ao = texture_input(p, "AO");
            let gi = texture_input(p, "GI");
            let reflection = texture_input(p, "Reflection");
            let out = texture_output(p, "Texture");
            move |cx| {
                let renderer = renderer(cx)?;
                let gbuffer = cx.first_resource(g_buffer)?.ok_or_else(|| cx.error(g_buffer, "no G-buffer connected"))?;
                let diffuse = cx.resources(diffuse)?;
                let specular = cx.resources(specular)?;
                if diffuse.is_empty() || diffuse.len() != specular.len() || diffuse.len() > MAX_COMPONENTS {
                    return Err(NodeError::Other(format!(
                        "Diffuse and Specular need the same number of slices, 1 to {MAX_COMPONENTS} (got {} and {})",
                        diffuse.len(),
                        specular.len()
                    )));
                }
                super::require_finite(cx, ambient)?;
                let ambient: Color = cx.first(ambient, Color::BLACK)?;
                let materials = cx.first_resource(material_world)?;
                let sss_slices: Vec<Arc<TextureRef>> = cx.resources(sss)?;
                if !sss_slices.is_empty() && sss_slices.len() != diffuse.len() {
                    return Err(cx.error(sss, format!("needs one slice per light type ({}) or none", diffuse.len())));
                }
                let components = diffuse
                    .iter()
                    .zip(&specular)
                    .enumerate()
                    .map(|(k, (d, s))| LightComponents {
                        diffuse: (**d).clone(),
                        specular: (**s).clone(),
                        sss: sss_slices.get(k).map(|t| (**t).clone()),
                    })
                    .collect();
                let occlusion = optional_texture(cx, ao)?;
                let gi = optional_texture(cx, gi)?;
                let reflection = optional_texture(cx, reflection)?;
                let inputs =
                    CompositeInputs { components, ambient: [ambient.r, ambient.g, ambient.b], materials, occlusion, gi, reflection };
                let composite = CompositeLight::new(&renderer, Some(cx.node_id.0), gbuffer, inputs)
                    .map_err(|e| NodeError::Other(e.to_string()))?;
                set_texture(cx, out, composite.texture());
                Ok(())
            }
        }),
    );
}

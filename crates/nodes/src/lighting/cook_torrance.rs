//! `CookTorrance`: point lights on the G-buffer, in compute, clustered or
//! naive (the reference). Roughness and metallic are spreads indexed by the
//! G-buffer's material id (until the MaterialBuffer lands).

use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{NodeDef, NodeError, Registry, ResourceKind};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, Surfaces};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::shadows::ShadowMaps;

use crate::gpu::renderer;

const LIGHT_LOOP_OPTIONS: &[&str] = &["Auto", "Clustered", "Naive", "Tiled", "Per Pixel"];

/// The Light Loop pin's options as values (CookTorrance, light shader nodes, Transparency).
pub static LIGHT_LOOPS: spreadlight_graph::Choices<LightLoop> = spreadlight_graph::Choices::new(
    "Light Loop",
    LIGHT_LOOP_OPTIONS,
    &[
        LightLoop::Auto,
        LightLoop::Clustered,
        LightLoop::Naive,
        LightLoop::Tiled,
        LightLoop::PerPixel,
    ],
);

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "CookTorrance",
            super::CATEGORY,
            "Shades the G-buffer with one light buffer (point, spot or sun: one permutation per type): GGX, height-correlated Smith, Schlick Fresnel. Clustered \
             loops over the lights of each pixel's froxel, shared by 16x16 blocks; Tiled does too over depth-bounded tiles (only the depth slices \
             and depth bins a tile's pixels occupy); Per Pixel walks each pixel's froxel list alone (no shared memory); Naive loops over all (the reference). \
             Auto (the default) is Naive for 16 lights or fewer, where assigning them to froxels costs more than it saves, and beyond that \
             Clustered on a GPU, Per Pixel on a CPU adapter (lavapipe). Energy Compensation \
             adds multiple scattering. Roughness and Metallic slice i apply to material id i (wrapping), unless a Material World is \
             connected: then each material's CookTorrance feature decides. \
             Diffuse includes albedo. SSS carries a wrap-lighting subsurface term when some material has \
             FakeSSS with a colour and a strength above 0, and is empty otherwise. Shadows: the ShadowMap node of the same light type; each light whose \
             AddLight has a Shadow Slice is shadowed by that slice. Light Cutoff (0: off, the exact image) trades accuracy for \
             speed with many lights: each light reaches only as far as its illuminance (intensity over distance squared, its \
             brightest channel) stays above the cutoff, fading to 0 there, so fewer lights reach each pixel. Light Merge (0: off, the exact \
             image) is a distance: point lights are binned into cubes half of it across, and a pixel at least that far from a cube's \
             centroid shades the cube's lights as one (their sum at their centroid), a nearer pixel one by one; lights with a shadow stay \
             apart, and the Naive and Tiled walks do not merge.",
        )
        .with_pins(|p| {
            // Not post's pin helpers: Transparency (post) imports this file's LIGHT_LOOPS.
            let g_buffer = p.input_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer);
            let lights_in = p.input_resource::<LightBuffer>("Lights", ResourceKind::LightWorld);
            let roughness = p.input("Roughness", 0.5f32);
            let metallic = p.input("Metallic", 0.0f32);
            let light_loop = p.input_choice("Light Loop", &LIGHT_LOOPS, LightLoop::Auto);
            let energy = p.input("Energy Compensation", true);
            let cutoff_pin = p.input("Light Cutoff", 0.0f32);
            let merge_pin = p.input("Light Merge", 0.0f32);
            let material_world = p.input_resource::<MaterialWorld>("Material World", ResourceKind::MaterialWorld);
            let shadows_in = p.input_resource::<ShadowMaps>("Shadows", ResourceKind::Shadows);
            let texture_output = |p: &mut spreadlight_graph::Pins<'_>, name: &'static str| {
                p.output_resource::<TextureRef>(name, ResourceKind::Texture)
            };
            let diffuse = texture_output(p, "Diffuse");
            let specular = texture_output(p, "Specular");
            let sss_out = texture_output(p, "SSS");
            move |cx| {
                // Checked first: a bad value is the node's error whatever else is connected.
                let cutoff = cx.first(cutoff_pin, 0.0f32)?;
                if !(cutoff.is_finite() && cutoff >= 0.0) {
                    return Err(cx.error(cutoff_pin, format!("is {cutoff}: a light cutoff is an illuminance of 0 (off) or more")));
                }
                let merge = cx.first(merge_pin, 0.0f32)?;
                if !(merge.is_finite() && merge >= 0.0) {
                    return Err(cx.error(merge_pin, format!("is {merge}: a light merge is a distance of 0 (off) or more")));
                }
                let renderer = renderer(cx)?;
                let gbuffer = cx.first_resource(g_buffer)?.ok_or_else(|| cx.error(g_buffer, "no G-buffer connected"))?;
                let lights = match cx.first_resource(lights_in)? {
                    Some(l) => l,
                    None => LightBuffer::points(&renderer, &[]),
                };
                let (roughness, metallic) = (cx.get(roughness)?, cx.get(metallic)?);
                let n = slice_count([roughness.len(), metallic.len()]);
                let surfaces: Vec<(f32, f32)> = cycled(roughness, n).zip(cycled(metallic, n)).map(|(r, m)| (*r, *m)).collect();
                if let Some(slice) = surfaces.iter().position(|(r, m)| !r.is_finite() || !m.is_finite()) {
                    return Err(NodeError::Other(format!("Roughness or Metallic slice {slice} is NaN or infinite")));
                }
                let mode = cx.choice(light_loop)?;
                let energy = cx.first(energy, true)?;
                let surfaces = match cx.first_resource(material_world)? {
                    Some(world) => Surfaces::Materials(world),
                    None => Surfaces::PerMaterialId(surfaces),
                };
                let shadows = cx.first_resource(shadows_in)?;
                if let Some(s) = &shadows
                    && s.kind != lights.kind
                {
                    return Err(cx.error(shadows_in, format!("holds shadows of {:?} lights, but Lights holds {:?} lights", s.kind, lights.kind)));
                }
                let recipe = CookTorrance::with_shadows(&renderer, Some(cx.node_id.0), gbuffer, lights, mode, energy, surfaces, shadows);
                let recipe = CookTorrance::with_light_cutoff(recipe, cutoff);
                let recipe = CookTorrance::with_light_merge(recipe, &renderer, merge);
                cx.put_resources(diffuse, vec![std::sync::Arc::new(recipe.diffuse_texture())]);
                cx.put_resources(specular, vec![std::sync::Arc::new(recipe.specular_texture())]);
                // Only when some material scatters (FakeSSS above 0): otherwise there is no subsurface term to pass on.
                let sss: Vec<std::sync::Arc<TextureRef>> = recipe.sss_texture().map(std::sync::Arc::new).into_iter().collect();
                cx.put_resources(sss_out, sss);
                Ok(())
            }
        }),
    );
}

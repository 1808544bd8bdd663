//! `CookTorrance`: point lights on the G-buffer, in compute, clustered or
//! naive (the reference). Roughness and metallic are spreads indexed by the
//! G-buffer's material id (until the MaterialBuffer lands).

use spreadlight_graph::spread::{cycled, slice_count};
use spreadlight_graph::{EnumDef, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread};
use spreadlight_render::TextureRef;
use spreadlight_render::gbuffer::GBuffer;
use spreadlight_render::lighting::{CookTorrance, LightBuffer, LightLoop, Surfaces};
use spreadlight_render::material::MaterialWorld;
use spreadlight_render::shadows::ShadowMaps;

use crate::gpu::{renderer, resource_spread, resources};

const LIGHT_LOOP_OPTIONS: &[&str] = &["Auto", "Clustered", "Naive", "Tiled", "Per Pixel"];

pub static LIGHT_LOOP: EnumDef = EnumDef {
    name: "Light Loop",
    options: LIGHT_LOOP_OPTIONS,
};

/// The Light Loop pin's options as values, for nodes with typed pins.
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
             AddLight has a Shadow Slice is shadowed by that slice.",
        )
        .input_spread("G-Buffer", PinType::Resource(ResourceKind::GBuffer), Spread::Resource(ResourceKind::GBuffer, vec![]))
        .input_spread("Lights", PinType::Resource(ResourceKind::LightWorld), Spread::Resource(ResourceKind::LightWorld, vec![]))
        .input("Roughness", 0.5f32)
        .input("Metallic", 0.0f32)
        .input_enum("Light Loop", &LIGHT_LOOP, "Auto")
        .input("Energy Compensation", true)
        .input_spread(
            "Material World",
            PinType::Resource(ResourceKind::MaterialWorld),
            Spread::Resource(ResourceKind::MaterialWorld, vec![]),
        )
        .input_spread("Shadows", PinType::Resource(ResourceKind::Shadows), Spread::Resource(ResourceKind::Shadows, vec![]))
        .output_typed("Diffuse", PinType::Resource(ResourceKind::Texture))
        .output_typed("Specular", PinType::Resource(ResourceKind::Texture))
        .output_typed("SSS", PinType::Resource(ResourceKind::Texture))
        .evaluate(|cx| {
            let renderer = renderer(cx)?;
            let gbuffer = resources::<GBuffer>(cx, 0)?.into_iter().next().ok_or_else(|| cx.input_error(0, "no G-buffer connected"))?;
            let lights = match resources::<LightBuffer>(cx, 1)?.into_iter().next() {
                Some(l) => l,
                None => LightBuffer::points(&renderer, &[]),
            };
            let (roughness, metallic) = (cx.slices::<f32>(2)?, cx.slices::<f32>(3)?);
            let n = slice_count([roughness.len(), metallic.len()]);
            let surfaces: Vec<(f32, f32)> = cycled(roughness, n).zip(cycled(metallic, n)).map(|(r, m)| (*r, *m)).collect();
            if let Some(slice) = surfaces.iter().position(|(r, m)| !r.is_finite() || !m.is_finite()) {
                return Err(NodeError::Other(format!("Roughness or Metallic slice {slice} is NaN or infinite")));
            }
            let mode = match cx.enum_slices(4)?.first().map(String::as_str) {
                Some("Naive") => LightLoop::Naive,
                Some("Clustered") => LightLoop::Clustered,
                Some("Tiled") => LightLoop::Tiled,
                Some("Per Pixel") => LightLoop::PerPixel,
                _ => LightLoop::Auto,
            };
            let energy = cx.slices::<bool>(5)?.first().copied().unwrap_or(true);
            let surfaces = match resources::<MaterialWorld>(cx, 6)?.into_iter().next() {
                Some(world) => Surfaces::Materials(world),
                None => Surfaces::PerMaterialId(surfaces),
            };
            let shadows = resources::<ShadowMaps>(cx, 7)?.into_iter().next();
            if let Some(s) = &shadows
                && s.kind != lights.kind
            {
                return Err(cx.input_error(7, format!("holds shadows of {:?} lights, but Lights holds {:?} lights", s.kind, lights.kind)));
            }
            let recipe = CookTorrance::with_shadows(&renderer, Some(cx.node_id.0), gbuffer, lights, mode, energy, surfaces, shadows);
            cx.set_output(0, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(recipe.diffuse_texture())]));
            cx.set_output(1, resource_spread::<TextureRef>(ResourceKind::Texture, vec![std::sync::Arc::new(recipe.specular_texture())]));
            // Only when some material scatters (FakeSSS above 0): otherwise there is no subsurface term to pass on.
            let sss: Vec<std::sync::Arc<TextureRef>> = recipe.sss_texture().map(std::sync::Arc::new).into_iter().collect();
            cx.set_output(2, resource_spread::<TextureRef>(ResourceKind::Texture, sss));
            Ok(())
        }),
    );
}

//! What the glTF render tests share: the generated quad (`builder::quad`)
//! seen from a camera on +Z, where each pixel's ray meets it, and a loaded
//! file's first mesh drawn as a layer over the file's material world, on
//! its own or through Transparency over a background.

use std::sync::Arc;

use glam::{Mat4, Vec3};
use spreadlight_gltf::{GltfScene, MaterialData};
use spreadlight_render::camera::CameraInput;
use spreadlight_render::gbuffer::{DrawBatch, GBuffer, InstanceInput, Layer, LayerFeatures};
use spreadlight_render::material::{Material, MaterialWorld};
use spreadlight_render::post::{Transparency, TransparencySettings};
use spreadlight_render::{Renderer, SizeRule, TextureRef};

/// A square image of the plane z = 0 from a camera on +Z looking at the
/// origin.
pub struct QuadView {
    pub size: (u32, u32),
    pub distance: f32,
    pub fov_y: f32,
}

impl QuadView {
    pub fn camera(&self) -> CameraInput {
        let eye = Vec3::Z * self.distance;
        CameraInput {
            view: glam::camera::rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
            projection: glam::camera::rh::proj::directx::perspective(self.fov_y, 1.0, 0.1, 100.0),
        }
    }

    /// Where the ray through pixel (x, y)'s centre meets the plane z = 0.
    pub fn hit(&self, x: u32, y: u32) -> (f32, f32) {
        let half = self.distance * (self.fov_y / 2.0).tan();
        let ndc_x = (x as f32 + 0.5) / self.size.0 as f32 * 2.0 - 1.0;
        let ndc_y = 1.0 - (y as f32 + 0.5) / self.size.1 as f32 * 2.0;
        (ndc_x * half, ndc_y * half)
    }
}

/// The file's material world (glTF's default material first, as the
/// importer's users number them) and its first mesh as a layer: one
/// instance placed by `transform`, of material 1 (the file's first) and
/// `color`.
pub fn world_and_layer(
    renderer: &Renderer,
    scene: &GltfScene,
    transform: Mat4,
    color: [f32; 4],
) -> (Arc<MaterialWorld>, Arc<Layer>) {
    world_and_layer_of(renderer, scene, transform, color, |m| m)
}

/// [`world_and_layer`] with every material of the world changed by
/// `adapt` (a feature the file cannot give added, such as Reflection).
pub fn world_and_layer_of(
    renderer: &Renderer,
    scene: &GltfScene,
    transform: Mat4,
    color: [f32; 4],
    adapt: impl Fn(Material) -> Material,
) -> (Arc<MaterialWorld>, Arc<Layer>) {
    let mesh = renderer
        .meshes
        .upload(&renderer.gpu, &scene.meshes[0])
        .expect("upload");
    let materials = std::iter::once(MaterialData::default())
        .chain(scene.materials.iter().cloned())
        .map(|m| adapt(m.to_material()))
        .collect();
    let world = MaterialWorld::new(renderer, materials);
    let instance = InstanceInput {
        transform,
        previous_transform: transform,
        color,
        material_id: 1,
        object_id: 1,
    };
    let layer = Layer::new(
        Some(1),
        vec![DrawBatch {
            mesh,
            instances: vec![instance],
        }],
        LayerFeatures::default(),
        None,
    )
    .expect("layer")
    .with_materials(Some(world.clone()));
    (world, Arc::new(layer))
}

/// Transparency over `background` of the file's quad, placed by
/// `transform` and coloured by its first material's factor as the glTF
/// node does, and the G-buffer under it: nothing opaque, so its depth is
/// the far plane everywhere.
// Not every test file composites (each compiles this module on its own).
#[allow(dead_code)]
pub fn transparency_over(
    renderer: &Renderer,
    view: &QuadView,
    scene: &GltfScene,
    transform: Mat4,
    background: TextureRef,
    settings: TransparencySettings,
) -> (Arc<GBuffer>, Arc<Transparency>) {
    let g = GBuffer::new(
        renderer,
        None,
        vec![],
        view.camera(),
        None,
        SizeRule::Relative(1.0),
    );
    let color = scene.materials[0].base_color;
    let (_, layer) = world_and_layer(renderer, scene, transform, color);
    let pass = Transparency::new(renderer, None, background, g.clone(), vec![layer], settings);
    (g, pass)
}

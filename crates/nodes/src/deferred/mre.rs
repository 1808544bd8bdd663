//! `MRE`: writes layers into Emeshe's G-buffer and outputs it with the
//! camera it was seen through.

use std::sync::Mutex;

use glam::{Mat4, Vec2};
use spreadlight_graph::{
    EnumDef, EvalContext, Node, NodeDef, NodeError, PinType, Registry, ResourceKind, Spread,
};
use spreadlight_render::SizeRule;
use spreadlight_render::camera::{CameraInput, jittered};
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};

use crate::gpu::{renderer, resource_spread, resources};

pub static RASTER: EnumDef = EnumDef {
    name: "Raster",
    options: &["Auto", "Compute", "Hardware"],
};

pub fn register(r: &mut Registry) {
    r.add(
        NodeDef::new(
            "MRE",
            super::CATEGORY,
            "Groups layers and writes the G-buffer (Emeshe's layout: color + material id, view-space normals + object \
             id, velocity + UV, reversed-Z depth). Width and Height of 0 follow the renderer's output size. Raster: Compute rasterizes in compute \
             shaders with 64-bit atomics (fast where raster hardware is scarce, as on the H100), Hardware uses the \
             raster units, Auto picks Compute where the adapter supports it. \
             Only the targets something reads are rendered. Publish Depth (a name, empty: none) keeps the depth of \
             its meshes (not its particles) each frame for the next frame's `Particles` with that Collide Depth: \
             particles collide with what this G-buffer shows without a link back into their own G-buffer.",
        )
        .input_spread("Layer", PinType::Resource(ResourceKind::Layer), Spread::Resource(ResourceKind::Layer, vec![]))
        .input("View", glam::camera::rh::view::look_at_mat4(glam::Vec3::new(0.0, 0.0, 5.0), glam::Vec3::ZERO, glam::Vec3::Y))
        .input("Projection", glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_3, 16.0 / 9.0, 0.1, 100.0))
        .input("Width", 0i64)
        .input("Height", 0i64)
        .input_enum("Raster", &RASTER, "Auto")
        .input("Publish Depth", String::new())
        .output_typed("G-Buffer", PinType::Resource(ResourceKind::GBuffer))
        // Last frame's camera, for the velocity buffer.
        .remembers(1)
        .construct(Mre::default),
    );
}

/// A sub-pixel offset, in pixels of the G-buffer, that every MRE moves its
/// projection by. A host that accumulates sub-frame renders (`spreadlight
/// render --samples`) provides it and sets a new offset before each render;
/// while it is provided, MRE runs every frame (the offset changes though no pin does).
#[derive(Debug, Default)]
pub struct SubPixelOffset(Mutex<Vec2>);

impl SubPixelOffset {
    pub fn set(&self, pixels: Vec2) {
        *self.0.lock().unwrap_or_else(|e| e.into_inner()) = pixels;
    }

    pub fn get(&self) -> Vec2 {
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Keeps last frame's view-projection, for velocity.
#[derive(Default)]
struct Mre {
    previous_view_projection: Option<Mat4>,
}

impl Node for Mre {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let renderer = renderer(cx)?;
        let layers = resources::<Layer>(cx, 0)?;
        let view = *cx
            .slices::<Mat4>(1)?
            .first()
            .ok_or_else(|| cx.input_error(1, "needs a view transform"))?;
        let projection = *cx
            .slices::<Mat4>(2)?
            .first()
            .ok_or_else(|| cx.input_error(2, "needs a projection"))?;
        if !view.is_finite() || !projection.is_finite() {
            return Err(NodeError::Other(
                "the camera matrices are not finite".to_owned(),
            ));
        }
        let dimension = |pin: usize| -> Result<u32, NodeError> {
            let v = cx.slices::<i64>(pin)?.first().copied().unwrap_or(0);
            u32::try_from(v)
                .ok()
                .filter(|v| *v <= 16384)
                .ok_or_else(|| cx.input_error(pin, "must be 0 (output size) to 16384"))
        };
        let (width, height) = (dimension(3)?, dimension(4)?);
        let size = if width == 0 || height == 0 {
            SizeRule::Relative(1.0)
        } else {
            SizeRule::Absolute { width, height }
        };
        let projection = match cx.service::<SubPixelOffset>() {
            Some(offset) => {
                cx.reevaluate_next_frame();
                let (w, h) = match size {
                    SizeRule::Absolute { width, height } => (width, height),
                    _ => renderer.output_size(),
                };
                let pixels = offset.get();
                // NDC spans 2 over the target; +y is up in NDC and down in pixels.
                let ndc = Vec2::new(
                    pixels.x * 2.0 / w.max(1) as f32,
                    -pixels.y * 2.0 / h.max(1) as f32,
                );
                jittered(projection, ndc)
            }
            None => projection,
        };
        let camera = CameraInput { view, projection };
        let previous = self
            .previous_view_projection
            .replace(camera.view_projection());
        if previous.is_some_and(|p| p != camera.view_projection()) {
            // Camera velocity is last frame's motion: next frame must see it settle.
            cx.reevaluate_next_frame();
        }
        let raster = match cx.enum_slices(5)?.first().map(String::as_str) {
            Some("Compute") => RasterChoice::Compute,
            Some("Hardware") => RasterChoice::Hardware,
            _ => RasterChoice::Auto,
        };
        let publish = cx.slices::<String>(6)?.first().cloned().unwrap_or_default();
        let gbuffer = GBuffer::publishing_depth(
            &renderer,
            Some(cx.node_id.0),
            layers,
            camera,
            previous,
            size,
            raster,
            publish,
        );
        cx.set_output(0, resource_spread(ResourceKind::GBuffer, vec![gbuffer]));
        Ok(())
    }
}

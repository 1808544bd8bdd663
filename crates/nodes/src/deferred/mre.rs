//! `MRE`: writes layers into Emeshe's G-buffer and outputs it with the
//! camera it was seen through.

use std::sync::Mutex;

use glam::{Mat4, Vec2};
use spreadlight_graph::{
    Choice, Choices, EvalContext, In, Node, NodeDef, NodeError, Out, Registry, Res, ResourceKind,
};
use spreadlight_render::SizeRule;
use spreadlight_render::camera::{CameraInput, jittered};
use spreadlight_render::gbuffer::{GBuffer, Layer, RasterChoice};

use crate::gpu::renderer;

pub static RASTER: Choices<RasterChoice> = Choices::new(
    "Raster",
    &["Auto", "Compute", "Hardware"],
    &[
        RasterChoice::Auto,
        RasterChoice::Compute,
        RasterChoice::Hardware,
    ],
);

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
        // Last frame's camera, for the velocity buffer.
        .remembers(1)
        .with_pins_node(|p| {
            let pins = MrePins {
                layer: p.input_resource::<Layer>("Layer", ResourceKind::Layer),
                view: p.input(
                    "View",
                    glam::camera::rh::view::look_at_mat4(glam::Vec3::new(0.0, 0.0, 5.0), glam::Vec3::ZERO, glam::Vec3::Y),
                ),
                projection: p.input(
                    "Projection",
                    glam::camera::rh::proj::directx::perspective(std::f32::consts::FRAC_PI_3, 16.0 / 9.0, 0.1, 100.0),
                ),
                width: p.input("Width", 0i64),
                height: p.input("Height", 0i64),
                raster: p.input_choice("Raster", &RASTER, RasterChoice::Auto),
                publish: p.input("Publish Depth", String::new()),
                out: p.output_resource::<GBuffer>("G-Buffer", ResourceKind::GBuffer),
            };
            move || Mre {
                pins,
                previous_view_projection: None,
            }
        }),
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

#[derive(Clone, Copy)]
struct MrePins {
    layer: In<Res<Layer>>,
    view: In<Mat4>,
    projection: In<Mat4>,
    width: In<i64>,
    height: In<i64>,
    raster: In<Choice<RasterChoice>>,
    publish: In<String>,
    out: Out<Res<GBuffer>>,
}

/// Keeps last frame's view-projection, for velocity.
struct Mre {
    pins: MrePins,
    previous_view_projection: Option<Mat4>,
}

impl Node for Mre {
    fn evaluate(&mut self, cx: &mut EvalContext<'_>) -> Result<(), NodeError> {
        let pins = self.pins;
        let renderer = renderer(cx)?;
        let layers = cx.resources(pins.layer)?;
        let view = *cx
            .get(pins.view)?
            .first()
            .ok_or_else(|| cx.error(pins.view, "needs a view transform"))?;
        let projection = *cx
            .get(pins.projection)?
            .first()
            .ok_or_else(|| cx.error(pins.projection, "needs a projection"))?;
        if !view.is_finite() || !projection.is_finite() {
            return Err(NodeError::Other(
                "the camera matrices are not finite".to_owned(),
            ));
        }
        let dimension = |pin: In<i64>| -> Result<u32, NodeError> {
            let v = cx.first(pin, 0)?;
            u32::try_from(v)
                .ok()
                .filter(|v| *v <= 16384)
                .ok_or_else(|| cx.error(pin, "must be 0 (output size) to 16384"))
        };
        let (width, height) = (dimension(pins.width)?, dimension(pins.height)?);
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
        let raster = cx.choice(pins.raster)?;
        let publish = cx.get(pins.publish)?.first().cloned().unwrap_or_default();
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
        cx.put_resources(pins.out, vec![gbuffer]);
        Ok(())
    }
}

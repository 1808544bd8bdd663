//! The camera as passes see it (Emeshe's CAM_* semantics), with reversed-Z.
//!
//! Camera nodes produce the conventional 0..1 depth projection; the renderer
//! flips it to reversed-Z (1 at the near plane, 0 far), which spreads float
//! depth precision evenly over distance.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3, Vec4};

/// Matches `Camera` in shaders/lib/camera.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GpuCamera {
    pub view: [[f32; 4]; 4],
    pub view_inverse: [[f32; 4]; 4],
    pub projection: [[f32; 4]; 4],
    pub projection_inverse: [[f32; 4]; 4],
    pub view_projection: [[f32; 4]; 4],
    pub previous_view_projection: [[f32; 4]; 4],
    pub position: [f32; 4],
    pub size: [f32; 4],
}

/// z' = w - z: maps depth 0..1 (near..far) to 1..0.
pub fn reverse_z(projection: Mat4) -> Mat4 {
    let flip = Mat4::from_cols(
        Vec4::X,
        Vec4::Y,
        Vec4::new(0.0, 0.0, -1.0, 0.0),
        Vec4::new(0.0, 0.0, 1.0, 1.0),
    );
    flip * projection
}

/// A camera: view and (conventional, 0..1 depth) projection, plus last frame's
/// view-projection for velocity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraInput {
    pub view: Mat4,
    pub projection: Mat4,
}

impl CameraInput {
    /// The uniform for a target of `size` pixels. `previous` is last frame's
    /// reversed-Z view-projection (this frame's when there is none).
    pub fn to_gpu(&self, previous: Option<Mat4>, size: (u32, u32)) -> GpuCamera {
        let projection = reverse_z(self.projection);
        let view_projection = projection * self.view;
        let view_inverse = safe_inverse(self.view);
        let position: Vec3 = view_inverse.w_axis.truncate();
        let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
        GpuCamera {
            view: self.view.to_cols_array_2d(),
            view_inverse: view_inverse.to_cols_array_2d(),
            projection: projection.to_cols_array_2d(),
            projection_inverse: safe_inverse(projection).to_cols_array_2d(),
            view_projection: view_projection.to_cols_array_2d(),
            previous_view_projection: previous.unwrap_or(view_projection).to_cols_array_2d(),
            position: [position.x, position.y, position.z, 1.0],
            size: [w, h, 1.0 / w, 1.0 / h],
        }
    }

    /// This frame's reversed-Z view-projection (next frame's "previous").
    pub fn view_projection(&self) -> Mat4 {
        reverse_z(self.projection) * self.view
    }
}

/// The radical inverse of `index` in `base`: the Halton sequence, in 0..1.
pub fn halton(index: u32, base: u32) -> f32 {
    let (mut f, mut r, mut i) = (1.0f32, 0.0f32, index);
    while i > 0 {
        f /= base as f32;
        r += f * (i % base) as f32;
        i /= base;
    }
    r
}

/// The sub-pixel jitter of `frame` for a target of `size` pixels, in NDC
/// units: Halton (2, 3) over 8 frames (index 1..=8, skipping 0 which would
/// sit on the pixel corner), centred so each offset is within half a pixel.
pub fn jitter_ndc(frame: u64, size: (u32, u32)) -> glam::Vec2 {
    let index = (frame % 8) as u32 + 1;
    let pixel = glam::Vec2::new(halton(index, 2) - 0.5, halton(index, 3) - 0.5);
    let (w, h) = (size.0.max(1) as f32, size.1.max(1) as f32);
    // NDC spans 2 over the target; +y is up in NDC and down in pixels.
    glam::Vec2::new(pixel.x * 2.0 / w, -pixel.y * 2.0 / h)
}

/// `projection` moved by `ndc` in normalized device coordinates: the whole
/// image shifts by that much whatever the depth (x' = x + ndc.x * w).
pub fn jittered(projection: Mat4, ndc: glam::Vec2) -> Mat4 {
    Mat4::from_translation(Vec3::new(ndc.x, ndc.y, 0.0)) * projection
}

/// The inverse, or identity for a singular matrix: a NaN must never reach a shader.
pub fn safe_inverse(m: Mat4) -> Mat4 {
    let det = m.determinant();
    if det.is_finite() && det.abs() > f32::MIN_POSITIVE {
        let inv = m.inverse();
        if inv.is_finite() {
            return inv;
        }
    }
    Mat4::IDENTITY
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reversed_z_puts_near_at_one_and_far_at_zero() {
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 1.5, 0.1, 100.0);
        let reversed = reverse_z(projection);
        let depth = |z: f32| {
            let clip = reversed * Vec4::new(0.0, 0.0, -z, 1.0);
            clip.z / clip.w
        };
        assert!((depth(0.1) - 1.0).abs() < 1e-5);
        assert!(depth(100.0).abs() < 1e-5);
        assert!(depth(1.0) > depth(10.0));
    }

    #[test]
    fn jitter_stays_within_half_a_pixel_and_averages_to_the_centre() {
        let size = (64, 32);
        let mut sum = glam::Vec2::ZERO;
        for frame in 0..8 {
            let j = jitter_ndc(frame, size);
            let pixels = j * glam::Vec2::new(32.0, -16.0);
            assert!(pixels.abs().max_element() < 0.5, "{frame}: {pixels}");
            sum += pixels;
        }
        assert!((sum / 8.0).length() < 0.1, "{sum}");
        assert_ne!(jitter_ndc(0, size), jitter_ndc(1, size));
        let projection = glam::camera::rh::proj::directx::perspective(1.0, 2.0, 0.1, 100.0);
        let moved = jittered(projection, glam::Vec2::new(0.01, -0.02));
        for z in [0.5f32, 10.0, 90.0] {
            let a = projection.project_point3(Vec3::new(0.3, 0.2, -z));
            let b = moved.project_point3(Vec3::new(0.3, 0.2, -z));
            assert!((b - a - Vec3::new(0.01, -0.02, 0.0)).length() < 1e-5);
        }
    }

    #[test]
    fn singular_matrices_invert_to_identity_not_nan() {
        assert_eq!(safe_inverse(Mat4::ZERO), Mat4::IDENTITY);
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_camera_matches_camera_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuCamera,
            "lib/camera.wgsl",
            [],
            "Camera",
            [
                view,
                view_inverse,
                projection,
                projection_inverse,
                view_projection,
                previous_view_projection,
                position,
                size
            ]
        );
    }
}

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
    fn singular_matrices_invert_to_identity_not_nan() {
        assert_eq!(safe_inverse(Mat4::ZERO), Mat4::IDENTITY);
    }
}

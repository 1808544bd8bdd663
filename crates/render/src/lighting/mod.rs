//! Lights and shading: light buffers (point, spot, sun), clustered light
//! assignment, the CookTorrance pass and CompositeLight. Shadows come with
//! their issue.

mod clusters;
pub(crate) mod clusters_key;
pub(crate) mod composite;
mod cook_torrance;
pub(crate) mod cook_torrance_key;
pub mod light_merge;
pub mod light_sets;
mod ssgi;
pub(crate) mod ssgi_key;
mod ssss;
pub(crate) mod ssss_key;

use std::sync::Arc;

use glam::{Mat4, Vec3};

pub use crate::light_kind::LightKind;
pub use clusters::{ClusterGrid, light_cutoff};
pub(crate) use clusters::{ClusterStore, GRID_BYTES, announce_assignment, assign_lights};
pub use composite::{
    CompositeInputs, CompositeKey, CompositeLight, LightComponents, LightPairs, MAX_COMPONENTS,
    MaterialAo, MaterialTerms, Shading, Textured,
};
pub(crate) use cook_torrance::near_far;
pub use cook_torrance::{CookTorrance, FEW_LIGHTS, LightLoop, Surfaces, Walk, resolve_walk};
pub use ssgi::GATHER_TEMPORAL as SSGI_GATHER_TEMPORAL;
pub use ssgi::HALF_RESOLUTION as SSGI_HALF_RESOLUTION;
pub use ssgi::{Ssgi, SsgiKey, SsgiSettings};
pub use ssss::{Ssss, SsssQuality};

use crate::recipe::TextureRef;
use crate::renderer::Renderer;

/// A point light. Intensity is luminous intensity in candela (lumens / 4 pi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
    pub intensity: f32,
    pub range: f32,
    /// The slice of a `ShadowMap (Point)` that holds this light's shadow (six faces); None: casts none.
    pub shadow: Option<u32>,
}

/// A spot light as Emeshe has it: a projector. `view` places it (it looks
/// down its -Z), `projection` shapes it: the frustum is the lit volume and
/// the light fades out at the far plane's distance. Through the frustum it projects a layer of the
/// buffer's texture array (`texture`), or, without one, a round cone whose
/// edge fades over `softness` (0..1 of its radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotLight {
    pub view: Mat4,
    pub projection: Mat4,
    pub color: Vec3,
    pub intensity: f32,
    pub texture: Option<u32>,
    pub softness: f32,
    /// The slice of a `ShadowMap (Spot)` that holds this light's shadow; None: casts none.
    pub shadow: Option<u32>,
}

/// The widest cone a perspective projection can make (just under 180 degrees).
const MAX_CONE: f32 = std::f32::consts::FRAC_PI_2 * 0.999;

impl SpotLight {
    /// A round spot at `position` shining along `direction`, out to `range`,
    /// fading from the inner to the outer half-angle (radians, clamped below 90 degrees).
    pub fn cone(
        position: Vec3,
        direction: Vec3,
        range: f32,
        inner_angle: f32,
        outer_angle: f32,
    ) -> SpotLight {
        let direction = unit(direction);
        // Any up that is not the direction itself.
        let up = if direction.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let outer = outer_angle.clamp(1e-4, MAX_CONE);
        let inner = inner_angle.clamp(0.0, outer);
        let range = range.max(1e-3);
        SpotLight {
            shadow: None,
            view: glam::camera::rh::view::look_to_mat4(position, direction, up),
            projection: glam::camera::rh::proj::directx::perspective(
                2.0 * outer,
                1.0,
                range * 1e-4,
                range,
            ),
            color: Vec3::ONE,
            intensity: 1.0,
            texture: None,
            softness: 1.0 - inner.tan() / outer.tan(),
        }
    }

    pub fn with_light(self, color: Vec3, intensity: f32) -> SpotLight {
        SpotLight {
            color,
            intensity,
            ..self
        }
    }
}

/// Why a spot's transforms cannot make a light.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpotError {
    #[error("spot {index}: the view transform cannot be inverted (a zero scale?)")]
    View { index: usize },
    #[error(
        "spot {index}: the projection has no finite frustum (it must be invertible with a finite far plane)"
    )]
    Projection { index: usize },
}

/// What shading needs of a spot's transforms: where it is, its axis, the
/// bounding cone of its frustum and its range (the far plane's distance).
struct SpotFrustum {
    position: Vec3,
    axis: Vec3,
    range: f32,
    cos_bound: f32,
}

impl SpotFrustum {
    fn of(index: usize, view: Mat4, projection: Mat4) -> Result<Self, SpotError> {
        let to_world = view.inverse();
        if !to_world.is_finite() || view.determinant().abs() < 1e-12 {
            return Err(SpotError::View { index });
        }
        let unproject = projection.inverse();
        let mut range = 0.0f32;
        let mut cos_bound = 1.0f32;
        for (x, y, z) in [-1.0f32, 1.0]
            .into_iter()
            .flat_map(|x| [-1.0f32, 1.0].map(move |y| (x, y)))
            .flat_map(|(x, y)| [0.0f32, 1.0].map(move |z| (x, y, z)))
        {
            let h = unproject * glam::Vec4::new(x, y, z, 1.0);
            let corner = h.truncate() / h.w;
            if !corner.is_finite() || h.w.abs() < 1e-12 {
                return Err(SpotError::Projection { index });
            }
            // The far plane's distance, not its corners': the light fades out
            // at it, so the sphere of this radius holds all it lights.
            range = range.max(corner.z.abs());
            cos_bound = cos_bound.min(corner.normalize_or_zero().dot(Vec3::NEG_Z));
        }
        if !(range.is_finite() && range > 0.0) {
            return Err(SpotError::Projection { index });
        }
        Ok(SpotFrustum {
            position: to_world.w_axis.truncate(),
            axis: unit(to_world.transform_vector3(Vec3::NEG_Z)),
            range,
            cos_bound,
        })
    }
}

/// A sun: parallel light travelling along `direction`, `illuminance` in lux.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunLight {
    pub direction: Vec3,
    pub color: Vec3,
    pub illuminance: f32,
    /// The slice of a `ShadowMap (Sun)` that holds this light's cascades; None: casts none.
    pub shadow: Option<u32>,
}

/// Matches `Light` in shaders/lighting/*.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuLight {
    /// xyz position, w range (suns: 0).
    position_range: [f32; 4],
    /// rgb colour times intensity (cd) or illuminance (lux).
    intensity: [f32; 4],
    /// xyz unit direction the light travels, w cosine of the outer cone angle.
    direction: [f32; 4],
    /// Spots: x edge softness of a round cone, y texture layer (-1: none).
    /// Every type: z its shadow slice (-1: none).
    cone: [f32; 4],
}

/// A light buffer's own bindings beside its `lights`: spots' projections
/// and texture array, and its shadow maps (depth, views, parameters and
/// the moments of a filter that keeps them). The one place every pass that
/// walks a light buffer (CookTorrance, lit transparency, EnvironmentProbe's
/// faces) binds them; `pass` names the pass in the error of shadow maps
/// not rendered this frame.
pub(crate) fn bind_light_buffer<'r>(
    mut b: crate::frame_graph::Bindings<'r>,
    cx: &crate::frame_graph::PassContext<'_>,
    lights: &'r LightBuffer,
    shadows: Option<&'r crate::shadows::ShadowMaps>,
    spot_textures: Option<crate::frame_graph::Tex>,
    pass: &str,
) -> Result<crate::frame_graph::Bindings<'r>, crate::error::RenderError> {
    b = b.buffer_opt("spot_projections", lights.projections());
    if let Some(textures) = spot_textures {
        b = b
            .array("spot_textures", textures)
            .sampler("spot_sampler", crate::shaders::Sampling::LinearClamp);
    }
    if let Some(shadows) = shadows {
        let (depth, moments) =
            shadows
                .textures()
                .ok_or_else(|| crate::error::RenderError::Pass {
                    pass: pass.to_owned(),
                    message: "the shadow maps were not rendered this frame".to_owned(),
                })?;
        let array = |t: &wgpu::Texture| cx.view_of(t, crate::texture_pool::ViewSpec::array());
        b = b
            .view("shadow_maps", array(&depth))
            .buffer("shadow_views", shadows.views())
            .buffer("shadow_params", shadows.params());
        if let Some(moments) = moments {
            b = b.view("shadow_moments", array(&moments));
        }
    }
    Ok(b)
}

/// What a light-buffer node outputs: lights of one type, uploaded once when its inputs change.
pub struct LightBuffer {
    pub kind: LightKind,
    count: u32,
    buffer: wgpu::Buffer,
    /// Spots: world to each light's clip space (its projection times its view).
    projections: Option<wgpu::Buffer>,
    /// Spots: the texture array their `texture` layers index.
    textures: Option<TextureRef>,
    /// A hash of what was uploaded (the lights, the spots' projections):
    /// an environment probe's re-render key.
    content: u64,
    /// Points: the lights as uploaded, for Light Merge (light_merge.rs).
    uploaded: Option<Arc<[GpuLight]>>,
    /// Merged lights: each light's band (light_merge.rs), read by the assignment.
    bands: Option<wgpu::Buffer>,
}

/// A hash of `bytes`, for [`LightBuffer::hash_content`].
fn bytes_hash(bytes: &[u8]) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    h.finish()
}

impl std::fmt::Debug for LightBuffer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LightBuffer({:?} x {})", self.kind, self.count)
    }
}

/// A unit vector, or straight down for a zero or non-finite one.
fn unit(v: Vec3) -> Vec3 {
    v.try_normalize().unwrap_or(Vec3::NEG_Y)
}

fn radiant(color: Vec3, intensity: f32) -> [f32; 4] {
    (color.max(Vec3::ZERO) * intensity.max(0.0))
        .extend(0.0)
        .to_array()
}

impl LightBuffer {
    pub fn points(renderer: &Renderer, lights: &[PointLight]) -> Arc<Self> {
        Self::points_of(renderer, None, lights)
    }

    /// As [`LightBuffer::points`], kept under node `owner` across its
    /// re-evaluations: the same buffer (written only when the lights
    /// change), so the bind groups over it are reused from frame to frame.
    pub fn points_of(renderer: &Renderer, owner: Option<u32>, lights: &[PointLight]) -> Arc<Self> {
        let gpu: Arc<[GpuLight]> = lights
            .iter()
            .map(|l| GpuLight {
                position_range: l.position.extend(l.range.max(0.0)).to_array(),
                intensity: radiant(l.color, l.intensity),
                direction: [0.0, -1.0, 0.0, -1.0],
                cone: [-1.0, 0.0, shadow_slice(l.shadow), 0.0],
            })
            .collect();
        let mut buffer = Self::upload(renderer, owner, LightKind::Point, &gpu);
        Arc::get_mut(&mut buffer).expect("just made").uploaded = Some(gpu);
        buffer
    }

    /// Spots projecting layers of `textures` (a 2D texture, or an array of
    /// them); without one, or for a spot with no layer, a round cone. A
    /// layer past the array's end wraps, as vvvv's slices do.
    pub fn spots(
        renderer: &Renderer,
        lights: &[SpotLight],
        textures: Option<TextureRef>,
    ) -> Result<Arc<Self>, SpotError> {
        Self::spots_of(renderer, None, lights, textures)
    }

    /// As [`LightBuffer::spots`], kept under node `owner` ([`LightBuffer::points_of`]).
    pub fn spots_of(
        renderer: &Renderer,
        owner: Option<u32>,
        lights: &[SpotLight],
        textures: Option<TextureRef>,
    ) -> Result<Arc<Self>, SpotError> {
        let mut gpu = Vec::with_capacity(lights.len());
        let mut projections = Vec::with_capacity(lights.len().max(1));
        for (index, l) in lights.iter().enumerate() {
            let frustum = SpotFrustum::of(index, l.view, l.projection)?;
            // Layers are exact in f32 far beyond any texture array's limit.
            let layer = match (l.texture, &textures) {
                (Some(t), Some(_)) => t as f32,
                _ => -1.0,
            };
            gpu.push(GpuLight {
                position_range: frustum.position.extend(frustum.range).to_array(),
                intensity: radiant(l.color, l.intensity),
                direction: frustum.axis.extend(frustum.cos_bound).to_array(),
                cone: [
                    sanitize_unit(l.softness),
                    layer,
                    shadow_slice(l.shadow),
                    0.0,
                ],
            });
            projections.push((l.projection * l.view).to_cols_array());
        }
        if projections.is_empty() {
            projections.push(Mat4::ZERO.to_cols_array());
        }
        let projections_cpu = projections;
        let projections = renderer.kept_init(
            owner,
            "spot projections",
            bytemuck::cast_slice(&projections_cpu),
            wgpu::BufferUsages::STORAGE,
        );
        let mut buffer = Self::upload(renderer, owner, LightKind::Spot, &gpu);
        let b = Arc::get_mut(&mut buffer).expect("just made");
        b.projections = Some(projections);
        b.content ^= bytes_hash(bytemuck::cast_slice(&projections_cpu)).rotate_left(1);
        b.textures = textures.filter(|_| lights.iter().any(|l| l.texture.is_some()));
        Ok(buffer)
    }

    pub fn suns(renderer: &Renderer, lights: &[SunLight]) -> Arc<Self> {
        Self::suns_of(renderer, None, lights)
    }

    /// As [`LightBuffer::suns`], kept under node `owner` ([`LightBuffer::points_of`]).
    pub fn suns_of(renderer: &Renderer, owner: Option<u32>, lights: &[SunLight]) -> Arc<Self> {
        let gpu: Vec<GpuLight> = lights
            .iter()
            .map(|l| GpuLight {
                position_range: [0.0; 4],
                intensity: radiant(l.color, l.illuminance),
                direction: unit(l.direction).extend(-1.0).to_array(),
                cone: [-1.0, 0.0, shadow_slice(l.shadow), 0.0],
            })
            .collect();
        Self::upload(renderer, owner, LightKind::Sun, &gpu)
    }

    fn upload(
        renderer: &Renderer,
        owner: Option<u32>,
        kind: LightKind,
        gpu: &[GpuLight],
    ) -> Arc<Self> {
        let count = gpu.len() as u32;
        let content = bytes_hash(bytemuck::cast_slice(gpu));
        let buffer = renderer.kept_storage(owner, "lights", gpu);
        Arc::new(LightBuffer {
            kind,
            count,
            buffer,
            projections: None,
            textures: None,
            content,
            uploaded: None,
            bands: None,
        })
    }

    pub fn count(&self) -> u32 {
        self.count
    }

    /// What the buffer holds, as far as it lights anything: its type, the
    /// lights as uploaded, the spots' projections and texture by name (a
    /// probe renders its faces again when this changes).
    pub fn hash_content(&self, h: &mut impl std::hash::Hasher) {
        use std::hash::Hash;
        (self.kind, self.count, self.content).hash(h);
        self.textures.as_ref().map(|t| &t.name).hash(h);
    }

    pub(crate) fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }

    /// Merged lights' bands (light_merge.rs): one per light, for the assignment.
    pub(crate) fn bands(&self) -> Option<&wgpu::Buffer> {
        self.bands.as_ref()
    }

    pub(crate) fn projections(&self) -> Option<&wgpu::Buffer> {
        self.projections.as_ref()
    }

    /// The spots' texture array, when some spot projects a layer of it.
    pub fn textures(&self) -> Option<&TextureRef> {
        self.textures.as_ref()
    }
}

/// A shadow slice as the shader reads it: exact in f32, -1 for none.
fn shadow_slice(slice: Option<u32>) -> f32 {
    slice.map_or(-1.0, |s| s as f32)
}

/// 0..1, and 0 for NaN.
fn sanitize_unit(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The layout the shader sees (shaders/layout.rs).
#[cfg(test)]
mod wgsl_layout {
    use super::*;

    #[test]
    fn gpu_light_matches_light_in_the_shader() {
        crate::assert_wgsl_layout!(
            GpuLight,
            crate::lighting::cook_torrance_key::CookTorranceKey,
            [],
            "Light",
            [position_range, intensity, direction, cone]
        );
    }
}

//! What a scene holds besides meshes: `KHR_lights_punctual` lights as the
//! renderer's point, spot and sun lights (placed by their nodes' world
//! transforms; intensities as the file gives them: candela for point and
//! spot, lux for directional, which is what the light buffers take), and
//! cameras as view and projection matrices.

use glam::{Mat4, Vec3};

use spreadlight_render::lighting::{PointLight, SpotLight, SunLight};

/// The scene's lights by type, each with a name (the file's, or `light N`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneLights {
    pub points: Vec<(String, PointLight)>,
    pub spots: Vec<(String, SpotLight)>,
    pub suns: Vec<(String, SunLight)>,
}

impl SceneLights {
    pub fn is_empty(&self) -> bool {
        self.points.is_empty() && self.spots.is_empty() && self.suns.is_empty()
    }
}

/// A camera of the scene: where it is and how it projects (right-handed,
/// depth 0..1, as the MRE's View and Projection pins take them).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneCamera {
    pub name: String,
    /// The node that places it.
    pub node: usize,
    pub view: Mat4,
    pub projection: Mat4,
    /// The file's aspect ratio, when it states one (perspective only).
    pub aspect_ratio: Option<f32>,
}

/// Where a light without a range fades out: where its inverse-square
/// falloff has dropped to a thousandth of a candela's, and never short of
/// the scene (`reach`: the scene's diameter).
fn default_range(intensity: f32, reach: f32) -> f32 {
    (intensity.abs() * 1000.0).sqrt().max(reach).max(1e-3)
}

/// The largest light range kept: a spot light's shadow projection spans
/// range x 1e-4 to range, and their product must stay a finite f32.
const MAX_RANGE: f32 = 1e20;

/// A light as its node holds it, to place at any pose of the node.
#[derive(Debug, Clone, PartialEq)]
pub struct LightSource {
    pub node: usize,
    pub name: String,
    kind: SourceKind,
    color: Vec3,
    /// Candela (point, spot) or lux (directional).
    intensity: f32,
    range: f32,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum SourceKind {
    Point,
    Spot { inner: f32, outer: f32 },
    Directional,
}

impl LightSource {
    /// The light `light` on node `node`; `reach` (the scene's diameter)
    /// bounds the range of lights that state none.
    pub(super) fn new(light: &gltf::khr_lights_punctual::Light, node: usize, reach: f32) -> Self {
        use gltf::khr_lights_punctual::Kind;
        let name = light
            .name()
            .map_or_else(|| format!("light {}", light.index()), str::to_owned);
        let finite = |v: f32, or: f32| if v.is_finite() { v } else { or };
        let intensity = finite(light.intensity(), 1.0).max(0.0);
        let range = light
            .range()
            .filter(|r| r.is_finite() && *r > 0.0)
            .unwrap_or_else(|| default_range(intensity, reach))
            .min(MAX_RANGE);
        let kind = match light.kind() {
            Kind::Point => SourceKind::Point,
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => SourceKind::Spot {
                inner: finite(inner_cone_angle, 0.0),
                outer: finite(outer_cone_angle, std::f32::consts::FRAC_PI_4),
            },
            Kind::Directional => SourceKind::Directional,
        };
        LightSource {
            node,
            name,
            kind,
            color: Vec3::from(light.color()).map(|c| finite(c, 1.0).max(0.0)),
            intensity,
            range,
        }
    }

    /// The light placed by its node's world transform `world`, added to `lights`.
    pub fn place(&self, world: Mat4, lights: &mut SceneLights) {
        let position = world.transform_point3(Vec3::ZERO);
        // Lights shine down their node's -Z.
        let direction = world
            .transform_vector3(Vec3::NEG_Z)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        let name = self.name.clone();
        match self.kind {
            SourceKind::Point => lights.points.push((
                name,
                PointLight {
                    position,
                    color: self.color,
                    intensity: self.intensity,
                    range: self.range,
                    shadow: None,
                },
            )),
            SourceKind::Spot { inner, outer } => lights.spots.push((
                name,
                SpotLight::cone(position, direction, self.range, inner, outer)
                    .with_light(self.color, self.intensity),
            )),
            SourceKind::Directional => lights.suns.push((
                name,
                SunLight {
                    direction,
                    color: self.color,
                    illuminance: self.intensity,
                    shadow: None,
                },
            )),
        }
    }
}

/// The camera `camera` on node `node` with world transform `world`. An
/// infinite perspective is given a far plane 10^6 near planes away.
pub(super) fn camera(camera: &gltf::Camera, node: usize, world: Mat4) -> SceneCamera {
    use gltf::camera::Projection;
    let name = camera
        .name()
        .map_or_else(|| format!("camera {}", camera.index()), str::to_owned);
    let positive = |v: f32, or: f32| if v.is_finite() && v > 0.0 { v } else { or };
    let (projection, aspect_ratio) = match camera.projection() {
        Projection::Perspective(p) => {
            // Planes beyond 1e30 are no real scene's; capped so the matrix stays finite.
            let near = positive(p.znear(), 0.01).min(1e30);
            let far = p
                .zfar()
                .filter(|f| f.is_finite() && *f > near)
                .unwrap_or(near * 1e6)
                .max(near * 1.001);
            let aspect = p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0);
            let fov = positive(p.yfov(), 0.8).min(3.1);
            let mut projection =
                glam::camera::rh::proj::directx::perspective(fov, aspect.unwrap_or(1.0), near, far);
            // glam forms near x far in f32, which overflows for large planes.
            let (n, f) = (f64::from(near), f64::from(far));
            projection.w_axis.z = (n * f / (n - f)) as f32;
            (projection, aspect)
        }
        Projection::Orthographic(o) => {
            let (x, y) = (positive(o.xmag().abs(), 1.0), positive(o.ymag().abs(), 1.0));
            let near = if o.znear().is_finite() {
                o.znear().max(0.0)
            } else {
                0.0
            };
            let far = positive(o.zfar(), near + 1.0).max(near + 1e-3);
            (
                glam::camera::rh::proj::directx::orthographic(-x, x, -y, y, near, far),
                None,
            )
        }
    };
    SceneCamera {
        name,
        node,
        view: view_of(world),
        projection,
        aspect_ratio,
    }
}

/// The view matrix of a camera node: the inverse of its rigid placement (scale dropped).
fn view_of(world: Mat4) -> Mat4 {
    let (_, rotation, translation) = world.to_scale_rotation_translation();
    // A node of scale 0 has no orientation (NaN here): it looks down -Z.
    let rotation = if rotation.is_finite() {
        rotation.normalize()
    } else {
        glam::Quat::IDENTITY
    };
    let translation = if translation.is_finite() {
        translation
    } else {
        Vec3::ZERO
    };
    Mat4::from_rotation_translation(rotation, translation).inverse()
}

impl SceneCamera {
    /// The camera with its node at world transform `world`.
    pub fn placed(&self, world: Mat4) -> SceneCamera {
        SceneCamera {
            view: view_of(world),
            ..self.clone()
        }
    }

    /// The projection for an output of `aspect` (width / height) when the
    /// file states none (a perspective camera's matrix is rebuilt).
    pub fn projection_for(&self, aspect: f32) -> Mat4 {
        if self.aspect_ratio.is_some() || self.projection.w_axis.w != 0.0 {
            // Stated aspect, or orthographic (w_axis.w = 1): as given.
            return self.projection;
        }
        let mut p = self.projection;
        // directx::perspective: x_axis.x = y_axis.y / aspect.
        p.x_axis.x = p.y_axis.y / aspect.max(1e-6);
        p
    }
}

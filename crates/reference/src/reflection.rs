//! Reflections on the CPU: the ground truth `Reflection` and `SSR` are
//! measured against (`spreadlight accuracy reflection`). Rays from each
//! surface point into a scene of analytic spheres over a square floor at
//! y = 0, under the same environment the GPU prefilters (the procedural
//! sky evaluated identically, or the same equirectangular image sampled
//! bilinearly). Mirror reflection is one ray; glossy reflection is many
//! GGX-importance-sampled rays weighted by the renderer's BRDF (height-
//! correlated Smith, Schlick Fresnel), so the result is the specular
//! reflection term per pixel: the integral of L(l) D V F (n.l) over l.

use glam::{Vec2, Vec3};

use crate::brdf::{f_schlick, roughness_to_alpha, v_smith_ggx_correlated};
use crate::shadows::Sphere;

/// The procedural sky as shaders/lib/sky.wgsl computes it (`GpuSky`'s sanitizing included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CpuSky {
    zenith: Vec3,
    horizon: Vec3,
    ground: Vec3,
    towards_sun: Vec3,
    sun_cos: f32,
    sun_color: Vec3,
    glow: f32,
}

fn clean(v: Vec3) -> Vec3 {
    let c = |x: f32| {
        if x.is_finite() {
            x.clamp(0.0, 65000.0)
        } else {
            0.0
        }
    };
    Vec3::new(c(v.x), c(v.y), c(v.z))
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// What the procedural sky is made of: the renderer's `SkySettings`, field
/// for field (`CpuSky::from(&settings)` there), kept here as plain numbers so
/// that this crate needs nothing of the renderer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyInputs {
    pub zenith: Vec3,
    pub horizon: Vec3,
    pub ground: Vec3,
    /// The direction the sunlight travels: the disk is opposite it.
    pub sun_direction: Vec3,
    pub sun_color: Vec3,
    /// The disk's angular radius in radians.
    pub sun_radius: f32,
    pub glow: f32,
}

impl CpuSky {
    pub fn new(s: &SkyInputs) -> Self {
        let finite = |v: f32, lo: f32, hi: f32| if v.is_finite() { v.clamp(lo, hi) } else { 0.0 };
        CpuSky {
            zenith: clean(s.zenith),
            horizon: clean(s.horizon),
            ground: clean(s.ground),
            towards_sun: (-s.sun_direction).try_normalize().unwrap_or(Vec3::Y),
            sun_cos: finite(s.sun_radius, 0.0, 0.5).cos(),
            sun_color: clean(s.sun_color),
            glow: finite(s.glow, 0.0, 1e3),
        }
    }

    /// Radiance along unit direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let up = d.y;
        let mut color = if up >= 0.0 {
            self.horizon.lerp(self.zenith, up.powf(0.5))
        } else {
            self.horizon.lerp(self.ground, (-up * 4.0).clamp(0.0, 1.0))
        };
        let c = d.dot(self.towards_sun);
        let disk = smoothstep(self.sun_cos - 1e-4, self.sun_cos + 1e-4, c);
        let glow = c.max(0.0).powf(64.0) * self.glow;
        color += self.sun_color * (disk + glow * 0.01);
        color.clamp(Vec3::ZERO, Vec3::splat(65000.0))
    }
}

/// Where direction `d` lands in an equirectangular image: `equirect_uv` of shaders/lib/ibl.wgsl.
pub fn equirect_uv(d: Vec3) -> Vec2 {
    let u = 0.5 + d.x.atan2(-d.z) / std::f32::consts::TAU;
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    Vec2::new(u, v)
}

/// An equirectangular image's linear radiance, row by row from the top
/// (the renderer's `EquirectImage` lends itself as one: `Equirect::from(&image)`).
#[derive(Clone, Copy, Debug)]
pub struct Equirect<'a> {
    pub width: u32,
    pub height: u32,
    pub pixels: &'a [[f32; 4]],
}

/// A texel as the renderer uploads it (`EquirectImage::sanitized`): NaN is
/// 0, the rest within 0..=65000 (infinity the largest).
fn as_uploaded(c: f32) -> f32 {
    if c.is_nan() {
        0.0
    } else {
        c.clamp(0.0, 65000.0)
    }
}

/// Bilinear lookup, wrapping in u and clamped in v, of the sanitized image
/// (as uploaded: half floats, NaN 0, within 0..=65000).
pub fn equirect_radiance(image: &Equirect<'_>, d: Vec3) -> Vec3 {
    let uv = equirect_uv(d);
    let (w, h) = (image.width as i64, image.height as i64);
    let x = uv.x * w as f32 - 0.5;
    let y = uv.y * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |xi: i64, yi: i64| {
        let p = image.pixels[(yi.clamp(0, h - 1) * w + xi.rem_euclid(w)) as usize];
        Vec3::new(p[0], p[1], p[2]).map(as_uploaded)
    };
    let (x0, y0) = (x0 as i64, y0 as i64);
    let top = texel(x0, y0).lerp(texel(x0 + 1, y0), fx);
    let bottom = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), fx);
    top.lerp(bottom, fy)
}

/// What surrounds the scene.
#[derive(Clone, Copy, Debug)]
pub enum CpuEnvironment<'a> {
    Sky(CpuSky),
    Equirect(Equirect<'a>),
}

impl CpuEnvironment<'_> {
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            CpuEnvironment::Sky(s) => s.radiance(d),
            CpuEnvironment::Equirect(image) => equirect_radiance(image, d),
        }
    }
}

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Surface {
    Ball(usize),
    Floor,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub point: Vec3,
    pub normal: Vec3,
    pub surface: Surface,
}

/// Spheres over a square floor of side `floor` centred at the origin, at y = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct BallsScene {
    pub balls: Vec<Sphere>,
    pub floor: f32,
}

impl BallsScene {
    /// The nearest hit along `origin + t dir`, t > 1e-4.
    pub fn trace(&self, origin: Vec3, dir: Vec3) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for (i, s) in self.balls.iter().enumerate() {
            let oc = origin - s.center;
            let b = oc.dot(dir);
            let c = oc.length_squared() - s.radius * s.radius;
            let disc = b * b - c;
            if disc < 0.0 {
                continue;
            }
            let root = disc.sqrt();
            let t = if -b - root > 1e-4 {
                -b - root
            } else {
                -b + root
            };
            if t > 1e-4 && best.is_none_or(|h| t < h.t) {
                let point = origin + dir * t;
                best = Some(Hit {
                    t,
                    point,
                    normal: (point - s.center) / s.radius,
                    surface: Surface::Ball(i),
                });
            }
        }
        if dir.y.abs() > 1e-8 {
            let t = -origin.y / dir.y;
            let point = origin + dir * t;
            let half = self.floor * 0.5;
            if t > 1e-4
                && point.x.abs() <= half
                && point.z.abs() <= half
                && best.is_none_or(|h| t < h.t)
            {
                best = Some(Hit {
                    t,
                    point,
                    normal: Vec3::Y,
                    surface: Surface::Floor,
                });
            }
        }
        best
    }
}

/// Van der Corput / Hammersley, as `hammersley` in shaders/lib/ibl.wgsl.
pub fn hammersley(i: u32, n: u32) -> Vec2 {
    Vec2::new(
        i as f32 / n.max(1) as f32,
        i.reverse_bits() as f32 * 2.328_306_4e-10,
    )
}

/// A GGX-distributed half vector around `n`, as `importance_sample_ggx` in shaders/lib/ibl.wgsl.
pub fn importance_sample_ggx(xi: Vec2, alpha: f32, n: Vec3) -> Vec3 {
    let a2 = alpha * alpha;
    let phi = std::f32::consts::TAU * xi.x;
    let cos_theta = ((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y))
        .clamp(0.0, 1.0)
        .sqrt();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let (t, b) = n.any_orthonormal_pair();
    (t * (sin_theta * phi.cos()) + b * (sin_theta * phi.sin()) + n * cos_theta).normalize()
}

/// The surface a specular reflection is computed for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularSurface {
    pub point: Vec3,
    pub normal: Vec3,
    /// Unit, towards the eye.
    pub view: Vec3,
    pub roughness: f32,
    pub f0: Vec3,
}

/// The specular reflection term at `s`: the integral of L(l) D V F (n.l)
/// over directions l, where L is `radiance_of(hit)` for a ray that hits the
/// scene and the environment otherwise. Roughness 0 is one mirror ray
/// weighted by Schlick's Fresnel at N.V (the split-sum's limit); otherwise
/// `samples` GGX-importance-sampled rays, jittered per pixel by `rotation`
/// (0..1) so neighbouring pixels do not share a pattern.
pub fn specular_reflection(
    scene: &BallsScene,
    environment: &CpuEnvironment<'_>,
    radiance_of: &dyn Fn(&Hit) -> Vec3,
    s: &SpecularSurface,
    samples: u32,
    rotation: f32,
) -> Vec3 {
    let n_dot_v = s.normal.dot(s.view).clamp(1e-4, 1.0);
    let origin = s.point + s.normal * 1e-3;
    let incoming = |l: Vec3| match scene.trace(origin, l) {
        Some(hit) => radiance_of(&hit),
        None => environment.radiance(l),
    };
    if s.roughness <= 0.0 {
        let l = (2.0 * n_dot_v * s.normal - s.view).normalize();
        return incoming(l) * f_schlick(s.f0, n_dot_v);
    }
    let alpha = roughness_to_alpha(s.roughness);
    let mut sum = Vec3::ZERO;
    let count = samples.max(1);
    for i in 0..count {
        let mut xi = hammersley(i, count);
        xi.x = (xi.x + rotation).fract();
        let h = importance_sample_ggx(xi, alpha, s.normal);
        let v_dot_h = s.view.dot(h);
        if v_dot_h <= 0.0 {
            continue;
        }
        let l = 2.0 * v_dot_h * h - s.view;
        let n_dot_l = s.normal.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        let n_dot_h = s.normal.dot(h).max(1e-6);
        // D V F (n.l) / pdf(l), with pdf(l) = D (n.h) / (4 v.h).
        let weight = f_schlick(s.f0, v_dot_h)
            * (v_smith_ggx_correlated(n_dot_v, n_dot_l, s.roughness) * 4.0 * n_dot_l * v_dot_h
                / n_dot_h);
        sum += incoming(l) * weight;
    }
    sum / count as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The renderer's default sky (`SkySettings::default()`).
    fn default_sky() -> SkyInputs {
        SkyInputs {
            zenith: Vec3::new(0.12, 0.25, 0.6),
            horizon: Vec3::new(0.6, 0.7, 0.85),
            ground: Vec3::new(0.2, 0.18, 0.16),
            sun_direction: Vec3::new(-0.3, -1.0, -0.2),
            sun_color: Vec3::new(50.0, 45.0, 38.0),
            sun_radius: 0.0047,
            glow: 1.0,
        }
    }

    #[test]
    fn a_mirror_sees_the_ball_above_it_and_the_sky_past_it() {
        let scene = BallsScene {
            balls: vec![Sphere {
                center: Vec3::new(0.0, 1.0, 0.0),
                radius: 0.5,
            }],
            floor: 10.0,
        };
        let sky = CpuEnvironment::Sky(CpuSky::new(&default_sky()));
        let red = |_: &Hit| Vec3::new(1.0, 0.0, 0.0);
        let floor = |x: f32| SpecularSurface {
            point: Vec3::new(x, 0.0, 0.0),
            normal: Vec3::Y,
            view: Vec3::Y,
            roughness: 0.0,
            f0: Vec3::ONE,
        };
        assert_eq!(
            specular_reflection(&scene, &sky, &red, &floor(0.0), 1, 0.0),
            Vec3::new(1.0, 0.0, 0.0)
        );
        let past = specular_reflection(&scene, &sky, &red, &floor(2.0), 1, 0.0);
        assert!((past - sky.radiance(Vec3::Y)).length() < 1e-5, "{past}");
        // A white furnace: a rough conductor with F0 = 1 under a uniform
        // environment reflects about the environment (energy lost to single scattering only).
        let uniform = CpuEnvironment::Sky(CpuSky::new(&SkyInputs {
            zenith: Vec3::ONE,
            horizon: Vec3::ONE,
            ground: Vec3::ONE,
            sun_color: Vec3::ZERO,
            glow: 0.0,
            ..default_sky()
        }));
        let empty = BallsScene {
            balls: vec![],
            floor: 0.0,
        };
        let mut s = floor(0.0);
        s.roughness = 0.5;
        s.view = Vec3::new(0.6, 0.8, 0.0);
        let white = specular_reflection(&empty, &uniform, &red, &s, 4096, 0.0);
        assert!(white.x > 0.85 && white.x <= 1.01, "{white}");
    }

    #[test]
    fn the_cpu_sky_is_the_shader_sky() {
        let sky = CpuSky::new(&default_sky());
        let sun = (-default_sky().sun_direction).normalize();
        assert!(sky.radiance(sun).x > 20.0, "the disk");
        assert!(
            sky.radiance(Vec3::Y).z > sky.radiance(Vec3::Y).x,
            "a blue zenith"
        );
        let u = equirect_uv(Vec3::NEG_Z);
        assert!((u - Vec2::new(0.5, 0.5)).length() < 1e-6);
    }
}

//! Node animations: glTF's translation, rotation and scale channels (step,
//! linear with quaternion slerp, cubic spline), read through the checked
//! accessor reader, and the scene posed at a time ([`GltfScene::pose`]).
//! Morph target `weights` channels load beside them ([`super::morph`]).

use glam::{Mat4, Quat, Vec3, Vec4};
use gltf::Document;
use gltf::animation::{Interpolation, Property};
use rayon::prelude::*;

use super::{GltfError, GltfScene, Importer};

/// The loaded scene's node tree: for each scene node, parents first, its
/// parent and its rest transform (what a pose starts from).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SceneGraph {
    /// (node, parent) in an order where parents come first.
    pub order: Vec<(usize, Option<usize>)>,
    /// Per glTF node: its local matrix at rest, and its TRS when it has one.
    pub rest: Vec<(Mat4, Trs)>,
}

/// A node's translation, rotation and scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trs {
    pub translation: Vec3,
    pub rotation: Quat,
    pub scale: Vec3,
}

impl Trs {
    fn matrix(&self) -> Mat4 {
        Mat4::from_scale_rotation_translation(self.scale, self.rotation, self.translation)
    }
}

/// What a channel animates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    Translation,
    Rotation,
    Scale,
}

/// One animated property of one node.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    pub node: usize,
    pub path: Path,
    pub interpolation: Interpolation,
    /// Keyframe times, seconds.
    pub times: Vec<f32>,
    /// Per keyframe (three per keyframe for cubic splines: in-tangent,
    /// value, out-tangent): xyz, or a quaternion's xyzw.
    pub values: Vec<Vec4>,
}

/// A named set of channels.
#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    pub name: String,
    pub channels: Vec<Channel>,
    /// Morph weight channels.
    pub weights: Vec<super::morph::WeightsChannel>,
    /// The last keyframe time over all channels.
    pub duration: f32,
}

impl Importer<'_> {
    pub(super) fn animations(&mut self, document: &Document) -> Result<Vec<Animation>, GltfError> {
        let mut out = Vec::new();
        for animation in document.animations() {
            let name = animation
                .name()
                .map_or_else(|| format!("animation {}", animation.index()), str::to_owned);
            let mut channels = Vec::new();
            let mut weights = Vec::new();
            for channel in animation.channels() {
                let sampler = channel.sampler();
                let what = format!("{name}, channel {}", channel.index());
                let times: Vec<[f32; 1]> = self.animation_floats(&what, &sampler.input())?;
                let path = match channel.target().property() {
                    Property::Translation => Path::Translation,
                    Property::Rotation => Path::Rotation,
                    Property::Scale => Path::Scale,
                    Property::MorphTargetWeights => {
                        let times = times.into_iter().map(|[t]| t).collect();
                        let node = channel.target().node();
                        weights.extend(self.weights_channel(&what, &node, &sampler, times)?);
                        continue;
                    }
                };
                let values: Vec<Vec4> = match path {
                    Path::Rotation => self
                        .animation_floats::<4>(&what, &sampler.output())?
                        .into_iter()
                        .map(Vec4::from)
                        .collect(),
                    _ => self
                        .animation_floats::<3>(&what, &sampler.output())?
                        .into_iter()
                        .map(|v| Vec3::from(v).extend(0.0))
                        .collect(),
                };
                let interpolation = sampler.interpolation();
                let per_key = if interpolation == Interpolation::CubicSpline {
                    3
                } else {
                    1
                };
                if times.is_empty() || values.len() != times.len() * per_key {
                    self.warn(format!(
                        "{what}: {} keyframes but {} values; the channel is skipped",
                        times.len(),
                        values.len()
                    ));
                    continue;
                }
                channels.push(Channel {
                    node: channel.target().node().index(),
                    path,
                    interpolation,
                    times: times.into_iter().map(|[t]| t).collect(),
                    values,
                });
            }
            let duration = channels
                .iter()
                .map(|c| &c.times)
                .chain(weights.iter().map(|w| &w.times))
                .filter_map(|times| times.last().copied())
                .filter(|t| t.is_finite())
                .fold(0.0, f32::max);
            out.push(Animation {
                name,
                channels,
                weights,
                duration,
            });
        }
        Ok(out)
    }

    fn animation_floats<const N: usize>(
        &self,
        what: &str,
        accessor: &gltf::Accessor,
    ) -> Result<Vec<[f32; N]>, GltfError> {
        self.buffers
            .read_floats::<N>(accessor)
            .map_err(|reason| GltfError::Accessor {
                path: self.path.to_owned(),
                index: accessor.index(),
                usage: format!("keyframes of {what}"),
                reason,
            })
    }
}

/// The rest TRS of a node (a matrix node decomposed, for animation only).
pub(super) fn rest_of(node: &gltf::Node) -> (Mat4, Trs) {
    let matrix = Mat4::from_cols_array_2d(&node.transform().matrix());
    let (t, r, s) = node.transform().decomposed();
    let trs = Trs {
        translation: Vec3::from(t),
        rotation: Quat::from_array(r),
        scale: Vec3::from(s),
    };
    (matrix, trs)
}

impl Animation {
    /// `time` wrapped into the animation's duration (0 when it has none).
    pub fn looped(&self, time: f32) -> f32 {
        if self.duration > 0.0 && time.is_finite() {
            time.rem_euclid(self.duration)
        } else {
            0.0
        }
    }
}

/// Channels of an animation sampled on the posing threads from this many.
const PARALLEL_CHANNELS: usize = 256;

impl Channel {
    /// The channel's value at `time` (held before the first and after the last keyframe).
    fn sample(&self, time: f32) -> Vec4 {
        let n = self.times.len();
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let value = |k: usize| {
            if cubic {
                self.values[3 * k + 1]
            } else {
                self.values[k]
            }
        };
        let next = self.times.partition_point(|&t| t <= time);
        if next == 0 {
            return value(0);
        }
        if next >= n {
            return value(n - 1);
        }
        let k = next - 1;
        let (t0, t1) = (self.times[k], self.times[next]);
        let span = t1 - t0;
        let s = if span > 0.0 {
            ((time - t0) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let rotation = self.path == Path::Rotation;
        match self.interpolation {
            Interpolation::Step => value(k),
            Interpolation::Linear if rotation => {
                let a = Quat::from_vec4(value(k)).normalize();
                let b = Quat::from_vec4(value(next)).normalize();
                Vec4::from(a.slerp(b, s))
            }
            Interpolation::Linear => value(k).lerp(value(next), s),
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                let out_tangent = self.values[3 * k + 2] * span;
                let in_tangent = self.values[3 * next] * span;
                let v = value(k) * (2.0 * s3 - 3.0 * s2 + 1.0)
                    + out_tangent * (s3 - 2.0 * s2 + s)
                    + value(next) * (-2.0 * s3 + 3.0 * s2)
                    + in_tangent * (s3 - s2);
                if rotation {
                    Vec4::from(Quat::from_vec4(v).normalize())
                } else {
                    v
                }
            }
        }
    }
}

impl GltfScene {
    /// Every instance's world transform with `animation` applied at `time`
    /// seconds (looping over its duration); `None`, or an index out of
    /// range: the rest pose.
    pub fn pose(&self, animation: Option<usize>, time: f32) -> Vec<Mat4> {
        let world = self.node_worlds(animation, time);
        self.instances
            .iter()
            .map(|i| world.get(i.node).copied().unwrap_or(i.transform))
            .collect()
    }

    /// The lights and cameras at a pose (`node_worlds`): they follow their nodes.
    pub fn posed_content(&self, world: &[Mat4]) -> (super::SceneLights, Vec<super::SceneCamera>) {
        let mut lights = super::SceneLights::default();
        for source in &self.light_sources {
            let at = world.get(source.node).copied().unwrap_or(Mat4::IDENTITY);
            source.place(at, &mut lights);
        }
        let cameras = self
            .cameras
            .iter()
            .map(|c| match world.get(c.node) {
                Some(w) => c.placed(*w),
                None => c.clone(),
            })
            .collect();
        (lights, cameras)
    }

    /// Every glTF node's world transform at a pose (identity for nodes outside the scene).
    pub fn node_worlds(&self, animation: Option<usize>, time: f32) -> Vec<Mat4> {
        let graph = &self.graph;
        // Per node, its place in `posed` (NOT_POSED: at rest): a herd's
        // thousands of nodes cost a word each to clear, not a pose each.
        const NOT_POSED: u32 = u32::MAX;
        let mut slot = vec![NOT_POSED; graph.rest.len()];
        let mut posed: Vec<Trs> = Vec::new();
        if let Some(a) = animation.and_then(|a| self.animations.get(a)) {
            let time = a.looped(time);
            // A herd's thousands of channels (each a search and a slerp) are
            // sampled on the posing threads (pool.rs); a few stay on this one, where the
            // pool's hand-off would cost more than they do.
            let samples: Vec<Vec4> = if a.channels.len() >= PARALLEL_CHANNELS {
                crate::pool::posing(|| {
                    a.channels
                        .par_iter()
                        .with_min_len(PARALLEL_CHANNELS / 4)
                        .map(|c| c.sample(time))
                        .collect()
                })
            } else {
                a.channels.iter().map(|c| c.sample(time)).collect()
            };
            for (c, v) in a.channels.iter().zip(samples) {
                let Some(rest) = graph.rest.get(c.node) else {
                    continue;
                };
                if slot[c.node] == NOT_POSED {
                    slot[c.node] = posed.len() as u32;
                    posed.push(rest.1);
                }
                let trs = &mut posed[slot[c.node] as usize];
                match c.path {
                    Path::Translation => trs.translation = v.truncate(),
                    Path::Rotation => trs.rotation = Quat::from_vec4(v).normalize(),
                    Path::Scale => trs.scale = v.truncate(),
                }
            }
        }
        let mut world = vec![Mat4::IDENTITY; graph.rest.len()];
        for &(node, parent) in &graph.order {
            let rest = graph.rest[node].0;
            let matrix = match slot[node] {
                NOT_POSED => rest,
                k => posed[k as usize].matrix(),
            };
            let parent = parent.map_or(Mat4::IDENTITY, |p| world[p]);
            let posed = parent * matrix;
            world[node] = if posed.is_finite() {
                posed
            } else {
                parent * rest
            };
        }
        world
    }
}

#[cfg(test)]
mod tests {
    use gltf::json;
    use json::accessor::{ComponentType, Type};
    use json::validation::Checked::Valid;

    use super::super::builder::{Doc, bytes, mesh_node};
    use super::super::load_gltf_slice;
    use super::*;
    use spreadlight_render::mesh::primitives::{BoxParams, box_mesh};

    /// A cube on a child node of a parent at x = 10, its translation
    /// animated by `interpolation` from keyframes `times` to `values`.
    fn animated(
        interpolation: json::animation::Interpolation,
        times: &[f32],
        values: &[[f32; 3]],
    ) -> GltfScene {
        let mut doc = Doc::new();
        let mesh = doc.mesh_data("Cube", &box_mesh(BoxParams::default()));
        let child = doc.node(mesh_node(Some(mesh), [0.0; 3], 1.0));
        let parent = doc.node(json::Node {
            children: Some(vec![child]),
            translation: Some([10.0, 0.0, 0.0]),
            ..Default::default()
        });
        doc.scene(vec![parent]);
        let input_view = doc.view(&bytes(times));
        let input = doc.accessor(
            Some(input_view),
            times.len(),
            ComponentType::F32,
            Type::Scalar,
        );
        doc.root.accessors[input.value()].min = Some(json::Value::from(vec![times[0]]));
        doc.root.accessors[input.value()].max =
            Some(json::Value::from(vec![*times.last().unwrap()]));
        let output = doc.floats(values);
        doc.root.push(json::Animation {
            channels: vec![json::animation::Channel {
                sampler: json::Index::new(0),
                target: json::animation::Target {
                    node: child,
                    path: Valid(json::animation::Property::Translation),
                    extensions: None,
                    extras: Default::default(),
                },
                extensions: None,
                extras: Default::default(),
            }],
            samplers: vec![json::animation::Sampler {
                input,
                interpolation: Valid(interpolation),
                output,
                extensions: None,
                extras: Default::default(),
            }],
            name: Some("Slide".into()),
            extensions: None,
            extras: Default::default(),
        });
        load_gltf_slice(&doc.gltf_data_uri(), None).unwrap()
    }

    fn x_at(scene: &GltfScene, time: f32) -> f32 {
        scene.pose(Some(0), time)[0].w_axis.x
    }

    #[test]
    fn linear_and_step_translation_under_a_parent() {
        use json::animation::Interpolation as I;
        let linear = animated(
            I::Linear,
            &[0.0, 1.0, 2.0],
            &[[0.0; 3], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0]],
        );
        assert_eq!(linear.animations[0].name, "Slide");
        assert_eq!(linear.animations[0].duration, 2.0);
        assert_eq!(x_at(&linear, 0.5), 11.0, "parent 10 + half of 2");
        assert_eq!(x_at(&linear, 1.5), 13.0);
        // Looping: 2.5 s is 0.5 s into the next round.
        assert_eq!(x_at(&linear, 2.5), 11.0);
        // No animation: the rest pose.
        assert_eq!(linear.pose(None, 0.5)[0].w_axis.x, 10.0);
        let step = animated(
            I::Step,
            &[0.0, 1.0, 2.0],
            &[[0.0; 3], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0]],
        );
        assert_eq!(x_at(&step, 0.9), 10.0);
        assert_eq!(x_at(&step, 1.1), 12.0);
    }

    #[test]
    fn cubic_spline_passes_through_keys_with_its_tangents() {
        use json::animation::Interpolation as I;
        // (in-tangent, value, out-tangent) per key: 0 -> 3 with zero tangents is smoothstep.
        let values = [
            [0.0; 3],
            [0.0; 3],
            [0.0; 3],
            [0.0; 3],
            [3.0, 0.0, 0.0],
            [0.0; 3],
        ];
        let cubic = animated(I::CubicSpline, &[0.0, 1.0], &values);
        assert_eq!(x_at(&cubic, 0.0), 10.0);
        assert!((x_at(&cubic, 0.5) - 11.5).abs() < 1e-5);
        assert!((x_at(&cubic, 0.25) - (10.0 + 3.0 * 0.15625)).abs() < 1e-5);
        // A channel whose values do not match its keyframes is skipped with a warning.
        let bad = animated(I::CubicSpline, &[0.0, 1.0], &values[..4]);
        assert!(bad.animations[0].channels.is_empty());
        assert!(
            bad.warnings
                .iter()
                .any(|w| w.contains("2 keyframes but 4 values")),
            "{:?}",
            bad.warnings
        );
    }

    #[test]
    fn lights_follow_their_animated_nodes() {
        let scene = load_gltf_slice(&crate::models::sliding_cube(), None).unwrap();
        let at = |time: f32| {
            let world = scene.node_worlds(Some(0), time);
            let (lights, _) = scene.posed_content(&world);
            lights.points[0].1.position
        };
        // Child of the cube (scale 0.5): 1 above it, riding from x = -1 to x = 1.
        assert!(
            (at(0.0) - glam::Vec3::new(-1.0, 1.5, 0.0)).length() < 1e-5,
            "{}",
            at(0.0)
        );
        assert!(
            (at(1.0) - glam::Vec3::new(1.0, 1.5, 0.0)).length() < 1e-5,
            "{}",
            at(1.0)
        );
        assert_eq!(scene.lights.points[0].0, "Lamp");
    }
}

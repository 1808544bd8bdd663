//! Morph targets: per primitive, each target's POSITION, NORMAL and TANGENT
//! deltas; per instance, the default weights (the node's, else the mesh's);
//! and animation `weights` channels. Like skinning, the blend runs on the
//! GPU (`render::geometry::skinning`), before the skin, as glTF orders them.

use glam::Vec3;
use gltf::animation::Interpolation;

use super::{GltfError, Importer};
pub use spreadlight_render::mesh::deform::{MorphTarget, morph_extent};

/// An animation channel of a node's morph weights.
#[derive(Debug, Clone, PartialEq)]
pub struct WeightsChannel {
    pub node: usize,
    pub interpolation: Interpolation,
    pub times: Vec<f32>,
    /// `count` weights per keyframe (three groups per keyframe for cubic
    /// splines: in-tangents, values, out-tangents).
    pub values: Vec<f32>,
    pub count: usize,
}

impl WeightsChannel {
    /// The weights at `time` (held before the first and after the last key).
    pub fn sample(&self, time: f32) -> Vec<f32> {
        let (n, c) = (self.times.len(), self.count);
        let cubic = self.interpolation == Interpolation::CubicSpline;
        let group = |k: usize, part: usize| -> &[f32] {
            let at = if cubic { (3 * k + part) * c } else { k * c };
            &self.values[at..at + c]
        };
        let next = self.times.partition_point(|&t| t <= time);
        if next == 0 {
            return group(0, 1).to_vec();
        }
        if next >= n {
            return group(n - 1, 1).to_vec();
        }
        let k = next - 1;
        let span = self.times[next] - self.times[k];
        let s = if span > 0.0 {
            ((time - self.times[k]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        match self.interpolation {
            Interpolation::Step => group(k, 1).to_vec(),
            Interpolation::Linear => group(k, 1)
                .iter()
                .zip(group(next, 1))
                .map(|(a, b)| a + (b - a) * s)
                .collect(),
            Interpolation::CubicSpline => {
                let (s2, s3) = (s * s, s * s * s);
                (0..c)
                    .map(|i| {
                        group(k, 1)[i] * (2.0 * s3 - 3.0 * s2 + 1.0)
                            + group(k, 2)[i] * span * (s3 - 2.0 * s2 + s)
                            + group(next, 1)[i] * (-2.0 * s3 + 3.0 * s2)
                            + group(next, 0)[i] * span * (s3 - s2)
                    })
                    .collect()
            }
        }
    }
}

impl Importer<'_> {
    /// The primitive's morph targets, their deltas remapped through
    /// `origin` when the loader unwelded the vertices.
    pub(super) fn morph_targets(
        &mut self,
        name: &str,
        primitive: &gltf::Primitive,
        vertices: usize,
        origin: Option<&[u32]>,
    ) -> Result<Vec<MorphTarget>, GltfError> {
        let mut out = Vec::new();
        for (t, target) in primitive.morph_targets().enumerate() {
            let read = |accessor: Option<gltf::Accessor>,
                        what: &str|
             -> Result<Vec<[f32; 3]>, GltfError> {
                let Some(accessor) = accessor else {
                    return Ok(Vec::new());
                };
                let usage = format!("morph target {t} {what}");
                let deltas = self
                    .buffers
                    .read_floats::<3>(&accessor)
                    .map_err(|reason| self.accessor_error(&accessor, &usage, name, reason))?;
                let problem = if deltas.len() != vertices {
                    Some(format!(
                        "{} elements but POSITION has {vertices}",
                        deltas.len()
                    ))
                } else if !deltas.iter().flatten().all(|x| x.is_finite()) {
                    Some("a delta is not finite".to_owned())
                } else {
                    None
                };
                if let Some(reason) = problem {
                    return Err(GltfError::Primitive {
                        path: self.path.to_owned(),
                        primitive: name.to_owned(),
                        reason: format!("{usage}: {reason}"),
                    });
                }
                Ok(match origin {
                    Some(o) => o.iter().map(|&v| deltas[v as usize]).collect(),
                    None => deltas,
                })
            };
            let positions = read(target.positions(), "POSITION")?;
            let normals = read(target.normals(), "NORMAL")?;
            let tangents = read(target.tangents(), "TANGENT")?;
            let extent = positions
                .iter()
                .map(|p| Vec3::from(*p).abs())
                .fold(Vec3::ZERO, Vec3::max);
            out.push(MorphTarget {
                positions,
                normals,
                tangents,
                extent,
            });
        }
        Ok(out)
    }

    /// An animation channel of `node`'s morph weights: `count` per key.
    pub(super) fn weights_channel(
        &mut self,
        what: &str,
        node: &gltf::Node,
        sampler: &gltf::animation::Sampler,
        times: Vec<f32>,
    ) -> Result<Option<WeightsChannel>, GltfError> {
        let count = node
            .mesh()
            .and_then(|m| m.primitives().next())
            .map_or(0, |p| p.morph_targets().count());
        if count == 0 {
            self.warn(format!(
                "{what}: animates morph weights of node {}, which has no morph targets; skipped",
                node.index()
            ));
            return Ok(None);
        }
        let output = sampler.output();
        let values: Vec<f32> = self
            .buffers
            .read_floats::<1>(&output)
            .map_err(|reason| GltfError::Accessor {
                path: self.path.to_owned(),
                index: output.index(),
                usage: format!("keyframes of {what}"),
                reason,
            })?
            .into_iter()
            .map(|[w]| w)
            .collect();
        let interpolation = sampler.interpolation();
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        if times.is_empty() || values.len() != times.len() * per_key * count {
            self.warn(format!(
                "{what}: {} keyframes of {count} weights but {} values; the channel is skipped",
                times.len(),
                values.len()
            ));
            return Ok(None);
        }
        Ok(Some(WeightsChannel {
            node: node.index(),
            interpolation,
            times,
            values,
            count,
        }))
    }
}

//! Light Merge (CookTorrance's quality pin; 0 by default, the exact image):
//! point lights far from a pixel are shaded there as one light per world
//! cube, a one-level cut of a light tree (lightcuts, Walter et al. 2005)
//! that each pixel chooses.
//!
//! The lights are binned into cubes half the merge distance D across. A
//! cube of two or more lights gets one more light: their summed intensity at
//! their luminance-weighted centroid, reaching as far as any of them does.
//! Each member and the merged light carry a band, the centroid and D: a pixel
//! nearer than D to the centroid shades the members, any other pixel the
//! merged light. The assignment (lighting/clusters.wgsl, MERGED) lists each
//! side in the froxels where some point may lie on it (a member where the
//! box's nearest point is within D, the merged light where its farthest is
//! not); the shade (lighting/cook_torrance.wgsl, MERGED) culls a block's
//! list by the block's box the same way and keeps, per pixel, the side the
//! pixel lies on. One comparison decides, so no pixel gets both or neither.
//!
//! A pixel then evaluates its near lights one by one and the far ones a cube
//! at a time: on bench-lights (about 800 lights reach a floor pixel) a merge
//! distance of 2 leaves about 130 near lights and 170 cubes. The error is the
//! far cubes' spread (a member lies up to a cube's diagonal, 0.87 D, from the
//! luminance-weighted centroid, seen from D or more) and the merged reach's
//! window, which fades the sum over the farthest member's reach (with a Light
//! Cutoff, the sum's own cut reach); `spreadlight accuracy lights
//! --merges` measures it. Lights with a shadow, and cubes of one, stay as
//! they are. Only the walks that read a pixel's own froxel list merge
//! (`Walk::merges`): the naive walk reads every light, and the tiled walk
//! culls by depth bins a band does not follow.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use glam::{IVec3, Vec3};

use super::{GpuLight, LightBuffer, LightKind};
use crate::renderer::Renderer;

/// Cubes per merge distance: a cube is D / 2 across.
const CUBES_PER_DISTANCE: f32 = 2.0;

/// Rec. 709 luminance: how much of a light's intensity its centroid weighs.
fn luminance(intensity: [f32; 4]) -> f32 {
    0.2126 * intensity[0] + 0.7152 * intensity[1] + 0.0722 * intensity[2]
}

/// The shortest merge distance: below it, no merging (its square would
/// underflow long before a cube held two distinct lights).
const MIN_DISTANCE: f32 = 1e-6;

/// A light merge distance as the recipe keeps it: a finite distance of
/// [`MIN_DISTANCE`] or more, or 0 (no merging) for anything else.
pub fn light_merge(distance: f32) -> f32 {
    if distance.is_finite() && distance >= MIN_DISTANCE {
        distance
    } else {
        0.0
    }
}

/// Point lights with their cubes' merged lights after them, and each one's
/// band: the centroid of its cube and +D for a member (shaded at pixels
/// nearer than D), -D for a merged light (at D or farther), zeros for a light
/// that is not merged (wherever it reaches).
#[derive(Debug, Clone, PartialEq)]
struct Merged {
    lights: Vec<GpuLight>,
    bands: Vec<[f32; 4]>,
    /// How many merged lights follow the originals.
    cubes: usize,
}

/// Merges `lights` (point lights as uploaded) at `distance` ([`light_merge`]).
fn merge(lights: &[GpuLight], distance: f32) -> Merged {
    let mut bands = vec![[0.0; 4]; lights.len()];
    let mut merged = lights.to_vec();
    let distance = light_merge(distance);
    if distance == 0.0 {
        return Merged {
            lights: merged,
            bands,
            cubes: 0,
        };
    }
    let cube = distance / CUBES_PER_DISTANCE;
    let mut cubes: HashMap<IVec3, Vec<usize>> = HashMap::new();
    for (k, l) in lights.iter().enumerate() {
        let p = Vec3::from_slice(&l.position_range[..3]);
        let shadowed = l.cone[2] >= 0.0;
        let lit = l.position_range[3] > 0.0 && luminance(l.intensity) > 0.0;
        if shadowed || !lit || !p.is_finite() || !luminance(l.intensity).is_finite() {
            continue;
        }
        // Beyond i32's cubes `as` would saturate and bin far-apart lights
        // together: such a light stays apart.
        let at = (p / cube).floor();
        if at.abs().max_element() >= i32::MAX as f32 {
            continue;
        }
        cubes
            .entry(IVec3::new(at.x as i32, at.y as i32, at.z as i32))
            .or_default()
            .push(k);
    }
    // In cube order, so the same lights merge into the same buffer every time.
    let mut members: Vec<(IVec3, Vec<usize>)> =
        cubes.into_iter().filter(|(_, m)| m.len() > 1).collect();
    members.sort_by_key(|(c, _)| (c.z, c.y, c.x));
    let mut count = 0;
    for (_, members) in members {
        let weight: f32 = members
            .iter()
            .map(|&k| luminance(lights[k].intensity))
            .sum();
        let centroid = members
            .iter()
            .map(|&k| {
                Vec3::from_slice(&lights[k].position_range[..3]) * luminance(lights[k].intensity)
            })
            .sum::<Vec3>()
            / weight;
        let mut intensity = [0.0f32; 4];
        let mut reach = 0.0f32;
        for &k in &members {
            let l = &lights[k];
            for (sum, i) in intensity.iter_mut().zip(&l.intensity) {
                *sum += i;
            }
            let offset = Vec3::from_slice(&l.position_range[..3]).distance(centroid);
            reach = reach.max(l.position_range[3] + offset);
        }
        // Finite lights can still sum past f32: such a cube stays as it is,
        // so no infinity or NaN reaches the shade.
        let sum = Vec3::from_slice(&intensity[..3]);
        if !(centroid.is_finite() && sum.is_finite() && reach.is_finite()) {
            continue;
        }
        for &k in &members {
            bands[k] = centroid.extend(distance).to_array();
        }
        count += 1;
        merged.push(GpuLight {
            position_range: centroid.extend(reach).to_array(),
            intensity,
            direction: [0.0, -1.0, 0.0, -1.0],
            cone: [-1.0, 0.0, -1.0, 0.0],
        });
        bands.push(centroid.extend(-distance).to_array());
    }
    Merged {
        lights: merged,
        bands,
        cubes: count,
    }
}

/// One merge: the lights' content hash, the distance's bits, and the merged
/// buffer (`None` where no cube held two lights).
type Made = (u64, u32, Option<Arc<LightBuffer>>);

/// The last merge a node made: kept while its lights and distance stay, so
/// still lights merge once.
#[derive(Default)]
struct Memo(Mutex<Option<Made>>);

impl LightBuffer {
    /// These point lights merged at `distance` ([`light_merge`]), kept under
    /// node `owner` while the lights and the distance stay; `None` where
    /// nothing merges (not points, no distance, no cube of two).
    pub fn merged(
        &self,
        renderer: &Renderer,
        owner: Option<u32>,
        distance: f32,
    ) -> Option<Arc<LightBuffer>> {
        let uploaded = self.uploaded.as_ref()?;
        let distance = light_merge(distance);
        if self.kind != LightKind::Point || distance == 0.0 {
            return None;
        }
        let memo = renderer.state::<Memo>(owner.map_or(u64::MAX, u64::from));
        let mut memo = memo.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((content, bits, kept)) = memo.as_ref()
            && (*content, *bits) == (self.content, distance.to_bits())
        {
            return kept.clone();
        }
        let merged = merge(uploaded, distance);
        if merged.cubes == 0 {
            // Nothing to merge: the lights as they are, and nothing uploaded.
            *memo = Some((self.content, distance.to_bits(), None));
            return None;
        }
        let buffer = Arc::new(LightBuffer {
            kind: LightKind::Point,
            count: merged.lights.len() as u32,
            buffer: renderer.kept_storage(owner, "merged lights", &merged.lights),
            projections: None,
            textures: None,
            content: self.content ^ u64::from(distance.to_bits()).rotate_left(17),
            uploaded: None,
            bands: Some(renderer.kept_storage(owner, "light bands", &merged.bands)),
        });
        *memo = Some((self.content, distance.to_bits(), Some(buffer.clone())));
        Some(buffer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(p: [f32; 3], intensity: [f32; 3], range: f32, shadow: f32) -> GpuLight {
        GpuLight {
            position_range: [p[0], p[1], p[2], range],
            intensity: [intensity[0], intensity[1], intensity[2], 0.0],
            direction: [0.0, -1.0, 0.0, -1.0],
            cone: [-1.0, 0.0, shadow, 0.0],
        }
    }

    #[test]
    fn a_cube_of_lights_adds_their_sum_at_their_centroid_and_bands_them_both_ways() {
        // Cubes of 1 at distance 2: three lights share [0, 1)^3, one is alone.
        let lights = [
            point([0.1, 0.1, 0.1], [1.0, 1.0, 1.0], 5.0, -1.0),
            point([0.9, 0.1, 0.1], [3.0, 3.0, 3.0], 4.0, -1.0),
            point([0.5, 0.9, 0.5], [0.0, 2.0, 0.0], 5.0, -1.0),
            point([5.5, 0.5, 0.5], [1.0, 0.0, 0.0], 5.0, -1.0),
        ];
        let m = merge(&lights, 2.0);
        assert_eq!((m.lights.len(), m.cubes), (5, 1));
        let merged = m.lights[4];
        let centroid = Vec3::from_slice(&merged.position_range[..3]);
        let intensity = Vec3::from_slice(&merged.intensity[..3]);
        let reach = merged.position_range[3];
        assert_eq!(intensity, Vec3::new(4.0, 6.0, 4.0), "the sum of the three");
        // Luminance-weighted: light 1 weighs 3, light 0 weighs 1, light 2 0.7152 * 2.
        let w = [1.0, 3.0, 0.7152 * 2.0];
        let want = (Vec3::splat(0.1) * w[0]
            + Vec3::new(0.9, 0.1, 0.1) * w[1]
            + Vec3::new(0.5, 0.9, 0.5) * w[2])
            / (w[0] + w[1] + w[2]);
        assert!((centroid - want).length() < 1e-5, "{centroid} vs {want}");
        // As far as the farthest-reaching member, from the centroid.
        let far = (0..3)
            .map(|k| {
                Vec3::from_slice(&lights[k].position_range[..3]).distance(centroid)
                    + lights[k].position_range[3]
            })
            .fold(0.0, f32::max);
        assert!((reach - far).abs() < 1e-5);
        for k in 0..3 {
            assert_eq!(m.bands[k], centroid.extend(2.0).to_array(), "member {k}");
        }
        assert_eq!(
            m.bands[4],
            centroid.extend(-2.0).to_array(),
            "the merged light"
        );
        assert_eq!(m.bands[3], [0.0; 4], "a cube of one is not merged");
        assert_eq!(
            &m.lights[..4],
            &lights[..],
            "the originals stay where they were"
        );
    }

    #[test]
    fn shadowed_dark_rangeless_and_non_finite_lights_are_never_merged() {
        let lights = [
            point([0.1, 0.1, 0.1], [1.0; 3], 5.0, 0.0),
            point([0.2, 0.1, 0.1], [0.0; 3], 5.0, -1.0),
            point([0.3, 0.1, 0.1], [1.0; 3], 0.0, -1.0),
            point([f32::NAN, 0.1, 0.1], [1.0; 3], 5.0, -1.0),
            point([0.4, 0.1, 0.1], [f32::INFINITY; 3], 5.0, -1.0),
            point([0.5, 0.1, 0.1], [1.0; 3], 5.0, -1.0),
        ];
        let m = merge(&lights, 2.0);
        assert_eq!(m.cubes, 0, "one mergeable light is a cube of one");
        assert!((0..6).all(|k| m.bands[k] == [0.0; 4]));
        assert_eq!(merge(&lights, 0.0).cubes, 0);
    }

    #[test]
    fn a_cube_whose_sum_overflows_and_lights_beyond_i32s_cubes_stay_apart() {
        // Two finite lights whose sum is infinite; two far lights 1e12 apart
        // that a saturating cube index would bin together.
        let lights = [
            point([0.1, 0.1, 0.1], [3e38, 3e38, 3e38], 5.0, -1.0),
            point([0.2, 0.1, 0.1], [3e38, 3e38, 3e38], 5.0, -1.0),
            point([1e13, 0.1, 0.1], [1.0; 3], 5.0, -1.0),
            point([2e13, 0.1, 0.1], [1.0; 3], 5.0, -1.0),
        ];
        let m = merge(&lights, 2.0);
        assert_eq!(m.cubes, 0, "{m:?}");
        assert!((0..4).all(|k| m.bands[k] == [0.0; 4]));
    }

    #[test]
    fn light_merge_keeps_finite_positive_distances_only() {
        assert_eq!(light_merge(1.5), 1.5);
        for bad in [0.0, 1e-9, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(light_merge(bad), 0.0, "{bad}");
        }
    }
}

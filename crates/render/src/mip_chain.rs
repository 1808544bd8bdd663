//! Mip chains built on the GPU, by compute, each frame they are needed:
//! level 0 copied from a source image, each further level reduced from the
//! one above (a box average for rough refraction's blur, the nearest depth
//! for SSR's hi-z). The texture with every level, and the plan of
//! dispatches that fills it, so that the passes that keep such a chain
//! differ only in their shader's entry points and binding names.
//!
//! The shaders follow one shape: `copy` writes level 0 alone (a 1x1
//! chain), `first` writes levels 0 and 1 from the source, `down` one level
//! from the level above, and `down2`, where a shader has one, two levels a
//! dispatch (a thread per texel of the second makes the texels of the
//! first under it, and keeps them to reduce), and `tail`, where a shader has
//! one, every level from the first of at most [`TAIL_SIDE`] texels a side
//! down to 1x1 in one workgroup (a level a barrier, through workgroup
//! memory, instead of a dispatch a level or two).

use smallvec::SmallVec;

use crate::error::RenderError;
use crate::frame_graph::{Bindings, PassContext, Tex};
use crate::shaders::ShaderKey;

/// A texture of `size` with every mip level down to 1x1.
pub fn texture(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    let (width, height) = (size.0.max(1), size.1.max(1));
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: crate::texture::mips::level_count(width, height),
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// The largest side of the first level a [`MipTail`] makes: its
/// workgroup keeps a level of up to TAIL_SIDE x TAIL_SIDE in workgroup
/// memory.
pub const TAIL_SIDE: u32 = 32;

/// The levels a tail writes at most: a level of TAIL_SIDE a side and every
/// one after it down to 1x1.
pub const TAIL_LEVELS: usize = TAIL_SIDE.ilog2() as usize + 1;

/// A chain shader's entry point that makes every remaining level in one
/// workgroup, and the storage bindings of those levels, first level first.
pub struct MipTail {
    pub entry: &'static str,
    pub outs: [&'static str; TAIL_LEVELS],
}

/// A chain shader's entry points and the names of its bindings.
pub struct MipChainShader {
    /// Copies the source into level 0 (a chain of one level).
    pub copy: &'static str,
    /// Writes levels 0 and 1 from the source.
    pub first: &'static str,
    /// Writes one level from the one above.
    pub down: &'static str,
    /// Writes two levels from the one above them, where the shader has it.
    pub down2: Option<&'static str>,
    /// Writes every level from one of at most TAIL_SIDE a side, where the
    /// shader has it.
    pub tail: Option<MipTail>,
    /// The source image (a declared texture).
    pub source: &'static str,
    /// The level a `down` or `down2` step reads.
    pub level_in: &'static str,
    /// The level a step writes, and the one after it (steps that write two).
    pub out: &'static str,
    pub out_next: &'static str,
}

/// One dispatch of a chain: its entry point and the levels it writes,
/// `first..=last` (one or two, or a tail's); it reads the source image
/// where `first` is 0, else the level above `first`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MipStep {
    pub entry: &'static str,
    pub first: usize,
    pub last: usize,
    /// A tail: one workgroup writes `first..=last`.
    pub tail: bool,
}

impl MipStep {
    /// The level bound to each of a tail's TAIL_LEVELS slots: the levels it
    /// writes, first to last, then, past the chain's end, levels above the
    /// one it reads (bound, never written). Distinct, and never the level
    /// it reads: no level is bound twice or both read and written.
    pub fn tail_slots(&self) -> impl Iterator<Item = usize> + use<> {
        let written = self.first..=self.last;
        let spare = 0..self.first.saturating_sub(1);
        written.chain(spare).take(TAIL_LEVELS)
    }
}

/// Level `m`'s size in a chain whose level 0 is `size`.
fn level_size(size: (u32, u32), m: usize) -> (u32, u32) {
    ((size.0 >> m).max(1), (size.1 >> m).max(1))
}

impl MipChainShader {
    /// The dispatches that fill a chain of `levels` levels whose level 0 is
    /// `size`, in order: two levels a dispatch where the shader has
    /// `down2`, one otherwise, and, where it has a tail and the device
    /// binds `storage_textures` enough, every level from the first of at
    /// most TAIL_SIDE a side in one more.
    pub fn plan(&self, size: (u32, u32), levels: usize, storage_textures: u32) -> Vec<MipStep> {
        let step = |entry, first, last| MipStep {
            entry,
            first,
            last,
            tail: false,
        };
        if levels <= 1 {
            return vec![step(self.copy, 0, 0)];
        }
        // A tail writes down to 1x1: the chain must end there.
        debug_assert_eq!(level_size(size, levels - 1), (1, 1), "a chain ends at 1x1");
        let tail = self.tail_start(size, levels, storage_textures);
        let mut plan = vec![step(self.first, 0, 1)];
        let mut made = 1;
        while made + 1 < levels {
            if let Some((entry, first)) = tail
                && made + 1 == first
            {
                plan.push(MipStep {
                    entry,
                    first,
                    last: levels - 1,
                    tail: true,
                });
                break;
            }
            let next = match self.down2 {
                Some(entry) if made + 2 < levels && tail.is_none_or(|(_, t)| made + 2 < t) => {
                    step(entry, made + 1, made + 2)
                }
                _ => step(self.down, made + 1, made + 1),
            };
            made = next.last;
            plan.push(next);
        }
        plan
    }

    /// Where a tail takes over, if it can: its entry and the first level
    /// it writes, the first of at most TAIL_SIDE a side after level 1. Its
    /// TAIL_LEVELS bindings need as many distinct levels: those it writes,
    /// and, for the ones past the chain's end, levels above the one it
    /// reads (bound, never written).
    fn tail_start(
        &self,
        size: (u32, u32),
        levels: usize,
        storage_textures: u32,
    ) -> Option<(&'static str, usize)> {
        let tail = self.tail.as_ref()?;
        if (storage_textures as usize) < TAIL_LEVELS {
            return None;
        }
        let first = (2..levels).find(|&m| {
            let (w, h) = level_size(size, m);
            w <= TAIL_SIDE && h <= TAIL_SIDE
        })?;
        let written = levels - first;
        let spare = first - 1;
        (written <= TAIL_LEVELS && written + spare >= TAIL_LEVELS).then_some((tail.entry, first))
    }

    /// What `step` binds: the source image or the level above, the level
    /// it writes and, for a step of two, the next.
    fn bindings<'b>(
        &self,
        step: MipStep,
        source: Tex,
        levels: &[wgpu::TextureView],
    ) -> Bindings<'b> {
        let bindings = match step.first {
            0 => Bindings::new().texture(self.source, source),
            m => Bindings::new().view(self.level_in, levels[m - 1].clone()),
        };
        if step.tail {
            let outs = &self.tail.as_ref().expect("a tail step has a tail").outs;
            return outs
                .iter()
                .zip(step.tail_slots())
                .fold(bindings, |b, (name, m)| b.view(name, levels[m].clone()));
        }
        let bindings = bindings.view(self.out, levels[step.first].clone());
        if step.last > step.first {
            bindings.view(self.out_next, levels[step.last].clone())
        } else {
            bindings
        }
    }

    /// Fills every level of a chain of `size` from `source` with `key`'s
    /// entry points, in the open compute pass labelled `label`; `levels`
    /// are the chain's views, level 0 first. Every pipeline and bind group
    /// is made before the first dispatch, so a shader error dispatches
    /// nothing. Returns how many dispatches it took.
    pub fn build(
        &self,
        cx: &mut PassContext<'_>,
        key: &ShaderKey,
        label: &str,
        source: Tex,
        levels: &[wgpu::TextureView],
        size: (u32, u32),
    ) -> Result<u64, RenderError> {
        let storage_textures = cx.gpu.device.limits().max_storage_textures_per_shader_stage;
        let plan = self.plan(size, levels.len(), storage_textures);
        let mut steps = Vec::with_capacity(plan.len());
        for step in plan {
            let bindings = self.bindings(step, source, levels);
            let pipeline = cx.compute_pipeline(key, step.entry)?;
            let groups = cx.bind_groups(key, step.entry, &pipeline, bindings)?;
            // A thread per texel of the last level the step writes; a tail
            // is one workgroup.
            let (w, h) = level_size(size, step.last);
            let groups_xy = if step.tail {
                (1, 1)
            } else {
                (w.div_ceil(8), h.div_ceil(8))
            };
            steps.push((pipeline, groups, groups_xy));
        }
        for (pipeline, groups, (x, y)) in &steps {
            let groups: SmallVec<[&wgpu::BindGroup; 4]> = groups.iter().collect();
            cx.dispatch(label, pipeline, &groups, (*x, *y, 1));
        }
        Ok(steps.len() as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shader(down2: Option<&'static str>) -> MipChainShader {
        MipChainShader {
            copy: "copy",
            first: "first",
            down: "down",
            down2,
            tail: None,
            source: "image",
            level_in: "level_in",
            out: "out",
            out_next: "out_next",
        }
    }

    /// `shader`'s plan for a whole chain whose level 0 is `size`.
    fn plan_for(shader: &MipChainShader, size: (u32, u32), storage: u32) -> Vec<MipStep> {
        let levels = crate::texture::mips::level_count(size.0, size.1) as usize;
        shader.plan(size, levels, storage)
    }

    /// Each step's entry and the levels it writes.
    fn entries(plan: Vec<MipStep>) -> Vec<(&'static str, usize, usize)> {
        plan.into_iter()
            .map(|s| (s.entry, s.first, s.last))
            .collect()
    }

    fn shape(down2: Option<&'static str>, levels: usize) -> Vec<(&'static str, usize, usize)> {
        // A size whose chain has `levels` levels (its width 2^(levels-1)).
        entries(plan_for(&shader(down2), (1 << (levels - 1), 1), 8))
    }

    fn with_tail() -> MipChainShader {
        MipChainShader {
            tail: Some(MipTail {
                entry: "tail",
                outs: ["t0", "t1", "t2", "t3", "t4", "t5"],
            }),
            ..shader(Some("down2"))
        }
    }

    fn tail_shape(size: (u32, u32), storage: u32) -> Vec<(&'static str, usize, usize)> {
        entries(plan_for(&with_tail(), size, storage))
    }

    #[test]
    fn a_tail_makes_every_level_from_the_first_of_32_a_side() {
        // 1920x1080: levels 6 (30x16) to 10 (1x1) in one workgroup.
        assert_eq!(
            tail_shape((1920, 1080), 8),
            vec![
                ("first", 0, 1),
                ("down2", 2, 3),
                ("down2", 4, 5),
                ("tail", 6, 10)
            ]
        );
        // 3840x2160: level 6 (60x33) alone, then 7 (30x16) to 11.
        assert_eq!(
            tail_shape((3840, 2160), 8),
            vec![
                ("first", 0, 1),
                ("down2", 2, 3),
                ("down2", 4, 5),
                ("down", 6, 6),
                ("tail", 7, 11)
            ]
        );
        // 99x61: level 2 (24x15) is already small enough.
        assert_eq!(
            tail_shape((99, 61), 8),
            vec![("first", 0, 1), ("tail", 2, 6)]
        );
        // 130x70: level 2 is 32x17, and the tail writes all six of its
        // slots (levels 2 to 7).
        assert_eq!(
            tail_shape((130, 70), 8),
            vec![("first", 0, 1), ("tail", 2, 7)]
        );
    }

    #[test]
    fn a_tails_slots_are_the_levels_it_writes_then_levels_above_the_one_it_reads() {
        let slots = |size: (u32, u32)| {
            let plan = plan_for(&with_tail(), size, 8);
            let tail = *plan.last().expect("a plan");
            assert!(tail.tail, "{size:?}: {plan:?}");
            assert!(plan[..plan.len() - 1].iter().all(|s| !s.tail));
            (tail.first, tail.tail_slots().collect::<Vec<_>>())
        };
        assert_eq!(slots((1920, 1080)), (6, vec![6, 7, 8, 9, 10, 0]));
        assert_eq!(slots((99, 61)), (2, vec![2, 3, 4, 5, 6, 0]));
        assert_eq!(slots((130, 70)), (2, vec![2, 3, 4, 5, 6, 7]));
        assert_eq!(slots((3840, 2160)), (7, vec![7, 8, 9, 10, 11, 0]));
        for size in [
            (64, 64),
            (601, 7),
            (1920, 1080),
            (3840, 2160),
            (99, 61),
            (130, 70),
        ] {
            let (first, slots) = slots(size);
            let mut distinct = slots.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert_eq!(distinct.len(), TAIL_LEVELS, "{size:?}: {slots:?}");
            assert!(
                !slots.contains(&(first - 1)),
                "{size:?} binds the level it reads"
            );
        }
    }

    #[test]
    fn no_tail_where_the_device_or_the_chain_cannot_bind_its_levels() {
        // Four storage textures (WebGPU's minimum): two levels a dispatch.
        assert_eq!(
            tail_shape((1920, 1080), 4),
            vec![
                ("first", 0, 1),
                ("down2", 2, 3),
                ("down2", 4, 5),
                ("down2", 6, 7),
                ("down2", 8, 9),
                ("down", 10, 10)
            ]
        );
        // 16x16: levels 2 to 4 are three, and only level 0 is spare to bind
        // the other three slots to.
        assert_eq!(
            tail_shape((16, 16), 8),
            vec![("first", 0, 1), ("down2", 2, 3), ("down", 4, 4)]
        );
        // 64x64: level 1 (32x32) is small enough, but a tail reads a level
        // of the chain: from level 2, levels 2 to 6 and level 0 bind its six.
        assert_eq!(
            tail_shape((64, 64), 8),
            vec![("first", 0, 1), ("tail", 2, 6)]
        );
    }

    #[test]
    fn one_level_a_dispatch_without_down2() {
        assert_eq!(shape(None, 1), vec![("copy", 0, 0)]);
        assert_eq!(shape(None, 2), vec![("first", 0, 1)]);
        assert_eq!(
            shape(None, 4),
            vec![("first", 0, 1), ("down", 2, 2), ("down", 3, 3)]
        );
    }

    #[test]
    fn two_levels_a_dispatch_with_down2() {
        assert_eq!(shape(Some("down2"), 1), vec![("copy", 0, 0)]);
        assert_eq!(
            shape(Some("down2"), 3),
            vec![("first", 0, 1), ("down", 2, 2)]
        );
        // 64x36: levels 0..=6; the last odd one out takes `down`.
        assert_eq!(
            shape(Some("down2"), 7),
            vec![
                ("first", 0, 1),
                ("down2", 2, 3),
                ("down2", 4, 5),
                ("down", 6, 6)
            ]
        );
        assert_eq!(
            shape(Some("down2"), 6),
            vec![("first", 0, 1), ("down2", 2, 3), ("down2", 4, 5)]
        );
    }
}

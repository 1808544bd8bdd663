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
//! first under it, and keeps them to reduce).

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
    /// The source image (a declared texture).
    pub source: &'static str,
    /// The level a `down` or `down2` step reads.
    pub level_in: &'static str,
    /// The level a step writes, and the one after it (steps that write two).
    pub out: &'static str,
    pub out_next: &'static str,
}

/// One dispatch of a chain: its entry point and the levels it writes,
/// `first..=last` (one or two); it reads the source image where `first`
/// is 0, else the level above `first`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MipStep {
    pub entry: &'static str,
    pub first: usize,
    pub last: usize,
}

impl MipChainShader {
    /// The dispatches that fill a chain of `levels` levels, in order: two
    /// levels a dispatch where the shader has `down2`, one otherwise.
    pub fn plan(&self, levels: usize) -> Vec<MipStep> {
        let step = |entry, first, last| MipStep { entry, first, last };
        if levels <= 1 {
            return vec![step(self.copy, 0, 0)];
        }
        let mut plan = vec![step(self.first, 0, 1)];
        let mut made = 1;
        while made + 1 < levels {
            let next = match self.down2 {
                Some(entry) if made + 2 < levels => step(entry, made + 1, made + 2),
                _ => step(self.down, made + 1, made + 1),
            };
            made = next.last;
            plan.push(next);
        }
        plan
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
        let plan = self.plan(levels.len());
        let mut steps = Vec::with_capacity(plan.len());
        for step in plan {
            let bindings = self.bindings(step, source, levels);
            let pipeline = cx.compute_pipeline(key, step.entry)?;
            let groups = cx.bind_groups(key, step.entry, &pipeline, bindings)?;
            // A thread per texel of the last level the step writes.
            let (w, h) = ((size.0 >> step.last).max(1), (size.1 >> step.last).max(1));
            steps.push((pipeline, groups, (w.div_ceil(8), h.div_ceil(8))));
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
            source: "image",
            level_in: "level_in",
            out: "out",
            out_next: "out_next",
        }
    }

    fn shape(down2: Option<&'static str>, levels: usize) -> Vec<(&'static str, usize, usize)> {
        shader(down2)
            .plan(levels)
            .into_iter()
            .map(|s| (s.entry, s.first, s.last))
            .collect()
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

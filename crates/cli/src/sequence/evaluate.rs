//! One frame of a sequence, from the patch's runtime: the clock at a fixed
//! frame rate, the sub-frame renders `--samples` averages, and the images of
//! every `Output`, or the errors that failed the frame.

use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec2;
use spreadlight_graph::FrameClock;
use spreadlight_nodes::deferred::mre::SubPixelOffset;
use spreadlight_render::image_io::Encoding;
use spreadlight_render::readback::ImageF32;

use super::accumulate::{Average, pixel_offset, shutter_offset};
use crate::session::Session;

/// How frames are evaluated: the same for a chunk and for a full run, so both agree.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    pub fps: f64,
    /// Frames between two evaluated frames (`--step`).
    pub step: u64,
    /// Sub-frame renders per frame.
    pub samples: u32,
    /// The shutter, open for this fraction of a frame.
    pub shutter: f64,
}

impl Timing {
    /// The time of sub-frame `k` of `frame`, in seconds (never before 0).
    fn time(&self, frame: i128, k: u32) -> f64 {
        let n = self.samples.max(1);
        ((frame as f64 + shutter_offset(k, n, self.shutter)) / self.fps).max(0.0)
    }

    /// The clock of sub-frame `k` of `frame`. Its delta is the time since the
    /// evaluation before it in a run from frame 0 (the previous sub-frame,
    /// or the last one of the previous frame), whichever frame a run starts
    /// at: integrating nodes advance the same in a chunk as in a full run,
    /// and K sub-frames advance them by one frame, not K.
    fn clock(&self, frame: u64, k: u32) -> FrameClock {
        let f = i128::from(frame);
        let time = self.time(f, k);
        let previous = match k {
            0 if frame == 0 => time,
            0 => self.time(f - i128::from(self.step), self.samples.max(1) - 1),
            _ => self.time(f, k - 1),
        };
        FrameClock {
            frame,
            time,
            delta: (time - previous).max(0.0),
        }
    }
}

/// An output's image of one frame (in the order of the outputs given).
pub struct Rendered {
    pub image: ImageF32,
    pub encoding: Encoding,
}

pub struct Evaluator {
    session: Session,
    offset: Option<Arc<SubPixelOffset>>,
    timing: Timing,
    outputs: Vec<String>,
    size: (u32, u32),
    patch: PathBuf,
}

impl Evaluator {
    pub fn new(
        mut session: Session,
        timing: Timing,
        outputs: Vec<String>,
        size: (u32, u32),
        patch: PathBuf,
    ) -> Self {
        let offset = (timing.samples > 1).then(|| {
            let offset = Arc::new(SubPixelOffset::default());
            session.runtime.provide(offset.clone());
            offset
        });
        Evaluator {
            session,
            offset,
            timing,
            outputs,
            size,
            patch,
        }
    }

    pub fn adapter(&self) -> String {
        self.session
            .renderer
            .as_ref()
            .map_or_else(String::new, |r| r.gpu.adapter_name().to_string())
    }

    /// Evaluate `frame` (every sub-frame) and take each output's image (the
    /// average of its sub-frames; one image averages to itself exactly). A
    /// frame fails when a node or pass fails, or an output rendered nothing.
    pub fn frame(&mut self, frame: u64) -> Result<Vec<Rendered>, Vec<String>> {
        let n = self.timing.samples.max(1);
        let pixels = (self.size.0 * self.size.1) as usize;
        let mut sums: Vec<Average> = self.outputs.iter().map(|_| Average::new(pixels)).collect();
        let mut encodings = vec![Encoding::Srgb; self.outputs.len()];
        for k in 0..n {
            if let Some(offset) = &self.offset {
                offset.set(pixel_offset(k, n));
            }
            let clock = self.timing.clock(frame, k);
            self.session.runtime.evaluate(clock);
            let errors = self.session.frame_errors(&self.patch);
            if !errors.is_empty() {
                return Err(errors);
            }
            for (i, name) in self.outputs.iter().enumerate() {
                let Some((image, encoding)) = self.session.images.get(name) else {
                    return Err(vec![format!("the Output named `{name}` rendered nothing")]);
                };
                if (image.width, image.height) != self.size {
                    return Err(vec![format!(
                        "the Output named `{name}` rendered {}x{}, not {}x{}",
                        image.width, image.height, self.size.0, self.size.1
                    )]);
                }
                sums[i].add(&image);
                encodings[i] = encoding;
            }
        }
        if let Some(offset) = &self.offset {
            offset.set(Vec2::ZERO);
        }
        Ok(sums
            .into_iter()
            .zip(encodings)
            .map(|(sum, encoding)| Rendered {
                image: sum.image(self.size),
                encoding,
            })
            .collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_frames_advance_the_clock_by_one_frame_in_all() {
        let timing = Timing {
            fps: 10.0,
            step: 2,
            samples: 4,
            shutter: 0.5,
        };
        let clocks: Vec<FrameClock> = (0..4).map(|k| timing.clock(4, k)).collect();
        let total: f64 = clocks.iter().map(|c| c.delta).sum();
        assert!((total - 0.2).abs() < 1e-12, "{total}");
        assert!((clocks[0].time - (4.0 - 0.1875) / 10.0).abs() < 1e-12);
        assert!(clocks.iter().all(|c| c.frame == 4));
        let plain = Timing {
            samples: 1,
            ..timing
        };
        assert_eq!(plain.clock(0, 0).delta, 0.0);
        assert!((plain.clock(6, 0).delta - 0.2).abs() < 1e-12);
        assert!((plain.clock(6, 0).time - 0.6).abs() < 1e-12);
    }
}

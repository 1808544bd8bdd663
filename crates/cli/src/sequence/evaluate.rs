//! One frame of a sequence, from the patch's runtime: the clock at a fixed
//! frame rate, the sub-frame renders `--samples` averages, and the images of
//! every `Output`, or the errors that failed the frame.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use glam::Vec2;
use spreadlight_graph::FrameClock;
use spreadlight_nodes::deferred::mre::SubPixelOffset;
use spreadlight_render::accumulate::PendingSum;
use spreadlight_render::image_io::Encoding;
use spreadlight_render::readback::{ImageF32, PendingImage, Pixels, Readback};
use spreadlight_render::renderer::Timing as GpuTiming;

use super::accumulate::{Average, pixel_offset, shutter_offset};
use crate::cold_start::ColdStart;
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

/// An output's image of one frame (in the order of the outputs given):
/// the texture's halves when it held them, else 32-bit floats.
pub struct Rendered {
    pub pixels: Pixels,
    pub encoding: Encoding,
}

/// A frame's images, and how long taking them from the GPU took.
pub struct Resolved {
    pub images: Vec<Rendered>,
    /// Blocked until the copies were made and mapped.
    pub waited: Duration,
    /// Taking the rows out of the mapped buffers (and averaging sub-frames).
    pub copied: Duration,
}

/// One sub-frame's image of one output: read back already (an `Output`
/// that writes its own file too), or a copy still on its way.
enum Shot {
    Ready(ImageF32),
    Pending(PendingImage),
}

/// One output's image of a frame, not yet waited for: its sub-frames one
/// by one (averaged on the CPU), or their sum made on the GPU.
enum Frame {
    Shots(Vec<Shot>),
    Sum(PendingSum),
}

/// A frame evaluated and its copies started, not yet waited for: what goes
/// through the pipeline (`pipeline.rs`) to the thread that writes it.
pub struct Captured {
    /// Per output, its image, and its encoding.
    outputs: Vec<(String, Frame, Encoding)>,
    size: (u32, u32),
}

impl Captured {
    /// How many of the outputs' images combine sub-frames: summed on the
    /// GPU, and read back one by one to be averaged on the CPU.
    pub fn combined(&self) -> (u64, u64) {
        let mut counts = (0, 0);
        for (_, frame, _) in &self.outputs {
            match frame {
                Frame::Sum(_) => counts.0 += 1,
                Frame::Shots(shots) if shots.len() > 1 => counts.1 += 1,
                Frame::Shots(_) => {}
            }
        }
        counts
    }

    /// Wait for the copies and average each output's sub-frames. One image
    /// averages to itself exactly, so it is passed on as it is: the same
    /// images, bit for bit, as reading each back at once would give. A sum
    /// made on the GPU is divided by its count (`accumulate/` in render).
    pub fn resolve(self) -> Result<Resolved, Vec<String>> {
        let size = self.size;
        let pixels = size.0 as usize * size.1 as usize;
        let mut resolved = Resolved {
            images: Vec::with_capacity(self.outputs.len()),
            waited: Duration::ZERO,
            copied: Duration::ZERO,
        };
        for (name, frame, encoding) in self.outputs {
            let failed = |e: spreadlight_render::RenderError| {
                vec![format!("the Output named `{name}`: {e}")]
            };
            // As the Output stretches what it reads back at once.
            let stretched = |pixels: Pixels| {
                if pixels.size() == size {
                    pixels
                } else {
                    Pixels::Float(pixels.into_f32().resized(size))
                }
            };
            let mut take = |read: Result<Readback, spreadlight_render::RenderError>| {
                let read = read.map_err(failed)?;
                resolved.waited += read.waited;
                resolved.copied += read.copied;
                Ok::<_, Vec<String>>(stretched(read.pixels))
            };
            let mut shot = |shot: Shot| {
                let pixels = match shot {
                    Shot::Ready(image) => Pixels::Float(image),
                    Shot::Pending(pending) => take(pending.wait_pixels())?,
                };
                if pixels.size() != size {
                    return Err(vec![format!(
                        "the Output named `{name}` rendered {}x{}, not {}x{}",
                        pixels.size().0,
                        pixels.size().1,
                        size.0,
                        size.1
                    )]);
                }
                Ok(pixels)
            };
            let pixels = match frame {
                Frame::Sum(sum) => take(sum.wait_readback())?,
                // Sub-frames are taken one at a time, so K of them never sit in memory at once.
                Frame::Shots(shots) => match <[Shot; 1]>::try_from(shots) {
                    Ok([one]) => shot(one)?,
                    Err(shots) => {
                        let mut sum = Average::new(pixels);
                        for one in shots {
                            sum.add(&shot(one)?.into_f32());
                        }
                        Pixels::Float(sum.image(size))
                    }
                },
            };
            resolved.images.push(Rendered { pixels, encoding });
        }
        Ok(resolved)
    }
}

pub struct Evaluator {
    session: Session,
    offset: Option<Arc<SubPixelOffset>>,
    timing: Timing,
    /// `--sub-frame K`: only sub-frame K's image is kept (not averaged).
    only: Option<u32>,
    outputs: Vec<String>,
    size: (u32, u32),
    patch: PathBuf,
    /// The cold start, measured at the end of the first frame evaluated.
    cold_start: Option<ColdStart>,
}

impl Evaluator {
    pub fn new(
        mut session: Session,
        timing: Timing,
        only: Option<u32>,
        outputs: Vec<String>,
        size: (u32, u32),
        patch: PathBuf,
    ) -> Self {
        let offset = (timing.samples > 1).then(|| {
            let offset = Arc::new(SubPixelOffset::default());
            session.runtime.provide(offset.clone());
            offset
        });
        // Copies are waited for where the frame is written, not in the Output node.
        session.images.set_deferred(true);
        // Sub-frames are added up on the GPU and the sum read back once (the one kept of
        // `--sub-frame` is not summed).
        session
            .images
            .set_accumulating(timing.samples > 1 && only.is_none());
        // No timestamps (nothing reports per-pass times here), so the CPU does not wait for the
        // GPU after every frame: the next frame is recorded while the GPU renders this one.
        if let Some(renderer) = &session.renderer {
            renderer.set_timing(GpuTiming::Off);
        }
        Evaluator {
            session,
            offset,
            timing,
            only,
            outputs,
            size,
            patch,
            cold_start: None,
        }
    }

    /// End the process's use of the GPU without tearing it down, for a
    /// process that ends next (`render` after its last file is written).
    /// What dropping would have done that outlives the process is done
    /// here: the submissions drained, the threads making pipelines ahead
    /// waited for (their pipelines belong in the cache), the pipeline cache
    /// saved, device errors no one reported printed. The rest (the device,
    /// every texture, buffer and pipeline) the driver and the kernel reclaim
    /// when the process exits. Dropping them one by one took 50-60 ms on
    /// the H200 after post.ron's frame was written (docs/benchmarks.md,
    /// "Session 25"). `SPREADLIGHT_TEARDOWN=full` drops them as before.
    pub fn leave(self) {
        if std::env::var("SPREADLIGHT_TEARDOWN").as_deref() == Ok("full") {
            return;
        }
        if let Some(renderer) = &self.session.renderer {
            if let Err(e) = renderer.wait_idle() {
                eprintln!("warning: the GPU's last work did not finish: {e}");
            }
            renderer.shaders().wait_ahead();
            let gpu = &renderer.gpu;
            gpu.print_unreported_errors();
            if let Some(cache) = gpu.disk_pipeline_cache() {
                cache.save_or_warn();
            }
        }
        std::mem::forget(self);
    }

    /// Where the process's time went up to its first frame (None before one).
    pub fn cold_start(&self) -> Option<ColdStart> {
        self.cold_start.clone()
    }

    pub fn adapter(&self) -> String {
        self.session
            .renderer
            .as_ref()
            .map_or_else(String::new, |r| r.gpu.adapter_name().to_string())
    }

    /// Evaluate `frame` (every sub-frame) and start each output's copies.
    /// A frame fails when a node or pass fails, or an output rendered
    /// nothing; [`Captured::resolve`] makes the images.
    pub fn frame(&mut self, frame: u64) -> Result<Captured, Vec<String>> {
        let started = std::time::Instant::now();
        let result = self.evaluate(frame);
        if self.cold_start.is_none() {
            let seconds = started.elapsed().as_secs_f64();
            self.cold_start = Some(ColdStart::now(&self.session, seconds));
            // What the first frame composed, for the next run to compose ahead.
            self.session.remember_permutations(&self.patch);
        }
        result
    }

    fn evaluate(&mut self, frame: u64) -> Result<Captured, Vec<String>> {
        let n = self.timing.samples.max(1);
        let mut outputs: Vec<(String, Vec<Shot>, Encoding)> = self
            .outputs
            .iter()
            .map(|name| (name.clone(), Vec::new(), Encoding::Srgb))
            .collect();
        // Sums a frame that failed half way began are not this frame's.
        self.session.images.restart_sums();
        for k in 0..n {
            if let Some(offset) = &self.offset {
                offset.set(pixel_offset(k, n));
            }
            let clock = self.timing.clock(frame, k);
            // Every Output renders every (sub-)frame, even when nothing it depends on changed:
            // its copy goes to the writer threads, so there is no last image here to use again.
            self.session.runtime.invalidate_sinks();
            self.session.runtime.evaluate(clock);
            let errors = self.session.frame_errors(&self.patch);
            if !errors.is_empty() {
                return Err(errors);
            }
            // `--sub-frame`: the others are rendered all the same (what the nodes remember
            // advances as in a full run), their copies dropped.
            let keep = self.only.is_none_or(|only| only == k);
            for (name, shots, encoding) in &mut outputs {
                let shot = match self.session.images.take_pending(name) {
                    Some((pending, e)) => {
                        *encoding = e;
                        Some(Shot::Pending(pending))
                    }
                    // Added into the output's sum on the GPU (taken below).
                    None if self.session.images.sum_count(name) == k + 1 => None,
                    None => {
                        let Some((image, e)) = self.session.images.get(name) else {
                            return Err(vec![format!(
                                "the Output named `{name}` rendered nothing"
                            )]);
                        };
                        *encoding = e;
                        Some(Shot::Ready(image))
                    }
                };
                if let Some(shot) = shot.filter(|_| keep) {
                    shots.push(shot);
                }
            }
        }
        if let Some(offset) = &self.offset {
            offset.set(Vec2::ZERO);
        }
        let gpu = self.session.renderer.as_ref().map(|r| &r.gpu);
        let mut captured = Vec::with_capacity(outputs.len());
        for (name, shots, encoding) in outputs {
            let sum = gpu.and_then(|gpu| self.session.images.take_sum(&name, gpu));
            let frame = match sum {
                None => Frame::Shots(shots),
                Some(Err(e)) => return Err(vec![format!("the Output named `{name}`: {e}")]),
                Some(Ok((sum, e))) if shots.is_empty() && sum.count() == n => {
                    captured.push((name, Frame::Sum(sum), e));
                    continue;
                }
                Some(Ok((sum, _))) => {
                    return Err(vec![format!(
                        "the Output named `{name}` added {} of {n} sub-frames to its sum and read {} back",
                        sum.count(),
                        shots.len()
                    )]);
                }
            };
            captured.push((name, frame, encoding));
        }
        Ok(Captured {
            outputs: captured,
            size: self.size,
        })
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

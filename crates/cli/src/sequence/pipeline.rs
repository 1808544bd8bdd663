//! Frames in flight. The main thread evaluates frame after frame and only
//! starts each output's copy to the CPU; a pool of threads waits for the
//! copies, averages sub-frames, encodes (PNG or EXR) and writes each file to
//! its temporary name; a second pool syncs the files to the disk (so a
//! writer's core goes on encoding while the disk catches up); the main
//! thread then renames finished, synced frames into place in frame order. So the GPU renders the next frame while this
//! one is read back, encoding uses every core, and the files on disk are
//! still always the first frames of the run, whole (a killed run resumes
//! as before). The bytes are those of a frame rendered on its own: the same
//! images, the same encoder.

use std::borrow::Cow;
use std::collections::{BTreeMap, VecDeque};
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, SyncSender, channel, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use spreadlight_render::image_io::{encode_image, encode_png, halves_to_rgba8, is_exr, to_rgba8};
use spreadlight_render::readback::Pixels;

use super::evaluate::{Captured, Rendered};
use super::exr_pixels::{ExrPixels, encode_half};
use super::files::create_partial;
use super::stages::FrameStages;

/// A frame evaluated, its copies started: for a writer thread.
pub struct Job {
    pub frame: u64,
    pub captured: Captured,
    /// Each output's file, in the order of the outputs.
    pub files: Vec<PathBuf>,
    /// When its evaluation began.
    pub started: Instant,
    /// How EXR files store their pixels.
    pub exr: ExrPixels,
}

/// A frame whose files are written and synced under their temporary names
/// (each temporary file and the file it becomes), or the errors that failed it.
pub struct Finished {
    pub frame: u64,
    pub result: Result<Vec<(PathBuf, PathBuf)>, Vec<String>>,
    pub started: Instant,
    /// Where its time went on the writer and sync threads.
    pub stages: FrameStages,
}

/// A frame written, its files still open to be synced.
struct Unsynced {
    frame: u64,
    result: Result<Vec<(PathBuf, PathBuf, File)>, Vec<String>>,
    started: Instant,
    stages: FrameStages,
}

/// Where a pool hands its results: a channel, bounded or not.
trait Out<R>: Clone + Send + 'static {
    /// False once nobody takes them any more.
    fn put(&self, result: R) -> bool;
}

impl<R: Send + 'static> Out<R> for Sender<R> {
    fn put(&self, result: R) -> bool {
        self.send(result).is_ok()
    }
}

impl<R: Send + 'static> Out<R> for SyncSender<R> {
    fn put(&self, result: R) -> bool {
        self.send(result).is_ok()
    }
}

/// `threads` threads taking work from one queue, each handing its results on.
fn pool<T: Send + 'static, R: Send + 'static>(
    name: &str,
    threads: usize,
    queue: Receiver<T>,
    out: &impl Out<R>,
    work: fn(T) -> R,
) -> anyhow::Result<Vec<JoinHandle<()>>> {
    let queue = Arc::new(Mutex::new(queue));
    (0..threads)
        .map(|i| {
            let queue = queue.clone();
            let out = out.clone();
            let thread = std::thread::Builder::new()
                .name(format!("{name} {i}"))
                .spawn(move || {
                    loop {
                        // The lock is held only while taking a job, not while doing it.
                        let job = queue.lock().unwrap_or_else(|e| e.into_inner()).recv();
                        let Ok(job) = job else { break };
                        if !out.put(work(job)) {
                            break;
                        }
                    }
                })?;
            Ok::<_, anyhow::Error>(thread)
        })
        .collect()
}

pub struct Pipeline {
    jobs: Option<SyncSender<Job>>,
    results: Receiver<Finished>,
    workers: Vec<JoinHandle<()>>,
    /// Frames handed in, not yet handed out, in the order they came.
    order: VecDeque<u64>,
    /// Frames finished before the ones ahead of them.
    arrived: BTreeMap<u64, Finished>,
}

impl Pipeline {
    /// `threads` writer threads; as many frames wait for one, so at most
    /// twice that are encoded or waiting (memory stays bounded however long
    /// the run). As many threads sync written files: they wait on the disk,
    /// not on a core, and what waits for them is files in the page cache,
    /// at most four times `threads` frames (then writers wait: a disk slower
    /// than the encoding holds the run, not its open files).
    pub fn new(threads: usize) -> anyhow::Result<Pipeline> {
        let threads = threads.max(1);
        let (jobs, queue) = sync_channel::<Job>(threads);
        let (written, to_sync) = sync_channel::<Unsynced>(threads * 4);
        let (done, results) = channel();
        // Writers hold the only senders to the syncers: when the last writer ends, they end.
        let mut workers = pool("frame writer", threads, queue, &written, write)?;
        drop(written);
        workers.extend(pool("frame sync", threads, to_sync, &done, sync)?);
        Ok(Pipeline {
            jobs: Some(jobs),
            results,
            workers,
            order: VecDeque::new(),
            arrived: BTreeMap::new(),
        })
    }

    /// Hand a frame to the writers; waits while all are busy and the queue is full.
    pub fn submit(&mut self, job: Job) {
        self.order.push_back(job.frame);
        let (frame, started) = (job.frame, job.started);
        let sent = self.jobs.as_ref().map(|jobs| jobs.send(job));
        if !matches!(sent, Some(Ok(()))) {
            self.arrived.insert(
                frame,
                Finished {
                    frame,
                    result: Err(vec!["the threads that write frames stopped".to_owned()]),
                    started,
                    stages: FrameStages::default(),
                },
            );
        }
    }

    /// A frame that failed before it could be written: handed out in its turn.
    pub fn fail(&mut self, frame: u64, errors: Vec<String>, started: Instant) {
        self.order.push_back(frame);
        self.arrived.insert(
            frame,
            Finished {
                frame,
                result: Err(errors),
                started,
                stages: FrameStages::default(),
            },
        );
    }

    /// The frames finished so far whose turn it is, in the order they were
    /// handed in; `wait`: every frame handed in (the end of the run).
    pub fn finished(&mut self, wait: bool) -> Vec<Finished> {
        let mut out = Vec::new();
        loop {
            while let Some(finished) = self
                .order
                .front()
                .and_then(|frame| self.arrived.remove(frame))
            {
                self.order.pop_front();
                out.push(finished);
            }
            if self.order.is_empty() {
                break;
            }
            let next = if wait {
                self.results.recv().ok()
            } else {
                self.results.try_recv().ok()
            };
            match next {
                Some(finished) => {
                    self.arrived.insert(finished.frame, finished);
                }
                None => break,
            }
        }
        out
    }

    /// Every frame still in flight, in order, once written; the threads end.
    pub fn finish(mut self) -> Vec<Finished> {
        // No more jobs: idle writers end, so a writer that died cannot leave the wait hanging.
        self.jobs = None;
        let mut out = self.finished(true);
        for worker in std::mem::take(&mut self.workers) {
            let _ = worker.join();
        }
        // Frames a writer took and never answered (it panicked): failed, in their turn.
        while let Some(frame) = self.order.pop_front() {
            let finished = self.arrived.remove(&frame).unwrap_or_else(|| Finished {
                frame,
                result: Err(vec!["the thread writing this frame stopped".to_owned()]),
                started: Instant::now(),
                stages: FrameStages::default(),
            });
            out.push(finished);
        }
        out
    }
}

/// On a writer thread: wait for the frame's images, encode each, write it
/// to its temporary file (not yet synced). A frame that fails leaves no
/// temporary file.
fn write(job: Job) -> Unsynced {
    let began = Instant::now();
    let mut stages = FrameStages::default();
    let result = job.captured.resolve().and_then(|resolved| {
        stages.readback_wait = resolved.waited;
        stages.readback_copy = resolved.copied;
        let mut written: Vec<(PathBuf, PathBuf, File)> = Vec::new();
        for (rendered, path) in resolved.images.iter().zip(&job.files) {
            let step = encode(rendered, path, job.exr, &mut stages)
                .map_err(|e| format!("cannot encode {}: {e}", path.display()))
                .and_then(|bytes| {
                    let started = Instant::now();
                    let file = create_partial(path, &bytes)
                        .map_err(|e| format!("cannot write {}: {e}", path.display()));
                    stages.write += started.elapsed();
                    file
                });
            match step {
                Ok((partial, file)) => written.push((partial, path.clone(), file)),
                Err(e) => {
                    for (partial, _, _) in &written {
                        let _ = std::fs::remove_file(partial);
                    }
                    return Err(vec![e]);
                }
            }
        }
        Ok(written)
    });
    stages.busy = began.elapsed();
    Unsynced {
        frame: job.frame,
        result,
        started: job.started,
        stages,
    }
}

/// An output's file as bytes: PNG, or EXR as `--exr` asks; the time into
/// `stages`. The bytes are those of its 32-bit floats whichever the pixels
/// are (`image_io::encode_pixels`).
fn encode(
    rendered: &Rendered,
    path: &Path,
    exr: ExrPixels,
    stages: &mut FrameStages,
) -> Result<Vec<u8>, String> {
    let (width, height) = rendered.pixels.size();
    let started = Instant::now();
    match (is_exr(path), exr) {
        (true, ExrPixels::Half) => {
            let (bytes, spent) = encode_half(&rendered.pixels)?;
            stages.convert += spent.converting;
            stages.compress += spent.compressing;
            Ok(bytes)
        }
        (true, ExrPixels::Float) => {
            let floats = match &rendered.pixels {
                Pixels::Half(image) => Cow::Owned(image.to_f32()),
                Pixels::Float(image) => Cow::Borrowed(image),
            };
            let converted = Instant::now();
            stages.convert += converted - started;
            let bytes = encode_image(&floats, rendered.encoding, true);
            stages.compress += converted.elapsed();
            bytes
        }
        (false, _) => {
            let rgba = match &rendered.pixels {
                Pixels::Half(image) => halves_to_rgba8(image, rendered.encoding),
                Pixels::Float(image) => to_rgba8(image, rendered.encoding),
            };
            let converted = Instant::now();
            stages.convert += converted - started;
            let bytes = encode_png(width, height, &rgba);
            stages.compress += converted.elapsed();
            bytes
        }
    }
}

/// On a sync thread: the frame's files synced to the disk, so a rename
/// never puts a file in place whose bytes a crash could still lose. A file
/// that fails to sync fails its frame; its temporary files are removed.
fn sync(unsynced: Unsynced) -> Finished {
    let mut stages = unsynced.stages;
    let result = unsynced.result.and_then(|files| {
        let started = Instant::now();
        let mut error = None;
        let mut synced = Vec::with_capacity(files.len());
        for (partial, path, file) in files {
            if error.is_none()
                && let Err(e) = file.sync_all()
            {
                error = Some(format!("cannot write {}: {e}", path.display()));
            }
            synced.push((partial, path));
        }
        stages.sync = started.elapsed();
        match error {
            None => Ok(synced),
            Some(e) => {
                for (partial, _) in &synced {
                    let _ = std::fs::remove_file(partial);
                }
                Err(vec![e])
            }
        }
    });
    Finished {
        frame: unsynced.frame,
        result,
        started: unsynced.started,
        stages,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spreadlight_render::image_io::Encoding;
    use spreadlight_render::readback::ImageF16;

    /// Every half there is (NaNs, infinities, subnormals, negatives, past 1), each once in every
    /// channel: a 256x256 image whose channels hold the 65,536 halves, rotated per channel.
    fn every_half() -> ImageF16 {
        let values = (0..65_536u32)
            .flat_map(|i| {
                [0u32, 1, 2, 3].map(|c| half::f16::from_bits(((i + c * 16_411) % 65_536) as u16))
            })
            .collect();
        ImageF16 {
            width: 256,
            height: 256,
            values,
        }
    }

    /// A texture's halves, encoded as they are, make the files their 32-bit floats make, in
    /// every format: PNG in both encodings, 32-bit EXR, `--exr half`.
    #[test]
    fn files_from_halves_are_the_files_of_their_floats() {
        let halves = every_half();
        let floats = halves.to_f32();
        assert_eq!(
            floats.pixels[3],
            [3, 16_414, 32_825, 49_236].map(|b| half::f16::from_bits(b).to_f32())
        );
        for encoding in [Encoding::Srgb, Encoding::Linear] {
            assert_eq!(
                halves_to_rgba8(&halves, encoding),
                to_rgba8(&floats, encoding),
                "{encoding:?}"
            );
            for (name, exr) in [
                ("f.png", ExrPixels::Float),
                ("f.exr", ExrPixels::Float),
                ("f.exr", ExrPixels::Half),
            ] {
                let file = |pixels: Pixels| {
                    let rendered = Rendered { pixels, encoding };
                    let mut stages = FrameStages::default();
                    encode(&rendered, Path::new(name), exr, &mut stages).expect("encodes")
                };
                let (from_halves, from_floats) = (
                    file(Pixels::Half(halves.clone())),
                    file(Pixels::Float(floats.clone())),
                );
                assert!(
                    from_halves == from_floats,
                    "{encoding:?}, {name} {exr:?}: other bytes"
                );
            }
        }
        // A PNG decodes to the 8-bit values it was given.
        let rgba = halves_to_rgba8(&halves, Encoding::Srgb);
        let png = encode_png(256, 256, &rgba).expect("encodes");
        let decoded = image::load_from_memory_with_format(&png, image::ImageFormat::Png)
            .expect("decodes")
            .to_rgba8()
            .into_raw();
        assert!(decoded == rgba, "PNG is lossless");
        assert!(
            encode_png(256, 255, &rgba).is_err(),
            "a buffer of another size"
        );
    }
}

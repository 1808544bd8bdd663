//! Frames in flight. The main thread evaluates frame after frame and only
//! starts each output's copy to the CPU; a pool of threads waits for the
//! copies, averages sub-frames, encodes (PNG or EXR) and writes each file to
//! its temporary name, synced; the main thread then renames finished frames
//! into place in frame order. So the GPU renders the next frame while this
//! one is read back, encoding uses every core, and the files on disk are
//! still always the first frames of the run, whole (a killed run resumes
//! as before). The bytes are those of a frame rendered on its own: the same
//! images, the same encoder.

use std::collections::{BTreeMap, VecDeque};
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, SyncSender, channel, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::Instant;

use spreadlight_render::image_io::{encode_image, is_exr};

use super::evaluate::Captured;
use super::exr_pixels::{ExrPixels, encode_half};
use super::files::write_partial;

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

/// A frame whose files are written under their temporary names (each
/// temporary file and the file it becomes), or the errors that failed it.
pub struct Finished {
    pub frame: u64,
    pub result: Result<Vec<(PathBuf, PathBuf)>, Vec<String>>,
    pub started: Instant,
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
    /// twice that are in flight (memory stays bounded however long the run).
    pub fn new(threads: usize) -> anyhow::Result<Pipeline> {
        let threads = threads.max(1);
        let (jobs, queue) = sync_channel::<Job>(threads);
        let queue = Arc::new(Mutex::new(queue));
        let (done, results) = channel();
        let mut workers = Vec::with_capacity(threads);
        for i in 0..threads {
            let queue = queue.clone();
            let done = done.clone();
            let worker = std::thread::Builder::new()
                .name(format!("frame writer {i}"))
                .spawn(move || {
                    loop {
                        // The lock is held only while taking a job, not while writing it.
                        let job = queue.lock().unwrap_or_else(|e| e.into_inner()).recv();
                        let Ok(job) = job else { break };
                        if done.send(write(job)).is_err() {
                            break;
                        }
                    }
                })?;
            workers.push(worker);
        }
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
            });
            out.push(finished);
        }
        out
    }
}

/// On a writer thread: wait for the frame's images, encode each, write it
/// to its temporary file. A frame that fails leaves no temporary file.
fn write(job: Job) -> Finished {
    let result = job.captured.resolve().and_then(|images| {
        let mut written: Vec<(PathBuf, PathBuf)> = Vec::new();
        for (rendered, path) in images.iter().zip(&job.files) {
            let encoded = match (is_exr(path), job.exr) {
                (true, ExrPixels::Half) => encode_half(&rendered.image),
                (exr, _) => encode_image(&rendered.image, rendered.encoding, exr),
            };
            let step = encoded
                .map_err(|e| format!("cannot encode {}: {e}", path.display()))
                .and_then(|bytes| {
                    write_partial(path, &bytes)
                        .map_err(|e| format!("cannot write {}: {e}", path.display()))
                });
            match step {
                Ok(partial) => written.push((partial, path.clone())),
                Err(e) => {
                    for (partial, _) in &written {
                        let _ = std::fs::remove_file(partial);
                    }
                    return Err(vec![e]);
                }
            }
        }
        Ok(written)
    });
    Finished {
        frame: job.frame,
        result,
        started: job.started,
    }
}

//! Live playback: a source decoding ahead on its own thread.
//!
//! The thread decodes the frames after the last one asked for into a short
//! queue. The caller takes the frame it wants without waiting: when it is
//! ready it shows on time; when the decoder has not got there yet the caller
//! keeps showing what it had (a late frame, counted) and the patch's frame
//! rate does not drop; when the wanted frame is far from where the decoder
//! is (a seek, a loop point, a jump of the clock) the thread restarts there.

use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::Instant;

use crate::error::MediaError;
use crate::frame::{Frame, VideoInfo};
use crate::source::Source;

/// Frames decoded ahead of the one shown (8 MB each at 1080p).
const QUEUE: usize = 6;

/// How far ahead of the decoder a wanted frame may be while the caller
/// waits for it to catch up rather than making it jump.
const CATCH_UP: u64 = 8;

#[derive(Default)]
struct State {
    /// Start decoding here (a jump): set by the caller, taken by the thread.
    restart: Option<u64>,
    looping: bool,
    ready: VecDeque<Arc<Frame>>,
    /// The next frame the thread will decode (none: it reached the end).
    next: Option<u64>,
    error: Option<MediaError>,
    stop: bool,
    /// Decoding done so far: frames and seconds.
    decoded: u64,
    seconds: f64,
}

struct Shared {
    state: Mutex<State>,
    wake: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// What [`DecodeAhead::take`] found.
#[derive(Clone, Debug)]
pub struct Taken {
    /// The frame to show: the one asked for, or the last one shown when it is late.
    pub frame: Option<Arc<Frame>>,
    /// The frame asked for was not decoded yet.
    pub late: bool,
}

/// A source decoding on its own thread (stopped when dropped).
pub struct DecodeAhead {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    info: VideoInfo,
    shown: Option<Arc<Frame>>,
}

impl DecodeAhead {
    pub fn new(source: Source) -> Self {
        let info = source.info();
        let shared = Arc::new(Shared {
            state: Mutex::new(State::default()),
            wake: Condvar::new(),
        });
        let inner = shared.clone();
        let thread = std::thread::Builder::new()
            .name("spreadlight video decode".to_owned())
            .spawn(move || decode(source, &inner))
            .ok();
        DecodeAhead {
            shared,
            thread,
            info,
            shown: None,
        }
    }

    pub fn info(&self) -> VideoInfo {
        self.info
    }

    /// Frames decoded so far and the seconds the thread spent on them.
    pub fn cost(&self) -> (u64, f64) {
        let s = self.shared.lock();
        (s.decoded, s.seconds)
    }

    /// Frame `index` if it is decoded, else the last frame shown (late).
    /// `looping`: the frame after the last is the first.
    pub fn take(&mut self, index: u64, looping: bool) -> Result<Taken, MediaError> {
        if let Some(shown) = self.shown.as_ref().filter(|f| f.index == index) {
            return Ok(Taken {
                frame: Some(shown.clone()),
                late: false,
            });
        }
        let frames = self.info.frames.max(1);
        let mut s = self.shared.lock();
        if let Some(e) = &s.error {
            return Err(e.clone());
        }
        s.looping = looping;
        let found = if s.restart.is_none() {
            s.ready.iter().position(|f| f.index == index)
        } else {
            None
        };
        let taken = match found {
            Some(at) => {
                s.ready.drain(..at);
                s.ready.pop_front()
            }
            None => {
                // Still on its way (the decoder is a few frames behind), or
                // somewhere else: start over there.
                let distance = s.next.map(|next| {
                    if looping {
                        (index + frames - next % frames) % frames
                    } else {
                        index.wrapping_sub(next)
                    }
                });
                let behind_us = s.ready.back().is_none_or(|f| {
                    let d = if looping {
                        (index + frames - f.index % frames) % frames
                    } else {
                        index.wrapping_sub(f.index)
                    };
                    d <= CATCH_UP
                });
                match distance {
                    Some(d) if d <= CATCH_UP && behind_us && s.restart.is_none() => {
                        s.ready.clear();
                    }
                    _ => {
                        s.ready.clear();
                        s.restart = Some(index);
                    }
                }
                None
            }
        };
        drop(s);
        self.shared.wake.notify_all();
        let late = taken.is_none();
        if let Some(frame) = taken {
            self.shown = Some(frame);
        }
        Ok(Taken {
            frame: self.shown.clone(),
            late,
        })
    }
}

impl Drop for DecodeAhead {
    fn drop(&mut self) {
        self.shared.lock().stop = true;
        self.shared.wake.notify_all();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn decode(mut source: Source, shared: &Shared) {
    let frames = source.info().frames.max(1);
    loop {
        let index = {
            let s = shared.lock();
            let mut s = shared
                .wake
                .wait_while(s, |s| {
                    !s.stop
                        && s.restart.is_none()
                        && (s.next.is_none() || s.ready.len() >= QUEUE || s.error.is_some())
                })
                .unwrap_or_else(|e| e.into_inner());
            if s.stop {
                return;
            }
            if let Some(at) = s.restart.take() {
                s.ready.clear();
                s.error = None;
                s.next = Some(at);
            }
            match s.next {
                Some(index) => index,
                None => continue,
            }
        };
        let started = Instant::now();
        let result = source.frame(index);
        let seconds = started.elapsed().as_secs_f64();
        let mut s = shared.lock();
        s.decoded += 1;
        s.seconds += seconds;
        if s.restart.is_some() {
            continue;
        }
        match result {
            Ok(frame) => {
                s.ready.push_back(frame);
                s.next = if index + 1 < frames {
                    Some(index + 1)
                } else if s.looping {
                    Some(0)
                } else {
                    None
                };
            }
            Err(e) => {
                s.error = Some(e);
                s.next = None;
            }
        }
    }
}

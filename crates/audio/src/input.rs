//! Live input from the default capture device through cpal (ALSA on Linux).
//!
//! The device's callback writes into a ring of the latest seconds, mixed to
//! mono; each frame the node takes a snapshot of it as an [`AudioWindow`].
//! cpal's stream must stay on the thread that made it on some systems, so a
//! thread of its own holds it until the input is dropped. A machine without
//! a capture device (a CI machine, a server) gets [`AudioError::NoDevice`].

use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
use cpal::{FromSample, SampleFormat};

use crate::error::AudioError;
use crate::window::AudioWindow;

/// The latest samples, and how many arrived in all.
#[derive(Debug)]
struct Ring {
    samples: Vec<f32>,
    /// Where the next sample goes.
    next: usize,
    total: i64,
}

impl Ring {
    fn push(&mut self, sample: f32) {
        let cap = self.samples.len();
        if cap == 0 {
            return;
        }
        self.samples[self.next] = sample;
        self.next = (self.next + 1) % cap;
        self.total += 1;
    }

    /// Oldest first: the samples received, up to the ring's length.
    fn ordered(&self) -> Vec<f32> {
        let cap = self.samples.len();
        let held = (self.total.max(0) as usize).min(cap);
        let start = (self.next + cap - held) % cap.max(1);
        (0..held).map(|k| self.samples[(start + k) % cap]).collect()
    }
}

/// An open capture device.
#[derive(Debug)]
pub struct LiveInput {
    ring: Arc<Mutex<Ring>>,
    rate: u32,
    name: String,
    stop: Option<mpsc::Sender<()>>,
    thread: Option<JoinHandle<()>>,
}

impl LiveInput {
    /// Open the default capture device, keeping the latest `seconds`.
    pub fn open_default(seconds: f32) -> Result<LiveInput, AudioError> {
        let (opened_tx, opened_rx) = mpsc::channel();
        let (stop_tx, stop_rx) = mpsc::channel::<()>();
        let thread = std::thread::Builder::new()
            .name("spreadlight audio in".into())
            .spawn(move || match open_stream(seconds) {
                Ok((stream, ring, rate, name)) => {
                    let _ = opened_tx.send(Ok((ring, rate, name)));
                    // Hold the stream until the input is dropped.
                    let _ = stop_rx.recv();
                    drop(stream);
                }
                Err(e) => {
                    let _ = opened_tx.send(Err(e));
                }
            })
            .map_err(|e| AudioError::NoDevice(format!("cannot start the input thread: {e}")))?;
        let opened = opened_rx
            .recv()
            .map_err(|_| AudioError::NoDevice("the input thread stopped".into()))?;
        match opened {
            Ok((ring, rate, name)) => Ok(LiveInput {
                ring,
                rate,
                name,
                stop: Some(stop_tx),
                thread: Some(thread),
            }),
            Err(e) => {
                let _ = thread.join();
                Err(e)
            }
        }
    }

    pub fn rate(&self) -> u32 {
        self.rate
    }

    /// The device's name, as the system gives it.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What has arrived so far, up to the ring's length, ending now.
    pub fn window(&self) -> AudioWindow {
        let ring = self.ring.lock().unwrap_or_else(|e| e.into_inner());
        AudioWindow::live(Arc::from(ring.ordered()), self.rate, ring.total)
    }
}

impl Drop for LiveInput {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

type Opened = (cpal::Stream, Arc<Mutex<Ring>>, u32, String);

fn open_stream(seconds: f32) -> Result<Opened, AudioError> {
    let host = cpal::default_host();
    let device = host
        .default_input_device()
        .ok_or_else(|| AudioError::NoDevice("the system has no capture device".into()))?;
    let name = device
        .description()
        .map_or_else(|_| "default".to_owned(), |d| d.to_string());
    let supported = device
        .default_input_config()
        .map_err(|e| AudioError::NoDevice(format!("`{name}` cannot capture: {e}")))?;
    let config = supported.config();
    let (rate, channels) = (config.sample_rate, usize::from(config.channels).max(1));
    let ring = Arc::new(Mutex::new(Ring {
        samples: vec![0.0; (seconds.max(0.1) * rate as f32) as usize],
        next: 0,
        total: 0,
    }));
    let writer = ring.clone();
    let stream = device
        .build_input_stream_raw(
            config,
            supported.sample_format(),
            move |data: &cpal::Data, _: &cpal::InputCallbackInfo| {
                let mut ring = writer.lock().unwrap_or_else(|e| e.into_inner());
                match data.sample_format() {
                    SampleFormat::F32 => mix::<f32>(data, channels, &mut ring),
                    SampleFormat::I16 => mix::<i16>(data, channels, &mut ring),
                    SampleFormat::I32 => mix::<i32>(data, channels, &mut ring),
                    SampleFormat::U16 => mix::<u16>(data, channels, &mut ring),
                    // Formats no capture device here offers: silence rather than a panic.
                    _ => {}
                }
            },
            // Errors after the start (a device unplugged) leave the ring as it was.
            |_| {},
            None,
        )
        .map_err(|e| AudioError::NoDevice(format!("`{name}` cannot capture: {e}")))?;
    stream
        .play()
        .map_err(|e| AudioError::NoDevice(format!("`{name}` does not start: {e}")))?;
    Ok((stream, ring, rate, name))
}

/// Mix interleaved `data` of `channels` to mono into `ring`.
fn mix<T>(data: &cpal::Data, channels: usize, ring: &mut Ring)
where
    T: cpal::SizedSample,
    f32: FromSample<T>,
{
    let Some(samples) = data.as_slice::<T>() else {
        return;
    };
    let scale = 1.0 / channels as f32;
    for frame in samples.chunks_exact(channels) {
        let sum: f32 = frame.iter().map(|s| s.to_sample::<f32>()).sum();
        ring.push(sum * scale);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ring_keeps_the_latest_samples_in_order() {
        let mut ring = Ring {
            samples: vec![0.0; 3],
            next: 0,
            total: 0,
        };
        ring.push(1.0);
        assert_eq!(ring.ordered(), [1.0]);
        for s in [2.0, 3.0, 4.0, 5.0] {
            ring.push(s);
        }
        assert_eq!(ring.ordered(), [3.0, 4.0, 5.0]);
        assert_eq!(ring.total, 5);
    }

    /// Either the machine has a capture device, or opening says there is none.
    #[test]
    fn opening_the_default_input_works_or_says_there_is_no_device() {
        match LiveInput::open_default(0.5) {
            Ok(input) => assert!(input.rate() > 0),
            Err(e) => {
                assert!(matches!(e, AudioError::NoDevice(_)), "{e}");
                assert!(e.to_string().starts_with("no audio device"), "{e}");
            }
        }
    }
}

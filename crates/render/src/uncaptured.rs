//! Device errors that no error scope caught.
//!
//! wgpu's default handler for such an error panics. Here that is bad input
//! more often than a bug (a texture past the adapter's limits, an image
//! file's texture read back), so every [`GpuContext`](crate::GpuContext)
//! installs [`UncapturedErrors`] instead: the error is kept until a host
//! takes it ([`GpuContext::take_uncaptured_errors`](crate::GpuContext::take_uncaptured_errors))
//! and fails the node or frame it happened in, like any other error.
//! Nothing is lost silently: errors never taken are printed when the
//! device (which holds the handler) goes.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// Device errors no error scope caught, kept (up to [`UncapturedErrors::KEPT`])
/// until taken.
#[derive(Default)]
pub struct UncapturedErrors {
    /// The errors kept, and how many more came.
    errors: Mutex<(Vec<String>, usize)>,
    /// Whether any came since the last take: looked at after every node,
    /// so without the lock.
    pending: AtomicBool,
}

impl UncapturedErrors {
    /// Errors kept between takes; later ones are only counted.
    pub const KEPT: usize = 8;

    /// What the device's uncaptured-error handler calls.
    pub(crate) fn record(&self, error: &wgpu::Error) {
        let mut guard = self.errors.lock().unwrap_or_else(|e| e.into_inner());
        let (kept, more) = &mut *guard;
        if kept.len() < Self::KEPT {
            kept.push(error_text(error));
        } else {
            *more += 1;
        }
        self.pending.store(true, Ordering::Release);
    }

    /// The errors recorded since the last take, oldest first, and a line
    /// counting those past [`UncapturedErrors::KEPT`].
    pub fn take(&self) -> Vec<String> {
        if !self.pending.swap(false, Ordering::AcqRel) {
            return Vec::new();
        }
        let (mut errors, more) =
            std::mem::take(&mut *self.errors.lock().unwrap_or_else(|e| e.into_inner()));
        if more > 0 {
            errors.push(format!("and {more} more GPU error(s)"));
        }
        errors
    }

    /// Print on stderr what no host took: the last word on errors a
    /// process would otherwise lose (dropped, or left without dropping).
    pub fn print_unreported(&self) {
        for error in self.take() {
            eprintln!("GPU error no one reported: {error}");
        }
    }
}

impl Drop for UncapturedErrors {
    fn drop(&mut self) {
        self.print_unreported();
    }
}

/// A wgpu error on one line. A validation error's description holds its
/// causes (which usage flag or limit it was); out of memory has a source.
pub fn error_text(error: &wgpu::Error) -> String {
    let text = match error {
        wgpu::Error::OutOfMemory { source } => format!("out of GPU memory: {source}"),
        other => other.to_string(),
    };
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

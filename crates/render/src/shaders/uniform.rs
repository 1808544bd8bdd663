//! A uniform buffer of one Rust struct: its size comes from the struct, and
//! a write takes the struct, not a slice of words counted by hand. The
//! struct's WGSL twin is checked by a layout test (`assert_wgsl_layout!`).

use std::marker::PhantomData;

/// A buffer holding one `T` (`#[repr(C)]`, `Pod`), bound as a uniform.
pub struct Uniform<T> {
    buffer: wgpu::Buffer,
    value: PhantomData<fn(T)>,
}

impl<T: bytemuck::Pod> Uniform<T> {
    /// The buffer's size in bytes.
    pub const SIZE: u64 = std::mem::size_of::<T>() as u64;

    /// A buffer made for a `T` (at least [`Uniform::SIZE`] bytes, COPY_DST).
    pub fn new(buffer: wgpu::Buffer) -> Self {
        debug_assert!(
            buffer.size() >= Self::SIZE,
            "a uniform smaller than its struct"
        );
        Uniform {
            buffer,
            value: PhantomData,
        }
    }

    /// Upload `value`, ahead of this frame's submission.
    pub fn write(&self, queue: &wgpu::Queue, value: &T) {
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(value));
    }

    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

//! Buffers recipes keep across their re-creation, by owner node and label:
//! uniforms and storage written only where their bytes changed, so the bind
//! groups over them are reused from frame to frame, and scratch buffers.

use rustc_hash::FxHashMap;

use super::Renderer;

/// A kept buffer's name: the node that owns it, what it is, and which one
/// of several of the same kind (a G-buffer's layers, a rasterizer's batches).
pub(super) type KeptKey = (u32, &'static str, u32);

pub(super) struct KeptBuffer {
    buffer: wgpu::Buffer,
    /// What `Renderer::kept_init` last wrote (empty for scratch buffers).
    contents: Vec<u8>,
}

/// The buffer kept under `key` if it `fits`, else `make()` kept in its
/// place; true when it was made now.
fn kept_entry(
    kept: &mut FxHashMap<KeptKey, KeptBuffer>,
    key: KeptKey,
    fits: impl Fn(&KeptBuffer) -> bool,
    make: impl FnOnce() -> wgpu::Buffer,
) -> (&mut KeptBuffer, bool) {
    use std::collections::hash_map::Entry;
    match kept.entry(key) {
        Entry::Occupied(o) if fits(o.get()) => (o.into_mut(), false),
        Entry::Occupied(mut o) => {
            o.insert(KeptBuffer {
                buffer: make(),
                contents: Vec::new(),
            });
            (o.into_mut(), true)
        }
        Entry::Vacant(v) => (
            v.insert(KeptBuffer {
                buffer: make(),
                contents: Vec::new(),
            }),
            true,
        ),
    }
}

/// The range of `new` that differs from `old` (of the same length), widened
/// to 4-byte boundaries as buffer writes must be; None if nothing differs.
fn changed_span(old: &[u8], new: &[u8]) -> Option<(usize, usize)> {
    // Chunks compare as slices (memcmp), then bytes within the chunk found.
    const CHUNK: usize = 256;
    let chunk = old
        .chunks(CHUNK)
        .zip(new.chunks(CHUNK))
        .position(|(a, b)| a != b)?;
    let from = chunk * CHUNK;
    let first = from
        + old[from..]
            .iter()
            .zip(&new[from..])
            .position(|(a, b)| a != b)?;
    let chunk = old
        .rchunks(CHUNK)
        .zip(new.rchunks(CHUNK))
        .position(|(a, b)| a != b)?;
    let to = old.len() - chunk * CHUNK;
    let last = old[..to]
        .iter()
        .zip(&new[..to])
        .rposition(|(a, b)| a != b)?;
    let align = wgpu::COPY_BUFFER_ALIGNMENT as usize;
    let start = first / align * align;
    let end = (last + 1).div_ceil(align) * align;
    // A length off the alignment (not made here) is written whole, as before.
    if end > new.len() {
        return Some((0, new.len()));
    }
    Some((start, end))
}

/// Kept-buffer writes since the last frame graph ran (the frame report's counters).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Uploads {
    /// Writes made ("uniform uploads").
    pub made: u64,
    /// Writes skipped: nothing had changed ("uniform uploads skipped").
    pub skipped: u64,
    /// Bytes written ("uniform bytes uploaded").
    pub bytes: u64,
    /// Bytes compared with what was written before ("kept bytes compared").
    pub compared: u64,
}

impl Renderer {
    /// A uniform buffer holding `bytes` for node `owner`'s `label`: the same
    /// buffer each time the node's recipe is made again, written only when
    /// the bytes changed (counted: "uniform uploads", "uniform uploads
    /// skipped"), so bind groups over it are reused from frame to frame.
    /// One (owner, label) must name one buffer per frame: a node making
    /// several recipes gives each its own label. Without an owner, a new buffer.
    pub fn uniform(&self, owner: Option<u32>, label: &'static str, bytes: &[u8]) -> wgpu::Buffer {
        self.kept_init(
            owner,
            label,
            bytes,
            wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        )
    }

    /// A kept uniform of one `T`, written each frame ([`Renderer::kept_buffer`]).
    pub fn kept_uniform<T: bytemuck::Pod>(
        &self,
        owner: Option<u32>,
        label: &'static str,
    ) -> crate::shaders::Uniform<T> {
        let usage = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let size = crate::shaders::Uniform::<T>::SIZE;
        crate::shaders::Uniform::new(self.kept_buffer(owner, label, size, usage))
    }

    /// A kept storage buffer of `items` ([`Renderer::kept_init`]); one
    /// zeroed item when there are none, as a storage binding cannot be
    /// empty (the caller's count says there are none).
    pub fn kept_storage<T: bytemuck::Pod>(
        &self,
        owner: Option<u32>,
        label: &'static str,
        items: &[T],
    ) -> wgpu::Buffer {
        let none = [T::zeroed()];
        let items = if items.is_empty() { &none[..] } else { items };
        self.kept_init(
            owner,
            label,
            bytemuck::cast_slice(items),
            wgpu::BufferUsages::STORAGE,
        )
    }

    /// [`Renderer::uniform`] for any usage (COPY_DST is added): storage
    /// buffers such as a G-buffer's instances, kept and written on change.
    pub fn kept_init(
        &self,
        owner: Option<u32>,
        label: &'static str,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        self.kept_init_at(owner, label, 0, bytes, usage)
    }

    /// A temporal pass's "history was reset" flag as two kept uniforms
    /// (`vec4<u32>` with x = 0, then x = 1), so a pass binds
    /// `flags[usize::from(fresh)]` and its bind groups stay the same
    /// buffers from frame to frame whichever it is.
    pub fn kept_flags(&self, owner: Option<u32>, label: &'static str) -> [wgpu::Buffer; 2] {
        [0u32, 1].map(|flag| {
            self.kept_init_at(
                owner,
                label,
                flag,
                bytemuck::cast_slice(&[flag, 0, 0, 0]),
                wgpu::BufferUsages::UNIFORM,
            )
        })
    }

    /// [`Renderer::kept_init`] for the `index`th of several buffers of one
    /// kind that one recipe keeps (a G-buffer's layer records, a rasterizer's
    /// batches): each keeps its own buffer, so none overwrites another.
    pub fn kept_init_at(
        &self,
        owner: Option<u32>,
        label: &'static str,
        index: u32,
        bytes: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let fresh = || {
            wgpu::util::DeviceExt::create_buffer_init(
                &self.gpu.device,
                &wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage,
                },
            )
        };
        let Some(owner) = owner else {
            return fresh();
        };
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let (k, made) = kept_entry(
            &mut kept,
            (owner, label, index),
            |k| k.buffer.usage() == usage && k.contents.len() == bytes.len(),
            fresh,
        );
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        if made {
            k.contents = bytes.to_vec();
            uploads.made += 1;
            uploads.bytes += bytes.len() as u64;
        } else if !self.write_changed(&mut uploads, &k.buffer, 0, &mut k.contents, bytes) {
            uploads.skipped += 1;
        }
        k.buffer.clone()
    }

    /// Compare `bytes` with `contents`, what this last wrote at `offset` in
    /// `buffer`, and write only the span that changed (one moving instance
    /// among a thousand still ones writes its 224 bytes, not the buffer),
    /// keeping `contents` up to date; counted. Whether anything was written.
    fn write_changed(
        &self,
        uploads: &mut Uploads,
        buffer: &wgpu::Buffer,
        offset: usize,
        contents: &mut [u8],
        bytes: &[u8],
    ) -> bool {
        uploads.compared += bytes.len() as u64;
        let Some((start, end)) = changed_span(contents, bytes) else {
            return false;
        };
        self.write_whole(uploads, buffer, offset + start, &bytes[start..end]);
        contents[start..end].copy_from_slice(&bytes[start..end]);
        true
    }

    /// Write `bytes` at `offset` in `buffer`, counted as one upload.
    fn write_whole(
        &self,
        uploads: &mut Uploads,
        buffer: &wgpu::Buffer,
        offset: usize,
        bytes: &[u8],
    ) {
        self.gpu.queue.write_buffer(buffer, offset as u64, bytes);
        uploads.made += 1;
        uploads.bytes += bytes.len() as u64;
    }

    /// [`Renderer::kept_init`] for contents laid out as `parts` one after
    /// another (a G-buffer's layers), where `unchanged[i]` says that part `i`
    /// holds the bytes this wrote at the same offset last time: those are
    /// neither compared nor written, so one moving layer among a thousand
    /// still instances compares its own bytes, not ~230 KB. A buffer made
    /// now (new, or another length) is written whole.
    pub fn kept_init_parts(
        &self,
        owner: Option<u32>,
        label: &'static str,
        parts: &[&[u8]],
        unchanged: &[bool],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let len = parts.iter().map(|p| p.len()).sum::<usize>();
        let usage = usage | wgpu::BufferUsages::COPY_DST;
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let Some(k) = owner
            .and_then(|owner| kept.get_mut(&(owner, label, 0)))
            .filter(|k| k.buffer.usage() == usage && k.contents.len() == len)
        else {
            drop(kept);
            return self.kept_init(owner, label, &parts.concat(), usage);
        };
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        let align = wgpu::COPY_BUFFER_ALIGNMENT as usize;
        let (mut offset, mut wrote) = (0, false);
        for (i, part) in parts.iter().enumerate() {
            let at = offset;
            offset += part.len();
            if unchanged.get(i).copied().unwrap_or(false) {
                continue;
            }
            if at % align != 0 || part.len() % align != 0 {
                // Parts off the 4-byte grid (not made here): when one
                // changed, all of it, once.
                uploads.compared += part.len() as u64;
                if k.contents[at..offset] == **part {
                    continue;
                }
                let all = parts.concat();
                self.write_whole(&mut uploads, &k.buffer, 0, &all);
                k.contents = all;
                wrote = true;
                break;
            }
            wrote |= self.write_changed(
                &mut uploads,
                &k.buffer,
                at,
                &mut k.contents[at..offset],
                part,
            );
        }
        if !wrote {
            uploads.skipped += 1;
        }
        k.buffer.clone()
    }

    /// A buffer of `size` bytes and `usage` that node `owner`'s recipes keep
    /// under `label` across their re-creation (scratch a pass fills each
    /// frame, such as the compute rasterizer's 64-bit visibility buffer).
    /// Its contents are whatever the last frame left. Without an owner, a new one.
    pub fn kept_buffer(
        &self,
        owner: Option<u32>,
        label: &'static str,
        size: u64,
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let fresh = || {
            self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let Some(owner) = owner else {
            return fresh();
        };
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let fits = |k: &KeptBuffer| k.buffer.usage() == usage && k.buffer.size() == size;
        kept_entry(&mut kept, (owner, label, 0), fits, fresh)
            .0
            .buffer
            .clone()
    }

    /// Write `bytes` at the start of the buffer kept under node `owner`'s
    /// `label` ([`Renderer::kept_buffer`]), only the bytes that differ from
    /// what this last wrote there (counted as [`Renderer::uniform`]'s
    /// uploads): a recipe that fills its kept buffer as it declares, such as
    /// the G-buffer's camera, skips the write when nothing moved. A buffer
    /// that is not the one kept there (no owner, or replaced) is written whole.
    pub fn write_kept(
        &self,
        owner: Option<u32>,
        label: &'static str,
        buffer: &wgpu::Buffer,
        bytes: &[u8],
    ) {
        // The kept buffers' lock first, then the counters', as everywhere.
        let mut kept = self.kept.lock().unwrap_or_else(|e| e.into_inner());
        let mut uploads = self.uploads.lock().unwrap_or_else(|e| e.into_inner());
        let entry = owner
            .and_then(|owner| kept.get_mut(&(owner, label, 0)))
            .filter(|k| k.buffer == *buffer);
        match entry {
            Some(k) if k.contents.len() == bytes.len() => {
                if !self.write_changed(&mut uploads, buffer, 0, &mut k.contents, bytes) {
                    uploads.skipped += 1;
                }
            }
            Some(k) => {
                k.contents = bytes.to_vec();
                self.write_whole(&mut uploads, buffer, 0, bytes);
            }
            None => self.write_whole(&mut uploads, buffer, 0, bytes),
        }
    }

    /// Kept-buffer writes made and skipped, the bytes written and compared,
    /// since the last call (the frame report's counters).
    pub(crate) fn take_uploads(&self) -> Uploads {
        std::mem::take(&mut *self.uploads.lock().unwrap_or_else(|e| e.into_inner()))
    }
}

#[cfg(test)]
mod tests {
    use super::changed_span;

    #[test]
    fn only_the_changed_bytes_are_written_on_4_byte_boundaries() {
        let old = vec![0u8; 1000];
        let mut new = old.clone();
        assert_eq!(changed_span(&old, &new), None);
        new[517] = 1;
        new[600] = 2;
        assert_eq!(changed_span(&old, &new), Some((516, 604)));
        new[0] = 3;
        new[999] = 4;
        assert_eq!(changed_span(&old, &new), Some((0, 1000)));
        // A length off the alignment is written whole.
        assert_eq!(changed_span(&[0; 6], &[0, 0, 0, 0, 0, 1]), Some((0, 6)));
    }
}

//! Reading glTF accessors out of loaded buffers, with every offset, stride
//! and count checked before a byte is read. Handles all component types
//! (normalised or not), byte strides, accessors without a buffer view
//! (zeros) and sparse substitution. Errors are plain reasons; the caller
//! adds the file and the accessor.

use gltf::accessor::{DataType, Dimensions};
use gltf::buffer::View;

/// An accessor without a buffer view is all zeros, so its count is not
/// bounded by any file size; beyond this many elements it is refused rather
/// than allocated.
const MAX_VIEWLESS_ELEMENTS: usize = 1 << 24;

/// The bytes of every buffer of the file, by glTF buffer index.
pub(super) struct Buffers(pub(super) Vec<Vec<u8>>);

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn component_count(d: Dimensions) -> Option<usize> {
    match d {
        Dimensions::Scalar => Some(1),
        Dimensions::Vec2 => Some(2),
        Dimensions::Vec3 => Some(3),
        Dimensions::Vec4 => Some(4),
        // Columns of 4 components never need padding (MAT2 and MAT3 of
        // bytes and shorts do), so MAT4 reads as 16 packed components.
        Dimensions::Mat4 => Some(16),
        Dimensions::Mat2 | Dimensions::Mat3 => None,
    }
}

/// One little-endian component at `at`, widened to f64 (exact for every type).
fn component(bytes: &[u8], at: usize, t: DataType) -> Option<f64> {
    let b = |n: usize| bytes.get(at..at.checked_add(n)?);
    Some(match t {
        DataType::I8 => f64::from(i8::from_le_bytes(b(1)?.try_into().ok()?)),
        DataType::U8 => f64::from(u8::from_le_bytes(b(1)?.try_into().ok()?)),
        DataType::I16 => f64::from(i16::from_le_bytes(b(2)?.try_into().ok()?)),
        DataType::U16 => f64::from(u16::from_le_bytes(b(2)?.try_into().ok()?)),
        DataType::U32 => f64::from(u32::from_le_bytes(b(4)?.try_into().ok()?)),
        DataType::F32 => f64::from(f32::from_le_bytes(b(4)?.try_into().ok()?)),
    })
}

/// glTF's mapping of normalised integers to [0, 1] or [-1, 1].
fn normalize(x: f64, t: DataType) -> f64 {
    match t {
        DataType::I8 => (x / 127.0).max(-1.0),
        DataType::U8 => x / 255.0,
        DataType::I16 => (x / 32767.0).max(-1.0),
        DataType::U16 => x / 65535.0,
        DataType::U32 => x / 4294967295.0,
        DataType::F32 => x,
    }
}

fn type_name(t: DataType) -> &'static str {
    match t {
        DataType::I8 => "BYTE",
        DataType::U8 => "UNSIGNED_BYTE",
        DataType::I16 => "SHORT",
        DataType::U16 => "UNSIGNED_SHORT",
        DataType::U32 => "UNSIGNED_INT",
        DataType::F32 => "FLOAT",
    }
}

/// Where `count` elements of `size` bytes lie: a byte slice, a first offset, a stride.
struct Layout<'b> {
    bytes: &'b [u8],
    offset: usize,
    stride: usize,
}

impl Buffers {
    /// The bytes of a buffer view, checked against its buffer.
    pub(super) fn view_bytes(&self, view: &View) -> Result<&[u8], String> {
        let buffer = view.buffer().index();
        let data = self
            .0
            .get(buffer)
            .ok_or_else(|| format!("buffer {buffer} was not loaded"))?;
        let start = view.offset();
        view.offset()
            .checked_add(view.length())
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| {
                format!(
                    "buffer view {} (bytes {start}, length {}) lies outside buffer {buffer} ({} bytes)",
                    view.index(),
                    view.length(),
                    data.len()
                )
            })
    }

    /// Checks that `count` elements of `size` bytes fit in `view` from
    /// `offset`, `stride` apart (tightly packed when `None`).
    fn layout<'b>(
        &'b self,
        view: &View,
        offset: usize,
        stride: Option<usize>,
        count: usize,
        size: usize,
    ) -> Result<Layout<'b>, String> {
        let bytes = self.view_bytes(view)?;
        let stride = stride.unwrap_or(size);
        if stride < size {
            return Err(format!(
                "buffer view {} has a byte stride of {stride}, less than one element ({size} bytes)",
                view.index()
            ));
        }
        if count > 0 {
            let end = (count - 1)
                .checked_mul(stride)
                .and_then(|x| x.checked_add(offset))
                .and_then(|x| x.checked_add(size));
            if end.is_none_or(|end| end > bytes.len()) {
                return Err(format!(
                    "{count} elements of {size} bytes from byte {offset}, {stride} apart, do not fit in buffer view {} ({} bytes)",
                    view.index(),
                    bytes.len()
                ));
            }
        }
        Ok(Layout {
            bytes,
            offset,
            stride,
        })
    }

    /// Every element of the accessor as `N` components mapped by `map`
    /// (which gets the raw value), sparse substitution applied.
    fn read<T: Copy + Default, const N: usize>(
        &self,
        accessor: &gltf::Accessor,
        map: impl Fn(f64) -> T,
    ) -> Result<Vec<[T; N]>, String> {
        let dims = accessor.dimensions();
        if component_count(dims) != Some(N) {
            return Err(format!(
                "expected {N} components per element, found {dims:?}"
            ));
        }
        let t = accessor.data_type();
        let csize = component_size(t);
        let size = N * csize;
        let count = accessor.count();
        let decode = |layout: &Layout, i: usize| -> [T; N] {
            let at = layout.offset + i * layout.stride;
            std::array::from_fn(|k| {
                component(layout.bytes, at + k * csize, t).map_or_else(T::default, &map)
            })
        };
        let mut out = match accessor.view() {
            Some(view) => {
                let layout = self.layout(&view, accessor.offset(), view.stride(), count, size)?;
                (0..count).map(|i| decode(&layout, i)).collect()
            }
            None if count <= MAX_VIEWLESS_ELEMENTS => vec![[map(0.0); N]; count],
            None => {
                return Err(format!(
                    "{count} elements without a buffer view; at most {MAX_VIEWLESS_ELEMENTS} are read"
                ));
            }
        };

        if let Some(sparse) = accessor.sparse() {
            let n = sparse.count();
            if n > count {
                return Err(format!("{n} sparse values for {count} elements"));
            }
            let indices = sparse.indices();
            let index_type = match indices.index_type() {
                gltf::accessor::sparse::IndexType::U8 => DataType::U8,
                gltf::accessor::sparse::IndexType::U16 => DataType::U16,
                gltf::accessor::sparse::IndexType::U32 => DataType::U32,
            };
            let index_layout = self.layout(
                &indices.view(),
                indices.offset(),
                None,
                n,
                component_size(index_type),
            )?;
            let values = sparse.values();
            let value_layout = self.layout(&values.view(), values.offset(), None, n, size)?;
            for k in 0..n {
                let at = index_layout.offset + k * index_layout.stride;
                let target = component(index_layout.bytes, at, index_type).unwrap_or(f64::MAX);
                let slot = out.get_mut(target as usize).ok_or_else(|| {
                    format!("sparse index {k} is {target}, but there are {count} elements")
                })?;
                *slot = decode(&value_layout, k);
            }
        }
        Ok(out)
    }

    /// A float attribute of `N` components; integer components are converted
    /// as glTF says (normalised to [0, 1] or [-1, 1] when flagged so).
    pub(super) fn read_floats<const N: usize>(
        &self,
        accessor: &gltf::Accessor,
    ) -> Result<Vec<[f32; N]>, String> {
        let (t, normalized) = (accessor.data_type(), accessor.normalized());
        self.read::<f32, N>(accessor, |x| {
            (if normalized { normalize(x, t) } else { x }) as f32
        })
    }

    /// Vertex indices: scalars of an unsigned integer type.
    pub(super) fn read_indices(&self, accessor: &gltf::Accessor) -> Result<Vec<u32>, String> {
        let t = accessor.data_type();
        if !matches!(t, DataType::U8 | DataType::U16 | DataType::U32) {
            return Err(format!(
                "indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not {}",
                type_name(t)
            ));
        }
        // Every unsigned value up to u32::MAX is exact in f64.
        let read = self.read::<u32, 1>(accessor, |x| x as u32)?;
        Ok(read.into_iter().map(|[i]| i).collect())
    }
}

impl Buffers {
    /// Joint indices (JOINTS_n): VEC4 of UNSIGNED_BYTE or UNSIGNED_SHORT.
    pub(super) fn read_joints(&self, accessor: &gltf::Accessor) -> Result<Vec<[u32; 4]>, String> {
        let t = accessor.data_type();
        if !matches!(t, DataType::U8 | DataType::U16) {
            return Err(format!(
                "joints must be UNSIGNED_BYTE or UNSIGNED_SHORT, not {}",
                type_name(t)
            ));
        }
        self.read::<u32, 4>(accessor, |x| x as u32)
    }

    /// Column-major 4x4 float matrices (inverse bind matrices).
    pub(super) fn read_mat4(&self, accessor: &gltf::Accessor) -> Result<Vec<[f32; 16]>, String> {
        if accessor.data_type() != DataType::F32 {
            return Err(format!(
                "matrices must be FLOAT, not {}",
                type_name(accessor.data_type())
            ));
        }
        self.read::<f32, 16>(accessor, |x| x as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_decode_little_endian_and_normalise() {
        let bytes = [0x00, 0x00, 0x80, 0x3f, 0xff, 0x80];
        assert_eq!(component(&bytes, 0, DataType::F32), Some(1.0));
        assert_eq!(component(&bytes, 4, DataType::U8), Some(255.0));
        assert_eq!(component(&bytes, 5, DataType::I8), Some(-128.0));
        assert_eq!(
            component(&bytes, 4, DataType::U16),
            Some(f64::from(0x80ffu16))
        );
        assert_eq!(component(&bytes, 3, DataType::F32), None);
        assert_eq!(component(&bytes, usize::MAX, DataType::U16), None);
        assert_eq!(normalize(-128.0, DataType::I8), -1.0);
        assert_eq!(normalize(255.0, DataType::U8), 1.0);
        assert_eq!(normalize(-32767.0, DataType::I16), -1.0);
    }
}

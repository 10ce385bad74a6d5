//! Reading glTF accessors into plain numbers, with every byte range checked.
//!
//! The `gltf` crate's own reader slices buffers without checking element types against the
//! attribute (a VEC2 POSITION would panic) and reads only float positions; this one reads any
//! component type (normalised or not, so KHR_mesh_quantization works too), any byte stride and
//! sparse substitution, and answers every inconsistency with an error naming the accessor.

use gltf::accessor::{DataType, Dimensions};

/// Most elements one accessor may declare without a buffer view backing them (a sparse accessor
/// or an all-zero one): such counts cost memory without costing file size.
pub const MAX_UNBACKED_ELEMENTS: usize = 1 << 24;

/// An accessor's elements as `f32`, `components` per element (normalised integers mapped to
/// [0, 1] or [−1, 1] as the glTF specification says; other integers converted as they are).
pub struct Floats {
    pub components: usize,
    pub values: Vec<f32>,
}

impl Floats {
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.components).unwrap_or(0)
    }

    /// Element `i`, components beyond the accessor's filled with `fill`.
    pub fn get<const N: usize>(&self, i: usize, fill: f32) -> [f32; N] {
        let base = i * self.components;
        std::array::from_fn(|k| {
            if k < self.components {
                self.values.get(base + k).copied().unwrap_or(fill)
            } else {
                fill
            }
        })
    }
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

fn components(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

/// One component at the start of `b` (`b` holds at least [`component_size`] bytes).
fn component(b: &[u8], t: DataType, normalized: bool) -> f32 {
    match t {
        DataType::I8 => {
            let v = b[0] as i8 as f32;
            if normalized {
                (v / 127.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U8 => {
            let v = b[0] as f32;
            if normalized {
                v / 255.0
            } else {
                v
            }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
        DataType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                v / 65535.0
            } else {
                v
            }
        }
        DataType::U32 => {
            let v = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32;
            if normalized {
                v / u32::MAX as f32
            } else {
                v
            }
        }
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
    }
}

/// One unsigned integer component (u8, u16 or u32) at the start of `b`.
fn unsigned(b: &[u8], t: DataType) -> Option<u32> {
    match t {
        DataType::U8 => Some(u32::from(b[0])),
        DataType::U16 => Some(u32::from(u16::from_le_bytes([b[0], b[1]]))),
        DataType::U32 => Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// The bytes of `count` elements of `elem` bytes each, `stride` apart, starting `offset` bytes
/// into buffer view `view`: checked against the view's and the buffer's extent.
fn strided<'b>(
    view: &gltf::buffer::View,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &'b [Vec<u8>],
) -> Result<(&'b [u8], usize), String> {
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "bufferViews[{}].byteStride {stride} is smaller than an element ({elem} bytes)",
            view.index()
        ));
    }
    let buffer = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffers[{}] was not loaded", view.buffer().index()))?;
    let view_start = view.offset();
    let view_end = view_start
        .checked_add(view.length())
        .filter(|&e| e <= buffer.len())
        .ok_or_else(|| {
            format!(
                "bufferViews[{}] (bytes {}..{}) lies past the end of buffers[{}] ({} bytes)",
                view.index(),
                view_start,
                view_start.saturating_add(view.length()),
                view.buffer().index(),
                buffer.len()
            )
        })?;
    let data = &buffer[view_start..view_end];
    if count == 0 {
        return Ok((&[], stride));
    }
    let needed = stride
        .checked_mul(count - 1)
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    match needed {
        Some(end) if end <= data.len() => Ok((&data[offset..end], stride)),
        _ => Err(format!(
            "{count} elements of {elem} bytes (stride {stride}) from byte {offset} do not fit in \
             bufferViews[{}] ({} bytes)",
            view.index(),
            data.len()
        )),
    }
}

/// Reads accessor `a` as floats. `what` names it in errors (e.g. `accessors[3]`).
pub fn floats(a: &gltf::Accessor, buffers: &[Vec<u8>]) -> Result<Floats, String> {
    let t = a.data_type();
    let comps = components(a.dimensions());
    if matches!(
        a.dimensions(),
        Dimensions::Mat2 | Dimensions::Mat3 | Dimensions::Mat4
    ) {
        return Err(format!(
            "accessors[{}]: a matrix accessor where a vector or scalar was expected",
            a.index()
        ));
    }
    let size = component_size(t);
    let elem = comps * size;
    let count = a.count();
    let mut values = match a.view() {
        Some(view) => {
            let (data, stride) = strided(&view, a.offset(), count, elem, buffers)
                .map_err(|e| format!("accessors[{}]: {e}", a.index()))?;
            let mut out = Vec::with_capacity(count * comps);
            for i in 0..count {
                let e = &data[i * stride..i * stride + elem];
                for k in 0..comps {
                    out.push(component(&e[k * size..], t, a.normalized()));
                }
            }
            out
        }
        None => {
            if count > MAX_UNBACKED_ELEMENTS {
                return Err(format!(
                    "accessors[{}]: count {count} without a bufferView (the limit is {MAX_UNBACKED_ELEMENTS})",
                    a.index()
                ));
            }
            vec![0.0; count * comps]
        }
    };
    if let Some(sparse) = a.sparse() {
        let n = sparse.count();
        let idx = sparse.indices();
        let idx_type = match idx.index_type() {
            gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isize = component_size(idx_type);
        let (idata, istride) = strided(&idx.view(), idx.offset(), n, isize, buffers)
            .map_err(|e| format!("accessors[{}].sparse.indices: {e}", a.index()))?;
        let vals = sparse.values();
        let (vdata, vstride) = strided(&vals.view(), vals.offset(), n, elem, buffers)
            .map_err(|e| format!("accessors[{}].sparse.values: {e}", a.index()))?;
        for s in 0..n {
            let target = unsigned(&idata[s * istride..], idx_type).unwrap_or(0) as usize;
            if target >= count {
                return Err(format!(
                    "accessors[{}].sparse.indices: index {s} is {target}, but the accessor has {count} elements",
                    a.index()
                ));
            }
            let e = &vdata[s * vstride..s * vstride + elem];
            for k in 0..comps {
                values[target * comps + k] = component(&e[k * size..], t, a.normalized());
            }
        }
    }
    Ok(Floats {
        components: comps,
        values,
    })
}

/// Reads an index accessor (SCALAR of u8, u16 or u32), each index checked to be below
/// `vertices`.
pub fn indices(
    a: &gltf::Accessor,
    buffers: &[Vec<u8>],
    vertices: usize,
) -> Result<Vec<u32>, String> {
    let t = a.data_type();
    if a.dimensions() != Dimensions::Scalar
        || !matches!(t, DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "accessors[{}]: indices must be SCALAR unsigned bytes, shorts or ints, got {:?} {:?}",
            a.index(),
            a.dimensions(),
            t
        ));
    }
    let out: Vec<u32> = if a.sparse().is_none() {
        let size = component_size(t);
        let count = a.count();
        let view = a.view().ok_or_else(|| {
            format!(
                "accessors[{}]: an index accessor without a bufferView",
                a.index()
            )
        })?;
        let (data, stride) = strided(&view, a.offset(), count, size, buffers)
            .map_err(|e| format!("accessors[{}]: {e}", a.index()))?;
        (0..count)
            .map(|i| unsigned(&data[i * stride..], t).unwrap_or(0))
            .collect()
    } else {
        // Sparse indices are rare; the float path is exact for every u16 and for u32 below 2^24.
        let f = floats(a, buffers)?;
        f.values.iter().map(|&v| v as u32).collect()
    };
    if let Some((k, i)) = out
        .iter()
        .enumerate()
        .find(|(_, &i)| i as usize >= vertices)
    {
        return Err(format!(
            "accessors[{}]: index {k} is {i}, but the primitive has {vertices} vertices",
            a.index()
        ));
    }
    Ok(out)
}

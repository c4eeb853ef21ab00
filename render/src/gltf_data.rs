//! Reading a glTF's bytes: buffers (GLB chunk, `data:` URIs, files),
//! and accessors, with every offset, length and stride checked against the
//! buffer view and buffer it lies in, so a bad file is an error naming the
//! accessor or view, never an out-of-bounds read.

use std::path::PathBuf;

use gltf::accessor::{DataType, Dimensions};

/// How [`parse_gltf`](crate::gltf_mesh::parse_gltf) reads a file a glTF
/// names (buffer or image URI, percent-decoded, relative to the glTF
/// file): the resolved path and its bytes, or an I/O error. Here, where
/// the files are read, so this module does not depend on the loader built
/// on it; re-exported as `gltf_mesh::FileResolver`.
pub type FileResolver<'a> = dyn FnMut(&str) -> std::io::Result<(PathBuf, Vec<u8>)> + 'a;

/// Largest element count of an accessor without a buffer view (all zeros),
/// so a file cannot make the loader allocate without bound.
const MAX_VIEWLESS_COUNT: usize = 1 << 22;
/// Every buffer's bytes, checked against its declared length.
pub(crate) fn read_buffers(
    doc: &gltf::Document,
    blob: Option<&[u8]>,
    resolve: &mut FileResolver<'_>,
) -> Result<Vec<Vec<u8>>, String> {
    doc.buffers()
        .map(|b| {
            let what = format!("buffer {}", b.index());
            let data = match b.source() {
                gltf::buffer::Source::Bin => blob
                    .ok_or_else(|| {
                        format!("{what} is the GLB binary chunk, but the file has none")
                    })?
                    .to_vec(),
                gltf::buffer::Source::Uri(uri) => {
                    read_uri(uri, resolve).map_err(|e| format!("{what} (`{}`): {e}", short(uri)))?
                }
            };
            if data.len() < b.length() {
                return Err(format!(
                    "{what}: byteLength is {} but only {} bytes are there",
                    b.length(),
                    data.len()
                ));
            }
            Ok(data)
        })
        .collect()
}

/// A `data:` URI's bytes or a file's.
pub(crate) fn read_uri(uri: &str, resolve: &mut FileResolver<'_>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (meta, data) = rest.split_once(',').ok_or("`data:` URI without a comma")?;
        if !meta.ends_with(";base64") {
            return Err("`data:` URI that is not base64".into());
        }
        return base64_decode(data);
    }
    resolve(&percent_decode(uri))
        .map(|(_, b)| b)
        .map_err(|e| format!("cannot be read: {e}"))
}

/// The first 60 characters of a URI (data URIs are long).
pub(crate) fn short(uri: &str) -> String {
    match uri.char_indices().nth(60) {
        Some((i, _)) => format!("{}...", &uri[..i]),
        None => uri.to_owned(),
    }
}

/// Decodes standard base64 (padding optional, whitespace refused).
fn base64_decode(s: &str) -> Result<Vec<u8>, String> {
    let val = |c: u8| -> Result<u32, String> {
        Ok(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            _ => return Err(format!("invalid base64 character {:?}", c as char)),
        } as u32)
    };
    let s = s.trim_end_matches('=').as_bytes();
    let mut out = Vec::with_capacity(s.len() * 3 / 4);
    for chunk in s.chunks(4) {
        if chunk.len() == 1 {
            return Err("truncated base64".into());
        }
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= val(c)? << (18 - 6 * i);
        }
        let bytes = n.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Ok(out)
}

/// `%XX` escapes decoded (invalid ones kept as written).
pub(crate) fn percent_decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%'
            && i + 2 < b.len()
            && let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2]))
        {
            out.push((h * 16 + l) as u8);
            i += 3;
            continue;
        }
        out.push(b[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// An accessor's elements: the bytes from its first, the stride and the
/// element size.
pub(crate) type Located<'b> = (&'b [u8], usize, usize);

/// Where an accessor's elements lie: the buffer, the first byte, the
/// stride and the element size, all checked against the view and buffer.
pub(crate) fn locate<'b>(
    a: &gltf::Accessor,
    buffers: &'b [Vec<u8>],
) -> Result<Option<Located<'b>>, String> {
    if a.sparse().is_some() {
        return Err("sparse accessors are not read by acuity".into());
    }
    let elem = a.data_type().size() * a.dimensions().multiplicity();
    let Some(view) = a.view() else {
        return Ok(None);
    };
    let buf = &buffers[view.buffer().index()];
    let view_end = view
        .offset()
        .checked_add(view.length())
        .filter(|&e| e <= buf.len())
        .ok_or_else(|| {
            format!(
                "buffer view {} (bytes {}..+{}) lies outside buffer {} ({} bytes)",
                view.index(),
                view.offset(),
                view.length(),
                view.buffer().index(),
                buf.len()
            )
        })?;
    let data = &buf[view.offset()..view_end];
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "byteStride {stride} is below the element size {elem}"
        ));
    }
    if a.count() > 0 {
        let end = (a.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(a.offset()))
            .and_then(|x| x.checked_add(elem));
        if end.is_none_or(|e| e > data.len()) {
            return Err(format!(
                "{} elements from byte {} with stride {stride} run past the end of buffer view {} ({} bytes)",
                a.count(),
                a.offset(),
                view.index(),
                data.len()
            ));
        }
    }
    Ok(Some((&data[a.offset().min(data.len())..], stride, elem)))
}

/// An accessor as floats, `(components per element, values)`; integer
/// components are normalised when the accessor says so.
pub(crate) fn read_floats(
    a: &gltf::Accessor,
    buffers: &[Vec<u8>],
) -> Result<(usize, Vec<f32>), String> {
    let dims = a.dimensions().multiplicity();
    if matches!(
        a.dimensions(),
        Dimensions::Mat2 | Dimensions::Mat3 | Dimensions::Mat4
    ) {
        return Err("a matrix accessor where a vector is expected".into());
    }
    let Some((data, stride, _)) = locate(a, buffers)? else {
        if a.count() > MAX_VIEWLESS_COUNT {
            return Err(format!("{} elements without a buffer view", a.count()));
        }
        return Ok((dims, vec![0.0; a.count() * dims]));
    };
    let ty = a.data_type();
    let size = ty.size();
    let norm = a.normalized();
    let mut out = Vec::with_capacity(a.count() * dims);
    for i in 0..a.count() {
        for k in 0..dims {
            let at = i * stride + k * size;
            let b = &data[at..at + size];
            out.push(match ty {
                DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
                DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
                DataType::U16 => {
                    let v = f32::from(u16::from_le_bytes([b[0], b[1]]));
                    if norm { v / 65535.0 } else { v }
                }
                DataType::I16 => {
                    let v = f32::from(i16::from_le_bytes([b[0], b[1]]));
                    if norm { (v / 32767.0).max(-1.0) } else { v }
                }
                DataType::U8 => {
                    let v = f32::from(b[0]);
                    if norm { v / 255.0 } else { v }
                }
                DataType::I8 => {
                    let v = f32::from(b[0] as i8);
                    if norm { (v / 127.0).max(-1.0) } else { v }
                }
            });
        }
    }
    Ok((dims, out))
}

/// An index accessor (unsigned scalars), every index below `n_vertices`.
pub(crate) fn read_indices(
    a: &gltf::Accessor,
    buffers: &[Vec<u8>],
    n_vertices: usize,
) -> Result<Vec<u32>, String> {
    if a.dimensions() != Dimensions::Scalar
        || !matches!(a.data_type(), DataType::U8 | DataType::U16 | DataType::U32)
    {
        return Err(format!(
            "indices must be unsigned scalars, found {:?} {:?}",
            a.data_type(),
            a.dimensions()
        ));
    }
    let Some((data, stride, size)) = locate(a, buffers)? else {
        return Err("indices without a buffer view".into());
    };
    let mut out = Vec::with_capacity(a.count());
    for i in 0..a.count() {
        let b = &data[i * stride..i * stride + size];
        let v = match size {
            1 => u32::from(b[0]),
            2 => u32::from(u16::from_le_bytes([b[0], b[1]])),
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        };
        if v as usize >= n_vertices {
            return Err(format!(
                "index {i} is {v}, but the primitive has {n_vertices} vertices"
            ));
        }
        out.push(v);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_percent_escapes_decode() {
        assert_eq!(base64_decode("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64_decode("aGVsbG8").unwrap(), b"hello");
        assert_eq!(base64_decode("").unwrap(), b"");
        assert!(base64_decode("a").is_err());
        assert!(base64_decode("a*bc").is_err());
        assert_eq!(percent_decode("my%20file.bin"), "my file.bin");
        assert_eq!(percent_decode("100%"), "100%");
        assert_eq!(percent_decode("%zz"), "%zz");
    }
}

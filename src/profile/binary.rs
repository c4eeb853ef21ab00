//! The compact binary profile encoding.
//!
//! Layout, all integers and floats little-endian, strings as a `u32` byte
//! length and UTF-8 bytes, lists as a `u32` count and their items:
//!
//! ```text
//! magic             8 bytes  "ACUITYP\0"
//! format_version    u32
//! name              string
//! lod_triangles     list of u32
//! bounding_radius   f32
//! viewpoints        list of 3 x f32
//! rung_diameters_px list of f32
//! transitions       list of { feature_count u32,
//!                             features list of { freq_cdiam f32,
//!                                                area_diam2 f32,
//!                                                luminance 2 x f32,
//!                                                masker 2 x f32,
//!                                                count u32 } }
//! settings          list of { key string, value string }  (sorted by key)
//! inputs           list of { what string, hash_hex string }
//! checksum         u64, FNV-1a of every byte before it
//! ```
//!
//! The decoder checks every length against the bytes left before it
//! allocates, so a corrupt count cannot make it reserve gigabytes.

use crate::error::{Error, Result};

use super::{Feature, InputHash, PROFILE_FORMAT_VERSION, Profile, TransitionFeatures};

/// The first eight bytes of every binary profile.
pub const MAGIC: [u8; 8] = *b"ACUITYP\0";

/// 64-bit FNV-1a: a dependency-free checksum that catches corruption (not
/// tampering).
fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Validates and encodes a profile.
pub fn encode(profile: &Profile) -> Result<Vec<u8>> {
    profile.validate()?;
    let mut w = Vec::with_capacity(64 + profile.transitions.len() * 32);
    w.extend_from_slice(&MAGIC);
    put_u32(&mut w, profile.format_version);
    put_str(&mut w, &profile.name);
    put_len(&mut w, profile.lod_triangles.len());
    for &t in &profile.lod_triangles {
        put_u32(&mut w, t);
    }
    put_f32(&mut w, profile.bounding_radius);
    put_len(&mut w, profile.viewpoints.len());
    for v in &profile.viewpoints {
        v.iter().for_each(|&c| put_f32(&mut w, c));
    }
    put_len(&mut w, profile.rung_diameters_px.len());
    for &d in &profile.rung_diameters_px {
        put_f32(&mut w, d);
    }
    put_len(&mut w, profile.transitions.len());
    for t in &profile.transitions {
        put_u32(&mut w, t.feature_count);
        put_len(&mut w, t.features.len());
        for f in &t.features {
            put_f32(&mut w, f.freq_cdiam);
            put_f32(&mut w, f.area_diam2);
            for v in f.luminance.into_iter().chain(f.masker) {
                put_f32(&mut w, v);
            }
            put_u32(&mut w, f.count);
        }
    }
    put_len(&mut w, profile.settings.len());
    for (k, v) in &profile.settings {
        put_str(&mut w, k);
        put_str(&mut w, v);
    }
    put_len(&mut w, profile.inputs.len());
    for i in &profile.inputs {
        put_str(&mut w, &i.what);
        put_str(&mut w, &i.hash_hex);
    }
    let sum = fnv1a64(&w);
    w.extend_from_slice(&sum.to_le_bytes());
    Ok(w)
}

/// Decodes and validates a binary profile.
pub fn decode(bytes: &[u8]) -> Result<Profile> {
    if bytes.len() < MAGIC.len() + 4 + 8 {
        return Err(format_error(
            bytes.len(),
            "file too short for a binary profile",
        ));
    }
    if bytes[..MAGIC.len()] != MAGIC {
        return Err(format_error(0, "missing the binary profile magic bytes"));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version != PROFILE_FORMAT_VERSION {
        return Err(Error::ProfileVersion {
            path: None,
            found: version,
            supported: PROFILE_FORMAT_VERSION,
        });
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    let stored = u64::from_le_bytes(sum.try_into().expect("8 bytes"));
    if fnv1a64(body) != stored {
        return Err(format_error(
            body.len(),
            "checksum mismatch: the file is truncated or corrupt",
        ));
    }
    let mut r = Reader {
        bytes: body,
        pos: 12,
    };
    let name = r.string("name")?;
    let n = r.len(4, "lod_triangles")?;
    let lod_triangles = (0..n)
        .map(|_| r.u32("lod_triangles"))
        .collect::<Result<_>>()?;
    let bounding_radius = r.f32("bounding_radius")?;
    let n = r.len(12, "viewpoints")?;
    let viewpoints = (0..n)
        .map(|_| {
            Ok([
                r.f32("viewpoints")?,
                r.f32("viewpoints")?,
                r.f32("viewpoints")?,
            ])
        })
        .collect::<Result<_>>()?;
    let n = r.len(4, "rung_diameters_px")?;
    let rung_diameters_px = (0..n)
        .map(|_| r.f32("rung_diameters_px"))
        .collect::<Result<_>>()?;
    let n = r.len(8, "transitions")?;
    let mut transitions = Vec::with_capacity(n);
    for _ in 0..n {
        let feature_count = r.u32("transitions.feature_count")?;
        let m = r.len(28, "transitions.features")?;
        let features = (0..m)
            .map(|_| {
                let freq_cdiam = r.f32("transitions.features.freq_cdiam")?;
                let area_diam2 = r.f32("transitions.features.area_diam2")?;
                let mut pair = |field| Ok::<_, Error>([r.f32(field)?, r.f32(field)?]);
                Ok(Feature {
                    freq_cdiam,
                    area_diam2,
                    luminance: pair("transitions.features.luminance")?,
                    masker: pair("transitions.features.masker")?,
                    count: r.u32("transitions.features.count")?,
                })
            })
            .collect::<Result<_>>()?;
        transitions.push(TransitionFeatures {
            feature_count,
            features,
        });
    }
    let n = r.len(8, "settings")?;
    let mut settings = std::collections::BTreeMap::new();
    for _ in 0..n {
        let at = r.pos;
        let key = r.string("settings.key")?;
        let value = r.string("settings.value")?;
        if settings.insert(key, value).is_some() {
            return Err(format_error(at, "duplicate settings key"));
        }
    }
    let n = r.len(8, "inputs")?;
    let inputs = (0..n)
        .map(|_| {
            Ok(InputHash {
                what: r.string("inputs.what")?,
                hash_hex: r.string("inputs.hash_hex")?,
            })
        })
        .collect::<Result<_>>()?;
    if r.pos != body.len() {
        return Err(format_error(r.pos, "unexpected bytes after the profile"));
    }
    let profile = Profile {
        format_version: version,
        name,
        lod_triangles,
        bounding_radius,
        viewpoints,
        rung_diameters_px,
        transitions,
        settings,
        inputs,
    };
    profile.validate()?;
    Ok(profile)
}

fn format_error(at: usize, reason: &str) -> Error {
    Error::ProfileFormat {
        path: None,
        location: format!("byte {at}"),
        reason: reason.to_owned(),
    }
}

fn put_u32(w: &mut Vec<u8>, v: u32) {
    w.extend_from_slice(&v.to_le_bytes());
}

fn put_len(w: &mut Vec<u8>, n: usize) {
    put_u32(
        w,
        u32::try_from(n).expect("validated profiles have u32 counts"),
    );
}

fn put_f32(w: &mut Vec<u8>, v: f32) {
    w.extend_from_slice(&v.to_le_bytes());
}

fn put_str(w: &mut Vec<u8>, s: &str) {
    put_len(w, s.len());
    w.extend_from_slice(s.as_bytes());
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize, field: &str) -> Result<&[u8]> {
        if self.bytes.len() - self.pos < n {
            return Err(format_error(
                self.pos,
                &format!("file ends inside `{field}`"),
            ));
        }
        let s = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    fn u32(&mut self, field: &str) -> Result<u32> {
        Ok(u32::from_le_bytes(
            self.take(4, field)?.try_into().expect("4 bytes"),
        ))
    }

    fn f32(&mut self, field: &str) -> Result<f32> {
        Ok(f32::from_le_bytes(
            self.take(4, field)?.try_into().expect("4 bytes"),
        ))
    }

    /// A count of items each at least `min_item_bytes` long, checked
    /// against the bytes left.
    fn len(&mut self, min_item_bytes: usize, field: &str) -> Result<usize> {
        let at = self.pos;
        let n = self.u32(field)? as usize;
        let left = self.bytes.len() - self.pos;
        if n.saturating_mul(min_item_bytes) > left {
            return Err(format_error(
                at,
                &format!("`{field}` claims {n} items but only {left} bytes remain"),
            ));
        }
        Ok(n)
    }

    fn string(&mut self, field: &str) -> Result<String> {
        let n = self.len(1, field)?;
        let at = self.pos;
        let raw = self.take(n, field)?;
        String::from_utf8(raw.to_vec())
            .map_err(|_| format_error(at, &format!("`{field}` is not UTF-8")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profile::tests::sample_profile;

    #[test]
    fn round_trips_bit_identical() {
        let bytes = encode(&sample_profile()).unwrap();
        let back = decode(&bytes).unwrap();
        assert_eq!(back, sample_profile());
        assert_eq!(encode(&back).unwrap(), bytes);
    }

    #[test]
    fn every_truncation_is_an_error() {
        let bytes = encode(&sample_profile()).unwrap();
        for n in 0..bytes.len() {
            assert!(decode(&bytes[..n]).is_err(), "truncated at {n} decoded");
        }
    }

    #[test]
    fn every_flipped_byte_is_an_error() {
        let bytes = encode(&sample_profile()).unwrap();
        for i in 0..bytes.len() {
            let mut b = bytes.clone();
            b[i] ^= 0x40;
            assert!(decode(&b).is_err(), "flip at {i} decoded");
        }
    }

    #[test]
    fn non_finite_values_are_refused_on_write() {
        let mut p = sample_profile();
        p.bounding_radius = f32::INFINITY;
        assert!(encode(&p).is_err());
    }
}

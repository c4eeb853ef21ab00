//! The profile file: what the offline pass measured for one object, and
//! what the runtime selects from.
//!
//! A profile holds, for every sampled viewpoint and every LOD transition
//! `i -> i+1`, the unique spatial frequencies of that transition in cycles
//! per object diameter (c/diam; REFERENCE §1): at least the lowest, plus a
//! histogram. It also records the analysis settings and the hashes of the
//! inputs, so an unchanged object is not analysed again.
//!
//! Two encodings carry the same [`Profile`]:
//! - JSON (feature `json`), self-describing and diffable;
//! - a compact little-endian binary form (always available; see
//!   [`binary`]), about a tenth of the size, guarded by a checksum.
//!
//! Both are validated on read and on write: non-finite numbers and
//! inconsistent counts are refused with the field's path. Writing,
//! reading and writing again gives identical bytes.

pub mod binary;
#[cfg(feature = "json")]
pub mod json;

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The format version this build reads and writes.
pub const PROFILE_FORMAT_VERSION: u32 = 1;
/// Most LODs a profile may have (the selection stores LOD indices in a byte).
pub const MAX_LODS: usize = 64;
/// Most viewpoints a profile may have.
pub const MAX_VIEWPOINTS: usize = 65_535;
/// Most histogram bins a profile may have.
pub const MAX_HISTOGRAM_BINS: usize = 256;

/// Everything the offline pass measured for one object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    /// Always [`PROFILE_FORMAT_VERSION`] for profiles this build writes.
    pub format_version: u32,
    /// The object's name.
    pub name: String,
    /// Triangles of each LOD, finest (LOD 0) first; never increasing.
    pub lod_triangles: Vec<u32>,
    /// Bounding sphere radius of LOD 0 in the mesh's own units (> 0); the
    /// sphere the analysis camera fitted to its images.
    pub bounding_radius: f32,
    /// Unit directions from the object's centre towards each analysis
    /// camera, in the object's own frame (right-handed).
    pub viewpoints: Vec<[f32; 3]>,
    /// Upper edges of the histogram bins in c/diam, ascending; bin `b`
    /// counts frequencies in `(edges[b-1], edges[b]]`, bin 0 those up to
    /// `edges[0]`; frequencies above the last edge go into the last bin.
    pub histogram_edges_cdiam: Vec<f32>,
    /// One entry per viewpoint and transition, viewpoint-major:
    /// `transitions[view * (lod_count - 1) + transition]`.
    pub transitions: Vec<TransitionFrequencies>,
    /// The analysis settings, as `name -> value` text.
    pub settings: BTreeMap<String, String>,
    /// Content hashes of the inputs, in the order the analysis read them.
    pub inputs: Vec<InputHash>,
}

/// The unique frequencies of one LOD transition seen from one viewpoint.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransitionFrequencies {
    /// The lowest unique frequency in c/diam (finite, > 0), or `None` when
    /// the two LODs look the same: then the transition never costs detail.
    pub lowest_cdiam: Option<f32>,
    /// Number of unique features per histogram bin
    /// (`histogram_edges_cdiam.len()` bins).
    pub histogram: Vec<u32>,
}

/// A content hash of one analysis input.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputHash {
    /// What was hashed: a file path or a parameter description.
    pub what: String,
    /// The hash, as lower-case hexadecimal.
    pub hash_hex: String,
}

impl Profile {
    /// Number of LODs.
    pub fn lod_count(&self) -> usize {
        self.lod_triangles.len()
    }

    /// Number of transitions per viewpoint (`lod_count - 1`).
    pub fn transitions_per_view(&self) -> usize {
        self.lod_triangles.len().saturating_sub(1)
    }

    /// The transitions seen from one viewpoint, `0 -> 1` first.
    pub fn view_transitions(&self, view: usize) -> &[TransitionFrequencies] {
        let n = self.transitions_per_view();
        &self.transitions[view * n..(view + 1) * n]
    }

    /// Checks every rule of the format; the error names the field.
    pub fn validate(&self) -> Result<()> {
        let bad = |field: String, reason: String| Error::ProfileInvalid {
            path: None,
            field,
            reason,
        };
        if self.format_version != PROFILE_FORMAT_VERSION {
            return Err(Error::ProfileVersion {
                path: None,
                found: self.format_version,
                supported: PROFILE_FORMAT_VERSION,
            });
        }
        let lods = self.lod_triangles.len();
        if lods == 0 || lods > MAX_LODS {
            return Err(bad(
                "lod_triangles".into(),
                format!("{lods} LODs; a profile has 1 to {MAX_LODS}"),
            ));
        }
        if let Some(i) = (1..lods).find(|&i| self.lod_triangles[i] > self.lod_triangles[i - 1]) {
            return Err(bad(
                format!("lod_triangles[{i}]"),
                format!(
                    "{} triangles is more than LOD {} has ({}); LODs must not get finer",
                    self.lod_triangles[i],
                    i - 1,
                    self.lod_triangles[i - 1]
                ),
            ));
        }
        if !(self.bounding_radius.is_finite() && self.bounding_radius > 0.0) {
            return Err(bad(
                "bounding_radius".into(),
                format!("{} is not a finite radius > 0", self.bounding_radius),
            ));
        }
        let views = self.viewpoints.len();
        if views == 0 || views > MAX_VIEWPOINTS {
            return Err(bad(
                "viewpoints".into(),
                format!("{views} viewpoints; a profile has 1 to {MAX_VIEWPOINTS}"),
            ));
        }
        for (i, v) in self.viewpoints.iter().enumerate() {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if !(v.iter().all(|c| c.is_finite()) && (len - 1.0).abs() < 1e-3) {
                return Err(bad(
                    format!("viewpoints[{i}]"),
                    format!("{v:?} is not a unit vector"),
                ));
            }
        }
        let bins = self.histogram_edges_cdiam.len();
        if bins > MAX_HISTOGRAM_BINS {
            return Err(bad(
                "histogram_edges_cdiam".into(),
                format!("{bins} bins; at most {MAX_HISTOGRAM_BINS}"),
            ));
        }
        for (i, &e) in self.histogram_edges_cdiam.iter().enumerate() {
            let prev = if i == 0 {
                0.0
            } else {
                self.histogram_edges_cdiam[i - 1]
            };
            if !(e.is_finite() && e > prev) {
                return Err(bad(
                    format!("histogram_edges_cdiam[{i}]"),
                    format!("{e} is not finite and above the previous edge ({prev})"),
                ));
            }
        }
        let expected = views * (lods - 1);
        if self.transitions.len() != expected {
            return Err(bad(
                "transitions".into(),
                format!(
                    "{} entries; {views} viewpoints x {} transitions need {expected}",
                    self.transitions.len(),
                    lods - 1
                ),
            ));
        }
        for (i, t) in self.transitions.iter().enumerate() {
            if let Some(f) = t.lowest_cdiam
                && !(f.is_finite() && f > 0.0)
            {
                return Err(bad(
                    format!("transitions[{i}].lowest_cdiam"),
                    format!("{f} is not a finite frequency > 0"),
                ));
            }
            if t.histogram.len() != bins {
                return Err(bad(
                    format!("transitions[{i}].histogram"),
                    format!(
                        "{} bins; histogram_edges_cdiam has {bins}",
                        t.histogram.len()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Reads a profile file, binary or JSON (told apart by the binary
    /// magic bytes), and validates it. JSON needs the `json` feature.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let bytes = std::fs::read(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_bytes(&bytes).map_err(|e| e.with_path(path))
    }

    /// Decodes a profile from bytes, binary or JSON, and validates it.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self> {
        if bytes.starts_with(&binary::MAGIC) {
            return binary::decode(bytes);
        }
        #[cfg(feature = "json")]
        {
            json::decode(bytes)
        }
        #[cfg(not(feature = "json"))]
        {
            Err(Error::ProfileFormat {
                path: None,
                location: "byte 0".into(),
                reason: "not a binary profile (JSON profiles need the `json` feature)".into(),
            })
        }
    }

    /// Validates and writes the profile: JSON when the file name ends in
    /// `.json` (feature `json`), the binary form otherwise. The file is
    /// written beside its destination and renamed into place, so a failed
    /// write never leaves a truncated profile behind.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        let is_json = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let bytes = if is_json {
            #[cfg(feature = "json")]
            {
                json::encode(self)?
            }
            #[cfg(not(feature = "json"))]
            {
                return Err(Error::invalid(
                    "path",
                    "writing JSON profiles needs the `json` feature",
                ));
            }
        } else {
            binary::encode(self)?
        };
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        let tmp = std::path::PathBuf::from(tmp);
        std::fs::write(&tmp, &bytes).map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }
}

/// The default histogram edges in c/diam: octaves from 2 to 2048.
pub fn default_histogram_edges_cdiam() -> Vec<f32> {
    (1..=11).map(|i| (1u32 << i) as f32).collect()
}

/// The histogram bin of a frequency in c/diam for the given upper edges.
pub fn histogram_bin(edges_cdiam: &[f32], freq_cdiam: f32) -> usize {
    edges_cdiam
        .iter()
        .position(|&e| freq_cdiam <= e)
        .unwrap_or(edges_cdiam.len().saturating_sub(1))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small valid profile: 4 LODs, 6 viewpoints.
    pub(crate) fn sample_profile() -> Profile {
        let viewpoints = vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let edges = default_histogram_edges_cdiam();
        let mut transitions = Vec::new();
        for v in 0..6 {
            for t in 0..3 {
                let lowest = if v == 5 && t == 1 {
                    None
                } else {
                    Some(200.0 / (1 + t) as f32 + v as f32 * 1.5 + 0.1)
                };
                let mut histogram = vec![0; edges.len()];
                if let Some(f) = lowest {
                    histogram[histogram_bin(&edges, f)] = 3 + t as u32;
                }
                transitions.push(TransitionFrequencies {
                    lowest_cdiam: lowest,
                    histogram,
                });
            }
        }
        Profile {
            format_version: PROFILE_FORMAT_VERSION,
            name: "sample".into(),
            lod_triangles: vec![3928, 834, 254, 76],
            bounding_radius: 1.0,
            viewpoints,
            histogram_edges_cdiam: edges,
            transitions,
            settings: [("resolution_px".to_owned(), "512".to_owned())].into(),
            inputs: vec![InputHash {
                what: "lod0.obj".into(),
                hash_hex: "00ff".into(),
            }],
        }
    }

    #[test]
    fn sample_is_valid() {
        sample_profile().validate().unwrap();
    }

    #[test]
    fn rules_name_the_field() {
        let mut p = sample_profile();
        p.transitions[4].lowest_cdiam = Some(f32::NAN);
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("transitions[4].lowest_cdiam"), "{e}");

        let mut p = sample_profile();
        p.lod_triangles[2] = 900;
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .contains("lod_triangles[2]")
        );

        let mut p = sample_profile();
        p.viewpoints[3] = [0.0, 0.0, 0.0];
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .contains("viewpoints[3]")
        );

        let mut p = sample_profile();
        p.transitions.pop();
        assert!(
            p.validate()
                .unwrap_err()
                .to_string()
                .contains("transitions")
        );

        let mut p = sample_profile();
        p.format_version = 9;
        assert!(matches!(
            p.validate(),
            Err(Error::ProfileVersion { found: 9, .. })
        ));
    }

    #[test]
    fn histogram_bins_cover_every_frequency() {
        let edges = default_histogram_edges_cdiam();
        assert_eq!(histogram_bin(&edges, 0.5), 0);
        assert_eq!(histogram_bin(&edges, 2.0), 0);
        assert_eq!(histogram_bin(&edges, 2.5), 1);
        assert_eq!(histogram_bin(&edges, 1e9), edges.len() - 1);
    }
}

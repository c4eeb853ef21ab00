//! The profile file: what the offline pass measured for one object, and
//! what the runtime selects from.
//!
//! A profile holds, for every sampled viewpoint, every rung of a ladder of
//! on-screen sizes and every LOD transition `i -> i+1`, the unique features
//! of that transition: each with its spatial frequency in cycles per
//! object diameter (c/diam: independent of the display; a frequency of `f`
//! c/diam on an object `theta` degrees across is `f / theta` c/deg), the pair of relative linear
//! luminances it shows in the two renderings (its contrast once a display
//! is known), the luminance range it sits on (what masks it) and its area.
//! Every feature whose two luminances differ is stored: the run time pools
//! a transition's features (visible differences add up), so none can be
//! left out because another is more visible. It also records the analysis settings and the
//! hashes of the inputs, so an unchanged object is not analysed again.
//!
//! Nothing in a profile depends on the display: pixels per degree, the
//! display's luminance and the observer's sensitivity are folded in when
//! the profile is added to a [`crate::Selector`].
//!
//! Two encodings carry the same [`Profile`]:
//! - JSON (feature `json`), self-describing and diffable;
//! - a compact little-endian binary form (always available; see
//!   [`binary`]), guarded by a checksum.
//!
//! Both are validated on read and on write: non-finite numbers and
//! inconsistent counts are refused with the field's path. Writing,
//! reading and writing again gives identical bytes. A profile of an older
//! format version is refused with an error that says how to regenerate it.

pub mod binary;
#[cfg(feature = "json")]
pub mod json;

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// The format version this build reads and writes. Version 1 stored one
/// lowest frequency per transition, without contrast or on-screen sizes;
/// version 2 only each transition's most visible features (those no other
/// feature beat on frequency, contrast, masking and area at once), which
/// cannot be summed.
pub const PROFILE_FORMAT_VERSION: u32 = 3;
/// Most LODs a profile may have (the selection stores LOD indices in a byte).
pub const MAX_LODS: usize = 64;
/// Most viewpoints a profile may have.
pub const MAX_VIEWPOINTS: usize = 65_535;
/// Most rungs of the size ladder a profile may have.
pub const MAX_RUNGS: usize = 32;
/// Most features stored for one transition at one viewpoint and rung.
pub const MAX_FEATURES: usize = 65_535;
/// Largest profile file [`Profile::load`] reads, bytes (1 GiB).
pub const MAX_FILE_BYTES: u64 = 1 << 30;

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
    /// The size ladder: the bounding sphere's diameter in pixels at each
    /// rung, ascending, each finite and >= 1.
    pub rung_diameters_px: Vec<f32>,
    /// One entry per viewpoint, rung and transition:
    /// `transitions[(view * rungs + rung) * (lod_count - 1) + transition]`.
    pub transitions: Vec<TransitionFeatures>,
    /// The analysis settings, as `name -> value` text.
    pub settings: BTreeMap<String, String>,
    /// Content hashes of the inputs, in the order the analysis read them.
    pub inputs: Vec<InputHash>,
}

/// The unique features of one LOD transition seen from one viewpoint at one
/// on-screen size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransitionFeatures {
    /// How many unique features the analysis found (at least the sum of
    /// the features' `count`); 0 when the two LODs look the same, so the
    /// transition never costs detail.
    pub feature_count: u32,
    /// The features, ascending by frequency (see the module docs): all of
    /// them, unless the analysis found more than [`MAX_FEATURES`].
    pub features: Vec<Feature>,
}

/// One unique feature of a transition.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Feature {
    /// Spatial frequency, cycles per object diameter (finite, > 0): half a
    /// cycle over the feature's width.
    pub freq_cdiam: f32,
    /// Area in units of the squared bounding-sphere diameter (finite, in
    /// `(0, 1]`): with the object's size on screen, the field the CSF
    /// integrates over.
    pub area_diam2: f32,
    /// Relative linear luminance (0 = black, 1 = the display's peak) of the
    /// feature in the two renderings, lower then higher: its contrast is
    /// the Michelson contrast of the two on a given display.
    pub luminance: [f32; 2],
    /// Relative linear luminance range (lowest, highest) of what the
    /// feature sits on, in whichever rendering has the smaller: the
    /// contrast that masks it.
    pub masker: [f32; 2],
    /// How many measured features this record stands for (>= 1): each of
    /// them no finer, no larger, of no more contrast and no more masked
    /// than the record on any display, so pooling the record `count` times
    /// never understates the transition.
    pub count: u32,
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

    /// Number of transitions per viewpoint and rung (`lod_count - 1`).
    pub fn transitions_per_view(&self) -> usize {
        self.lod_triangles.len().saturating_sub(1)
    }

    /// The transitions seen from one viewpoint at one rung, `0 -> 1` first.
    pub fn transitions_at(&self, view: usize, rung: usize) -> &[TransitionFeatures] {
        let n = self.transitions_per_view();
        let i = (view * self.rung_diameters_px.len() + rung) * n;
        &self.transitions[i..i + n]
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
        let rungs = self.rung_diameters_px.len();
        if rungs == 0 || rungs > MAX_RUNGS {
            return Err(bad(
                "rung_diameters_px".into(),
                format!("{rungs} rungs; a profile has 1 to {MAX_RUNGS}"),
            ));
        }
        for (i, &d) in self.rung_diameters_px.iter().enumerate() {
            let prev = if i == 0 {
                0.0
            } else {
                self.rung_diameters_px[i - 1]
            };
            if !(d.is_finite() && d >= 1.0 && d > prev) {
                return Err(bad(
                    format!("rung_diameters_px[{i}]"),
                    format!("{d} is not a finite diameter >= 1 above the previous rung ({prev})"),
                ));
            }
        }
        let expected = views * rungs * (lods - 1);
        if self.transitions.len() != expected {
            return Err(bad(
                "transitions".into(),
                format!(
                    "{} entries; {views} viewpoints x {rungs} rungs x {} transitions need {expected}",
                    self.transitions.len(),
                    lods - 1
                ),
            ));
        }
        for (i, t) in self.transitions.iter().enumerate() {
            let counted: u64 = t.features.iter().map(|f| u64::from(f.count)).sum();
            if t.features.len() > MAX_FEATURES || counted > u64::from(t.feature_count) {
                return Err(bad(
                    format!("transitions[{i}].features"),
                    format!(
                        "{} records standing for {counted} features; at most {MAX_FEATURES} records, \
                         standing for at most feature_count ({})",
                        t.features.len(),
                        t.feature_count
                    ),
                ));
            }
            let mut prev = 0.0f32;
            for (j, f) in t.features.iter().enumerate() {
                let field = |name: &str| format!("transitions[{i}].features[{j}].{name}");
                if !(f.freq_cdiam.is_finite() && f.freq_cdiam > 0.0 && f.freq_cdiam >= prev) {
                    return Err(bad(
                        field("freq_cdiam"),
                        format!(
                            "{} is not a finite frequency > 0 and >= the previous feature's ({prev})",
                            f.freq_cdiam
                        ),
                    ));
                }
                prev = f.freq_cdiam;
                if f.count == 0 {
                    return Err(bad(field("count"), "0 is not a count >= 1".into()));
                }
                if !(f.area_diam2.is_finite() && f.area_diam2 > 0.0 && f.area_diam2 <= 1.0) {
                    return Err(bad(
                        field("area_diam2"),
                        format!("{} is not an area in (0, 1]", f.area_diam2),
                    ));
                }
                for (name, [lo, hi]) in [("luminance", f.luminance), ("masker", f.masker)] {
                    if !(lo.is_finite() && hi.is_finite() && 0.0 <= lo && lo <= hi && hi <= 1.0) {
                        return Err(bad(
                            field(name),
                            format!("[{lo}, {hi}] is not a pair 0 <= lower <= higher <= 1"),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Reads a profile file, binary or JSON (told apart by the binary
    /// magic bytes), and validates it. JSON needs the `json` feature. Only
    /// a regular file (or a link to one) of at most [`MAX_FILE_BYTES`] is
    /// read: a device, a FIFO or a larger file is an [`Error::Io`] of kind
    /// `InvalidInput`, returned without reading (or waiting for) it.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        use std::io::{ErrorKind, Read};
        let path = path.as_ref();
        let io = |source| Error::Io {
            path: path.to_path_buf(),
            source,
        };
        let refuse = |why: String| io(std::io::Error::new(ErrorKind::InvalidInput, why));
        let check = |meta: std::fs::Metadata| {
            if !meta.is_file() {
                Err(refuse("not a regular file".into()))
            } else if meta.len() > MAX_FILE_BYTES {
                Err(refuse(format!(
                    "{} bytes is more than a profile's {MAX_FILE_BYTES}",
                    meta.len()
                )))
            } else {
                Ok(meta.len())
            }
        };
        // Checked before opening (opening a FIFO waits for a writer) and
        // again on the open file, in case the path changed in between.
        check(std::fs::metadata(path).map_err(io)?)?;
        let file = std::fs::File::open(path).map_err(io)?;
        let len = check(file.metadata().map_err(io)?)?;
        let mut bytes = Vec::with_capacity(len as usize);
        file.take(MAX_FILE_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(io)?;
        if bytes.len() as u64 > MAX_FILE_BYTES {
            return Err(refuse(format!(
                "more than a profile's {MAX_FILE_BYTES} bytes"
            )));
        }
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
    /// written to a new file beside its destination (created exclusively,
    /// so never through a planted link) and renamed into place, so a failed
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
        // A fresh file beside the destination, created exclusively (never
        // through a link or over a file someone else made), then renamed
        // into place; on failure it is removed.
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(format!(".{}-{n}.tmp", std::process::id()));
        let tmp = std::path::PathBuf::from(tmp);
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(io)?;
        let written = std::io::Write::write_all(&mut file, &bytes)
            .and_then(|()| file.sync_all())
            .and_then(|()| std::fs::rename(&tmp, path));
        if written.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        written.map_err(io)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small valid profile: 4 LODs, 6 viewpoints, 2 rungs.
    pub(crate) fn sample_profile() -> Profile {
        let viewpoints = vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let rung_diameters_px = vec![32.0, 64.0];
        let mut transitions = Vec::new();
        for v in 0..6 {
            for rung in 0..2 {
                for t in 0..3 {
                    let features = if v == 5 && t == 1 {
                        vec![]
                    } else {
                        let f = 200.0 / (1 + t) as f32 + v as f32 * 1.5 + rung as f32 + 0.1;
                        vec![
                            Feature {
                                freq_cdiam: f,
                                area_diam2: 0.01,
                                luminance: [0.1, 0.12],
                                masker: [0.1, 0.12],
                                count: 2,
                            },
                            Feature {
                                freq_cdiam: 2.0 * f,
                                area_diam2: 0.002,
                                luminance: [0.0, 0.5],
                                masker: [0.0, 0.9],
                                count: 1,
                            },
                        ]
                    };
                    transitions.push(TransitionFeatures {
                        feature_count: 3 * features.len() as u32,
                        features,
                    });
                }
            }
        }
        Profile {
            format_version: PROFILE_FORMAT_VERSION,
            name: "sample".into(),
            lod_triangles: vec![3928, 834, 254, 76],
            bounding_radius: 1.0,
            viewpoints,
            rung_diameters_px,
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
        let field_of = |p: Profile| p.validate().unwrap_err().to_string();
        let mut p = sample_profile();
        p.transitions[4].features[0].freq_cdiam = f32::NAN;
        let e = field_of(p);
        assert!(e.contains("transitions[4].features[0].freq_cdiam"), "{e}");

        let mut p = sample_profile();
        p.transitions[4].features[1].luminance = [0.6, 0.5];
        let e = field_of(p);
        assert!(e.contains("transitions[4].features[1].luminance"), "{e}");

        let mut p = sample_profile();
        p.transitions[4].features[1].masker = [0.2, 1.5];
        let e = field_of(p);
        assert!(e.contains("transitions[4].features[1].masker"), "{e}");

        let mut p = sample_profile();
        p.transitions[2].features.swap(0, 1);
        assert!(field_of(p).contains("transitions[2].features[1].freq_cdiam"));

        let mut p = sample_profile();
        p.transitions[2].feature_count = 1;
        assert!(field_of(p).contains("transitions[2].features"));

        let mut p = sample_profile();
        p.lod_triangles[2] = 900;
        assert!(field_of(p).contains("lod_triangles[2]"));

        let mut p = sample_profile();
        p.viewpoints[3] = [0.0, 0.0, 0.0];
        assert!(field_of(p).contains("viewpoints[3]"));

        let mut p = sample_profile();
        p.rung_diameters_px = vec![64.0, 32.0];
        assert!(field_of(p).contains("rung_diameters_px[1]"));

        let mut p = sample_profile();
        p.transitions.pop();
        assert!(field_of(p).contains("transitions"));

        let mut p = sample_profile();
        p.format_version = 9;
        assert!(matches!(
            p.validate(),
            Err(Error::ProfileVersion { found: 9, .. })
        ));
    }

    #[test]
    fn an_old_profile_says_how_to_regenerate_it() {
        let mut p = sample_profile();
        p.format_version = 1;
        let e = p.validate().unwrap_err().to_string();
        assert!(
            e.contains("version 1") && e.contains("acuity preprocess"),
            "{e}"
        );
    }

    #[test]
    fn transitions_are_indexed_by_view_then_rung() {
        let p = sample_profile();
        let t = p.transitions_at(4, 1);
        assert_eq!(t.len(), 3);
        assert_eq!(t[0], p.transitions[(4 * 2 + 1) * 3]);
    }
}

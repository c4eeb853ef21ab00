//! What an analysis takes: the object's LOD source ([`ObjectSource`]) and
//! the settings ([`AnalysisSettings`]), with the algorithm's version. A
//! leaf of the pipeline: the input hashes ([`crate::input_files`]) and the
//! pipeline ([`crate::pipeline`]) both read them, and neither is read here.

use std::path::PathBuf;

use crate::features::{self, Grouping};
use crate::frequency::{self, FrequencyStatistic};
use crate::lods::{self, ProceduralParams};
use crate::shapes::Shape;
use crate::views;
use crate::{Error, Mesh, segment};

/// Version of the analysis algorithm, part of the settings hash so that
/// profiles made by an older algorithm are not reused.
pub const ANALYSIS_VERSION: u32 = 4;

/// Settings of the analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisSettings {
    /// Largest rung of the size ladder: square image size in pixels,
    /// 16..=8192 (default 512). The bounding sphere's diameter spans the
    /// whole image.
    pub resolution_px: u32,
    /// Smallest rung of the size ladder, pixels, 4..=`resolution_px`
    /// (default 16); rungs halve from `resolution_px` while they are at
    /// least this ([`AnalysisSettings::diameters_px`]). Equal to
    /// `resolution_px`: one analysis size.
    pub min_diameter_px: u32,
    /// View-sphere subdivision level, 0..=6: 6, 18 (default, level 1), 66,
    /// 258, ... viewpoints.
    pub viewpoint_level: u32,
    /// How changed pixels are grouped into features (default: by the sign
    /// of the change; see [`crate::features`]).
    pub grouping: Grouping,
    /// ΔE*uv just-noticeable difference of region growing, > 0 (default
    /// 2.3); used by [`Grouping::Regions`].
    pub threshold_delta_e: f32,
    /// A pixel counts as changed where two LODs' renderings differ by more
    /// than this, ΔE*uv: finite, >= 0 (0: any difference; default 1, just
    /// above one sRGB code step; see [`crate::features`]).
    pub min_change_delta_e: f32,
    /// Number of Feret directions K, 4..=360 (default 8).
    pub feret_directions: u32,
    /// MSAA samples, 4 (default), 1 (none) or what the adapter supports;
    /// must match the [`crate::Renderer`]'s.
    pub msaa_samples: u32,
    /// How a feature's extents become one length (default mean).
    pub statistic: FrequencyStatistic,
    /// Background colour, sRGB8 (default black).
    pub background_srgb: [u8; 3],
}

impl Default for AnalysisSettings {
    fn default() -> Self {
        Self {
            resolution_px: 512,
            min_diameter_px: 16,
            viewpoint_level: 1,
            grouping: Grouping::ChangeSign,
            threshold_delta_e: segment::DEFAULT_THRESHOLD_DELTA_E,
            min_change_delta_e: features::DEFAULT_MIN_CHANGE_DELTA_E,
            feret_directions: frequency::DEFAULT_FERET_DIRECTIONS,
            msaa_samples: crate::render::DEFAULT_MSAA_SAMPLES,
            statistic: FrequencyStatistic::default(),
            background_srgb: [0, 0, 0],
        }
    }
}

impl AnalysisSettings {
    /// Smallest `resolution_px`, pixels.
    pub const MIN_RESOLUTION_PX: u32 = 16;
    /// Largest `resolution_px`, pixels.
    pub const MAX_RESOLUTION_PX: u32 = 8192;
    /// Smallest `min_diameter_px`, pixels (at most `resolution_px`).
    pub const MIN_DIAMETER_PX: u32 = 4;
    /// Largest `viewpoint_level` ([`views::MAX_VIEWPOINT_LEVEL`]).
    pub const MAX_VIEWPOINT_LEVEL: u32 = views::MAX_VIEWPOINT_LEVEL;

    /// A stable text encoding of every field and [`ANALYSIS_VERSION`], the
    /// settings' part of a profile's cache key: fields by name, enums by
    /// their names, floats by their bit patterns, so the key changes exactly
    /// when a setting does, whatever `Debug` or float formatting does.
    pub fn cache_key(&self) -> String {
        // Destructured without `..`: a new field fails to compile until it
        // is part of the key.
        let Self {
            resolution_px,
            min_diameter_px,
            viewpoint_level,
            grouping,
            threshold_delta_e,
            min_change_delta_e,
            feret_directions,
            msaa_samples,
            statistic,
            background_srgb: [r, g, b],
        } = self;
        format!(
            "analysis v{ANALYSIS_VERSION}; resolution_px={resolution_px}; \
             min_diameter_px={min_diameter_px}; viewpoint_level={viewpoint_level}; \
             grouping={}; threshold_delta_e_bits={:#010x}; \
             min_change_delta_e_bits={:#010x}; feret_directions={feret_directions}; msaa_samples={msaa_samples}; \
             statistic={}; background_srgb={r},{g},{b}",
            grouping.name(),
            threshold_delta_e.to_bits(),
            min_change_delta_e.to_bits(),
            statistic.name(),
        )
    }

    /// The rungs of the size ladder, ascending: `resolution_px` halved
    /// (rounding down) while the result is at least `min_diameter_px`.
    pub fn diameters_px(&self) -> Vec<u32> {
        let mut d: Vec<u32> = std::iter::successors(Some(self.resolution_px), |&d| Some(d / 2))
            .take_while(|&d| d >= self.min_diameter_px.max(1))
            .collect();
        d.reverse();
        d
    }

    /// Checks every field's domain; the error names the field.
    pub fn validate(&self) -> Result<(), Error> {
        let bad = |field, message: String| Err(Error::Settings { field, message });
        if !(Self::MIN_RESOLUTION_PX..=Self::MAX_RESOLUTION_PX).contains(&self.resolution_px) {
            return bad(
                "resolution_px",
                format!(
                    "{} outside {}..={}",
                    self.resolution_px,
                    Self::MIN_RESOLUTION_PX,
                    Self::MAX_RESOLUTION_PX
                ),
            );
        }
        if !(Self::MIN_DIAMETER_PX..=self.resolution_px).contains(&self.min_diameter_px) {
            return bad(
                "min_diameter_px",
                format!(
                    "{} outside {}..={} (resolution_px)",
                    self.min_diameter_px,
                    Self::MIN_DIAMETER_PX,
                    self.resolution_px
                ),
            );
        }
        if self.viewpoint_level > views::MAX_VIEWPOINT_LEVEL {
            return bad(
                "viewpoint_level",
                format!(
                    "{} above {}",
                    self.viewpoint_level,
                    views::MAX_VIEWPOINT_LEVEL
                ),
            );
        }
        if !(self.threshold_delta_e.is_finite() && self.threshold_delta_e > 0.0) {
            return bad(
                "threshold_delta_e",
                format!("{} is not a positive number", self.threshold_delta_e),
            );
        }
        features::check_min_change_delta_e(self.min_change_delta_e)?;
        if !(4..=360).contains(&self.feret_directions) {
            return bad(
                "feret_directions",
                format!("{} outside 4..=360", self.feret_directions),
            );
        }
        if self.msaa_samples == 0 {
            return bad("msaa_samples", "0 samples".into());
        }
        Ok(())
    }
}

/// Where an object's LODs come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ObjectSource {
    /// One mesh file (OBJ or glTF) per LOD, finest first, or one glTF file
    /// carrying the chain (see [`lods::load_lod_files`]).
    Files {
        /// Object name (used in messages and reports).
        name: String,
        /// Mesh files, finest first.
        lod_paths: Vec<PathBuf>,
    },
    /// One mesh file (OBJ, or a glTF's LOD 0) simplified to each triangle
    /// target (see [`lods::generate_lods`]).
    Generated {
        /// Object name.
        name: String,
        /// The source mesh file.
        path: PathBuf,
        /// Triangle targets, finest first, strictly decreasing.
        triangle_targets: Vec<u32>,
    },
    /// A mesh file kept whole: LOD 0 is the mesh as given and each coarser
    /// LOD is simplified from it to a fraction of its triangles
    /// ([`lods::whole_mesh_targets`]: quarters down to a floor).
    Whole {
        /// Object name.
        name: String,
        /// The mesh file.
        path: PathBuf,
    },
    /// The procedural test object ([`lods::procedural_object`]) simplified to
    /// each triangle target.
    Procedural {
        /// Object name.
        name: String,
        /// Shape parameters.
        params: ProceduralParams,
        /// Triangle targets, finest first, strictly decreasing.
        triangle_targets: Vec<u32>,
    },
    /// A plain test shape tessellated at each triangle target (see
    /// [`Shape::lods`]).
    Shape {
        /// Object name.
        name: String,
        /// The shape.
        shape: Shape,
        /// Triangle targets, finest first, strictly decreasing.
        triangle_targets: Vec<u32>,
    },
}

impl ObjectSource {
    /// The object's name.
    pub fn name(&self) -> &str {
        match self {
            Self::Files { name, .. }
            | Self::Generated { name, .. }
            | Self::Whole { name, .. }
            | Self::Procedural { name, .. }
            | Self::Shape { name, .. } => name,
        }
    }

    /// Loads or generates the LOD chain (checked), with loader warnings.
    pub fn load_lods(&self) -> Result<(Vec<Mesh>, Vec<String>), Error> {
        match self {
            Self::Files { name, lod_paths } => lods::load_lod_files(name, lod_paths),
            Self::Generated {
                name,
                path,
                triangle_targets,
            } => {
                let (mesh, mut warnings) = lods::load_finest(path)?;
                let first = triangle_targets.first().copied().unwrap_or(0);
                if (mesh.triangle_count() as u64) < u64::from(first) {
                    warnings.push(format!(
                        "{}: {} triangles, fewer than the first target {first}: LOD 0 is the mesh as given",
                        path.display(),
                        mesh.triangle_count()
                    ));
                }
                Ok((
                    lods::generate_lods(name, &mesh, triangle_targets)?,
                    warnings,
                ))
            }
            Self::Whole { name, path } => {
                let (mesh, warnings) = lods::load_finest(path)?;
                let targets = lods::whole_mesh_targets(mesh.triangle_count() as u64);
                Ok((lods::generate_lods(name, &mesh, &targets)?, warnings))
            }
            Self::Procedural {
                name,
                params,
                triangle_targets,
            } => {
                let m = lods::procedural_object(*params);
                Ok((lods::generate_lods(name, &m, triangle_targets)?, Vec::new()))
            }
            Self::Shape {
                name,
                shape,
                triangle_targets,
            } => Ok((shape.lods(name, triangle_targets)?, Vec::new())),
        }
    }
}

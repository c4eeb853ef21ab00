//! A selector's compiled profiles: where each profile's prefix-minimum
//! rows lie, its viewpoint lookup and size ladder, and whether all
//! profiles share one row layout (which lets the loop find rows in bulk).

use crate::viewpoints::ViewpointLookup;

#[derive(Clone, Debug)]
pub(super) struct CompiledProfile {
    pub(super) lod_count: usize,
    pub(super) triangles: Vec<u32>,
}

/// Where a profile's prefix-minimum rows lie in
/// [`Selector::rows`](super::Selector::rows): row
/// `(block * rungs + rung) * stride` from `start`, block 0 the worst case
/// over viewpoints and block `1 + v` viewpoint `v`; each has
/// `lod_count - 1` entries padded with `-inf` to `stride`, a multiple of 4
/// ([`crate::rows`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct ProfileRows {
    pub(super) start: u32,
    pub(super) stride: u32,
    /// Index into [`Selector::lookups`](super::Selector::lookups), or
    /// [`NO_LOOKUP`](super::NO_LOOKUP) for one viewpoint or the worst-case
    /// rule.
    pub(super) lookup: u32,
    /// Index into [`Selector::ladders`](super::Selector::ladders).
    pub(super) ladder: u32,
}

/// A size ladder shared by the profiles analysed with it: the rungs'
/// diameters and, for the current display, the angular sizes at which an
/// object moves up a rung.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Ladder {
    pub(super) diameters_px: Vec<f32>,
    pub(super) boundaries_deg: Vec<f32>,
}

/// How the profiles' rows are laid out, over the profiles with more than
/// one LOD: with one stride and one viewpoint lookup for all of them (one
/// offline pass's profiles), the loop finds rows and counts LODs in bulk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum RowLayout {
    /// No profile with more than one LOD yet.
    Empty,
    /// Every row has `stride` entries; `lookup` is the one viewpoint
    /// lookup ([`NO_LOOKUP`](super::NO_LOOKUP): none, or the worst-case
    /// rule) and `ladder` the one size ladder.
    Uniform {
        stride: u32,
        lookup: u32,
        ladder: u32,
    },
    /// Strides or lookups differ: rows are found object by object.
    Mixed,
}

impl RowLayout {
    pub(super) fn admit(self, stride: u32, lookup: u32, ladder: u32) -> Self {
        let uniform = Self::Uniform {
            stride,
            lookup,
            ladder,
        };
        match self {
            Self::Empty => uniform,
            Self::Uniform { .. } if self == uniform => self,
            _ => Self::Mixed,
        }
    }
}

/// The selector's per-profile tables, borrowed for a frame.
pub(super) struct Tables<'a> {
    pub(super) rows: &'a [f32],
    pub(super) profiles: &'a [ProfileRows],
    pub(super) lookups: &'a [ViewpointLookup],
    pub(super) ladders: &'a [Ladder],
    pub(super) object_profiles: &'a [u32],
    pub(super) layout: RowLayout,
    /// The lowest `G(v)` on this display, c/deg.
    pub(super) motion_floor_cpd: f32,
}

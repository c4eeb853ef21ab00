//! Stereo: one LOD per object that is right for both eyes of a headset.
//!
//! Selection runs once per frame, from the centre eye (the head pose,
//! midway between the eyes), over a display that holds both eyes' fields
//! of view at the finer of their pixel densities, with every bounding
//! sphere grown by twice the larger eye offset `|o|` (the IPD, for eyes
//! either side of the head; [`SelectorSettings::radius_margin`]).
//! Engines do the same (one LOD per object from a centre view, so the two
//! eyes never show different LODs). Why it is right for each eye, with the
//! eyes' view axes parallel to the head's (as OpenXR reports them on most
//! headsets):
//!
//! - **Culling**: an eye's frustum is the centre frustum moved by the eye's
//!   offset `o`, so a point an eye sees, moved back by `o`, lies in the
//!   centre frustum, and the grown sphere holds it.
//! - **Size and eccentricity**: the eye can be `|o|` nearer the object
//!   (distance `d` from the centre eye), so its angular radius is at most
//!   `asin(r / (d - |o|))`, and the object's direction from it differs
//!   from the centre's by at most `asin(|o| / (d - |o|))` (law of sines).
//!   Their sum is at most `asin((r + |o|) / (d - |o|))` (`asin` is convex),
//!   which the grown sphere's angular radius `asin((r + 2|o|) / d)` is not
//!   below whenever the centre eye is outside the grown sphere (inside it,
//!   LOD 0 is chosen anyway). So the eye sees the object no smaller and
//!   no farther from its gaze than judged. Growing by `|o|` alone covers
//!   size but not this sum; a property test found the case. With an eye
//!   tracker the two gaze rays converge on the fixation point; their
//!   parallax there, `|o| / distance`, is within the tracker's default
//!   margin of 1 deg beyond about 1.8 m for a 64 mm IPD.
//! - **Viewpoint**: with [`crate::ViewpointRule::WorstCase`] the features
//!   judged do not depend on the direction the object is seen from, and
//!   the one selection is never coarser than either eye's own (a property
//!   test checks it). With `Nearest` (the default) the features are the
//!   sampled viewpoint nearest the centre eye's direction; an eye sees the
//!   object from up to `asin(|o| / (d - |o|))` away and can fall on a
//!   neighbouring viewpoint whose features ask for more detail, so there
//!   the rig is as right as the viewpoint sampling is fine.
//! - **Velocity** is judged from the centre eye; the eyes' own parallax
//!   motion adds to it only for objects within a few head lengths.

use glam::Vec3;

use crate::display::Display;
use crate::error::{Error, Result};
use crate::select::SelectorSettings;

/// One eye of a headset: its display (resolution, field of view given by
/// its edges, photometry, refresh rate) and its position relative to the
/// centre eye in the head's frame (x right, y up, -Z forward), world
/// units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// What the eye is shown.
    pub display: Display,
    /// Offset from the centre eye, head frame, world units; finite.
    pub offset: Vec3,
}

/// Two eyes whose view axes are parallel to the head's (see the module
/// docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StereoRig {
    left: Eye,
    right: Eye,
}

impl StereoRig {
    /// A rig from its two eyes. Fails when an offset is not finite or when
    /// the eyes' photometry or refresh rates differ (one selection judges
    /// contrast once for both).
    pub fn new(left: Eye, right: Eye) -> Result<Self> {
        for (name, eye) in [("left.offset", &left), ("right.offset", &right)] {
            if !eye.offset.is_finite() {
                return Err(Error::invalid(
                    "eye offset",
                    format!("{name} {} is not finite", eye.offset),
                ));
            }
        }
        if left.display.photometry() != right.display.photometry()
            || left.display.refresh_hz() != right.display.refresh_hz()
        {
            return Err(Error::invalid(
                "eye displays",
                "the two eyes' photometry and refresh rate must be the same",
            ));
        }
        Ok(Self { left, right })
    }

    /// A rig whose eyes sit `ipd / 2` left and right of the centre eye
    /// (`ipd`: the interpupillary distance, world units, finite, `>= 0`;
    /// 0.064 m is typical).
    pub fn from_ipd(left: Display, right: Display, ipd: f32) -> Result<Self> {
        if !(ipd.is_finite() && ipd >= 0.0) {
            return Err(Error::invalid(
                "ipd",
                format!("{ipd} is not a finite distance >= 0"),
            ));
        }
        let half = Vec3::new(0.5 * ipd, 0.0, 0.0);
        Self::new(
            Eye {
                display: left,
                offset: -half,
            },
            Eye {
                display: right,
                offset: half,
            },
        )
    }

    /// The left eye.
    pub fn left(&self) -> &Eye {
        &self.left
    }

    /// The right eye.
    pub fn right(&self) -> &Eye {
        &self.right
    }

    /// The display one selection for both eyes uses: the union of their
    /// fields of view ([`crate::display::FovEdges::union`]), with as many
    /// pixels on each axis as the finer eye has per degree over that field.
    pub fn selection_display(&self) -> Result<Display> {
        let (l, r) = (&self.left.display, &self.right.display);
        let edges = l.fov_edges().union(&r.fov_edges());
        let density = |d: &Display, axis: usize| d.resolution_px()[axis] as f32 / d.fov_deg()[axis];
        let fov = edges.fov_deg();
        let resolution_px = [0, 1].map(|axis| {
            let per_deg = density(l, axis).max(density(r, axis));
            (per_deg * fov[axis]).ceil().min(u32::MAX as f32) as u32
        });
        Display::with_fov_edges(resolution_px, edges)?
            .with_photometry(*l.photometry())?
            .with_refresh_hz(l.refresh_hz())
    }

    /// Twice the larger distance of an eye from the centre eye, world
    /// units: the [`SelectorSettings::radius_margin`] that makes one
    /// selection right for both eyes (see the module docs).
    pub fn radius_margin(&self) -> f32 {
        2.0 * self.left.offset.length().max(self.right.offset.length())
    }

    /// `settings` with [`StereoRig::radius_margin`] set.
    pub fn selector_settings(&self, settings: SelectorSettings) -> SelectorSettings {
        SelectorSettings {
            radius_margin: self.radius_margin(),
            ..settings
        }
    }
}

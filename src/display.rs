//! The display: resolution and field of view, the highest spatial
//! frequency it can show, and its light output.
//!
//! A field of view is symmetric about the view axis ([`Display::new`]) or
//! given by its four edges ([`FovEdges`], [`Display::with_fov_edges`]), as
//! a headset's per-eye fields are (OpenXR reports four angles per eye).
//! Pixels per degree are taken as uniform over the field: resolution over
//! field of view on each axis.

use glam::{DVec2, DVec3};

use crate::csf::Photometry;
use crate::error::{Error, Result};

/// A display as the viewer sees it: resolution in pixels, the field of
/// view the image subtends at the eye in degrees, and its photometry
/// (peak and black luminance; [`Photometry::default`] unless set).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Display {
    resolution_px: [u32; 2],
    fov_deg: [f32; 2],
    /// The direction of the field's middle from the view axis, deg (x
    /// right, y up): `[(left + right) / 2, (up + down) / 2]` of its edges;
    /// zero for a symmetric field.
    #[serde(default)]
    centre_deg: [f32; 2],
    #[serde(default)]
    photometry: Photometry,
    #[serde(default = "default_refresh_hz")]
    refresh_hz: Option<f32>,
}

/// Refresh rate of a display unless set otherwise, Hz: the common
/// sample-and-hold panel.
pub const DEFAULT_REFRESH_HZ: f32 = 60.0;

/// Largest field of view accepted, deg. A planar display subtends less than
/// 180 deg; the bound keeps `tan(fov / 2)` finite in `f32`.
pub const MAX_FOV_DEG: f32 = 179.9;
/// Smallest field of view accepted, deg.
pub const MIN_FOV_DEG: f32 = 1e-3;
/// Largest angle of a field's edge from the view axis, deg (half of
/// [`MAX_FOV_DEG`]): `tan` of it stays finite in `f32`.
pub const MAX_EDGE_DEG: f32 = 0.5 * MAX_FOV_DEG;

/// The four edges of a field of view: each edge's signed angle from the
/// view axis, deg, in OpenXR's `XrFovf` order and signs (x right, y up,
/// so `left_deg` and `down_deg` are negative when the view axis lies
/// inside the field). Each edge measures in its own axis's plane: the
/// right edge is the plane through the eye at `right_deg` to the right of
/// the view axis, and so on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FovEdges {
    /// Angle of the left edge, deg (negative left of the view axis).
    pub left_deg: f32,
    /// Angle of the right edge, deg.
    pub right_deg: f32,
    /// Angle of the upper edge, deg.
    pub up_deg: f32,
    /// Angle of the lower edge, deg (negative below the view axis).
    pub down_deg: f32,
}

impl FovEdges {
    /// The edges of a field `fov_deg` wide and tall (horizontal, vertical)
    /// centred on the view axis.
    pub fn symmetric(fov_deg: [f32; 2]) -> Self {
        let [h, v] = fov_deg.map(|a| 0.5 * a);
        Self {
            left_deg: -h,
            right_deg: h,
            up_deg: v,
            down_deg: -v,
        }
    }

    /// The edges from OpenXR's `XrFovf` angles, radians
    /// (`angleLeft`, `angleRight`, `angleUp`, `angleDown`).
    pub fn from_openxr_radians(left: f32, right: f32, up: f32, down: f32) -> Self {
        Self {
            left_deg: left.to_degrees(),
            right_deg: right.to_degrees(),
            up_deg: up.to_degrees(),
            down_deg: down.to_degrees(),
        }
    }

    /// Width and height of the field, deg: `right - left`, `up - down`.
    pub fn fov_deg(&self) -> [f32; 2] {
        [self.right_deg - self.left_deg, self.up_deg - self.down_deg]
    }

    /// The smallest field that holds both: the outermost of each edge.
    pub fn union(&self, other: &Self) -> Self {
        Self {
            left_deg: self.left_deg.min(other.left_deg),
            right_deg: self.right_deg.max(other.right_deg),
            up_deg: self.up_deg.max(other.up_deg),
            down_deg: self.down_deg.min(other.down_deg),
        }
    }
}

fn default_refresh_hz() -> Option<f32> {
    Some(DEFAULT_REFRESH_HZ)
}

impl Display {
    /// A display from its resolution (pixels, horizontal then vertical,
    /// each at least 1) and field of view (deg, horizontal then vertical,
    /// each in `[MIN_FOV_DEG, MAX_FOV_DEG]`). Zero or 180-degree fields of
    /// view and zero resolutions are refused.
    pub fn new(resolution_px: [u32; 2], fov_deg: [f32; 2]) -> Result<Self> {
        for (axis, &px) in ["horizontal", "vertical"].iter().zip(&resolution_px) {
            if px == 0 {
                return Err(Error::invalid(
                    "resolution_px",
                    format!("{axis} resolution is 0 pixels"),
                ));
            }
        }
        for (axis, &fov) in ["horizontal", "vertical"].iter().zip(&fov_deg) {
            if !(MIN_FOV_DEG..=MAX_FOV_DEG).contains(&fov) {
                return Err(Error::invalid(
                    "fov_deg",
                    format!(
                        "{axis} field of view {fov} deg is outside [{MIN_FOV_DEG}, {MAX_FOV_DEG}]"
                    ),
                ));
            }
        }
        Ok(Self {
            resolution_px,
            fov_deg,
            centre_deg: [0.0; 2],
            photometry: Photometry::default(),
            refresh_hz: Some(DEFAULT_REFRESH_HZ),
        })
    }

    /// A display whose field of view is given by its edges (an asymmetric
    /// field, as a headset's eye has): each edge finite and within
    /// `±MAX_EDGE_DEG`, right of left and up of down by at least
    /// [`MIN_FOV_DEG`]; resolution as in [`Display::new`]. The view axis
    /// (where [`crate::Gaze::screen_centre`] looks) need not be the
    /// field's middle.
    pub fn with_fov_edges(resolution_px: [u32; 2], edges: FovEdges) -> Result<Self> {
        let FovEdges {
            left_deg,
            right_deg,
            up_deg,
            down_deg,
        } = edges;
        for (name, a) in [
            ("left_deg", left_deg),
            ("right_deg", right_deg),
            ("up_deg", up_deg),
            ("down_deg", down_deg),
        ] {
            if !(-MAX_EDGE_DEG..=MAX_EDGE_DEG).contains(&a) {
                return Err(Error::invalid(
                    "fov_edges",
                    format!("{name} {a} deg is outside [-{MAX_EDGE_DEG}, {MAX_EDGE_DEG}]"),
                ));
            }
        }
        let mut display = Self::new(resolution_px, edges.fov_deg()).map_err(|e| match e {
            Error::InvalidParameter { reason, .. } => Error::invalid(
                "fov_edges",
                format!("{reason} (left {left_deg}, right {right_deg}, up {up_deg}, down {down_deg} deg)"),
            ),
            other => other,
        })?;
        display.centre_deg = [0.5 * (left_deg + right_deg), 0.5 * (up_deg + down_deg)];
        Ok(display)
    }

    /// The edges of the field of view, deg.
    pub fn fov_edges(&self) -> FovEdges {
        let [h, v] = self.fov_deg.map(|a| 0.5 * a);
        let [cx, cy] = self.centre_deg;
        FovEdges {
            left_deg: cx - h,
            right_deg: cx + h,
            up_deg: cy + v,
            down_deg: cy - v,
        }
    }

    /// The same display refreshed `refresh_hz` times a second, each frame
    /// held until the next (sample and hold, as LCD and OLED panels and
    /// headsets show them; default [`DEFAULT_REFRESH_HZ`]). Motion then
    /// hides less detail: content that moves a pixel or more per frame is
    /// seen as still frames ([`crate::csf::Csf::sampled_motion_floor`]).
    /// `None` treats motion as continuous, as the velocity models were
    /// measured; on a real panel that drops detail a fixating viewer
    /// sees. A rate must be finite and in `[1, 10000]` Hz.
    pub fn with_refresh_hz(self, refresh_hz: Option<f32>) -> Result<Self> {
        if let Some(hz) = refresh_hz
            && !(1.0..=10_000.0).contains(&hz)
        {
            return Err(Error::invalid(
                "refresh_hz",
                format!("{hz} Hz is outside [1, 10000]"),
            ));
        }
        Ok(Self { refresh_hz, ..self })
    }

    /// The refresh rate, Hz; `None` for continuous motion.
    pub fn refresh_hz(&self) -> Option<f32> {
        self.refresh_hz
    }

    /// The same display with other photometry (validated; the error names
    /// the field).
    pub fn with_photometry(self, photometry: Photometry) -> Result<Self> {
        photometry.validate()?;
        Ok(Self { photometry, ..self })
    }

    /// The display's photometry.
    pub fn photometry(&self) -> &Photometry {
        &self.photometry
    }

    /// A display from its physical size and the viewing distance: a
    /// `screen_size_cm` wide and tall image seen from `distance_cm` subtends
    /// `2 atan(size / (2 distance))` on each axis. All lengths must be
    /// finite and positive (any one unit will do, as long as both share it).
    pub fn from_physical(
        resolution_px: [u32; 2],
        screen_size_cm: [f32; 2],
        distance_cm: f32,
    ) -> Result<Self> {
        if !(distance_cm.is_finite() && distance_cm > 0.0) {
            return Err(Error::invalid(
                "distance_cm",
                format!("viewing distance {distance_cm} cm is not a positive finite length"),
            ));
        }
        let mut fov_deg = [0.0; 2];
        for (i, &size) in screen_size_cm.iter().enumerate() {
            if !(size.is_finite() && size > 0.0) {
                return Err(Error::invalid(
                    "screen_size_cm",
                    format!("screen size {size} cm is not a positive finite length"),
                ));
            }
            fov_deg[i] = physical_fov_deg(f64::from(size), f64::from(distance_cm)) as f32;
        }
        Self::new(resolution_px, fov_deg)
    }

    /// Resolution in pixels, horizontal then vertical.
    pub fn resolution_px(&self) -> [u32; 2] {
        self.resolution_px
    }

    /// Field of view in degrees, horizontal then vertical.
    pub fn fov_deg(&self) -> [f32; 2] {
        self.fov_deg
    }

    /// The display limit `xi` in c/deg (Reddy 1998, eq. 4): one pixel is
    /// half a cycle, and the finer of the two axes counts,
    /// `max(h_px / (2 h_fov), v_px / (2 v_fov))`.
    pub fn max_frequency_cpd(&self) -> f32 {
        let h = self.resolution_px[0] as f32 / (2.0 * self.fov_deg[0]);
        let v = self.resolution_px[1] as f32 / (2.0 * self.fov_deg[1]);
        h.max(v)
    }

    /// Average pixels per degree, the larger of the two axes (`2 xi`).
    pub fn pixels_per_degree(&self) -> f32 {
        2.0 * self.max_frequency_cpd()
    }

    /// The angular size in deg an object has when it fills the display:
    /// the larger field of view. Used when the size component is off.
    pub fn filling_angular_size_deg(&self) -> f32 {
        self.fov_deg[0].max(self.fov_deg[1])
    }
}

/// The field of view in deg that a planar screen `size` across subtends
/// from `distance` on its centre line: `2 atan(size / (2 distance))`. Any
/// one length unit for both; meaningful for finite, positive lengths (the
/// callers check them).
pub fn physical_fov_deg(size: f64, distance: f64) -> f64 {
    2.0 * (0.5 * size / distance).atan().to_degrees()
}

/// The perspective scale `1 / tan(fov / 2)` of an axis with a field of
/// view of `fov_deg` (0 to 180 deg, exclusive): how far in image halves a
/// direction of slope 1 off the view axis lands from the centre.
pub fn projection_scale(fov_deg: f64) -> f64 {
    1.0 / half_tan(fov_deg)
}

/// `tan(fov / 2)`: half the extent of the image plane one unit ahead.
fn half_tan(fov_deg: f64) -> f64 {
    (0.5 * fov_deg).to_radians().tan()
}

/// Largest angle from the view axis, deg, that a direction through a
/// point of a planar display can make: 89 deg keeps `tan` finite.
pub const MAX_SCREEN_ANGLE_DEG: f64 = 89.0;

/// The camera-space unit direction (-Z forward, +X right, +Y up) through a
/// point of a planar display given as angles from its centre in deg
/// (`x` right, `y` up), each measured in its own axis's plane, so the
/// point sits at `(tan x, tan y)` on the plane one unit ahead. Angles are
/// clamped into `[-89, 89]` deg; non-finite ones count as 0.
pub fn screen_angles_to_direction(angles_deg: DVec2) -> DVec3 {
    let slope = |a: f64| {
        if a.is_finite() {
            a.clamp(-MAX_SCREEN_ANGLE_DEG, MAX_SCREEN_ANGLE_DEG)
                .to_radians()
                .tan()
        } else {
            0.0
        }
    };
    DVec3::new(slope(angles_deg.x), slope(angles_deg.y), -1.0).normalize()
}

/// Where a camera-space direction (-Z forward) lands in an image of
/// `resolution_px` covering `fov_deg` (symmetric about the view axis)
/// under a perspective projection, in pixels:
/// [`direction_to_pixel_in_edges`] of the symmetric edges.
pub fn direction_to_pixel(
    direction_camera: DVec3,
    resolution_px: [u32; 2],
    fov_deg: [f64; 2],
) -> [f64; 2] {
    let [h, v] = fov_deg.map(|a| 0.5 * a);
    direction_to_pixel_in_edges(direction_camera, resolution_px, [-h, h, v, -v])
}

/// Where a camera-space direction (-Z forward) lands in an image of
/// `resolution_px` whose field of view has the edges `edges_deg` (left,
/// right, up, down, signed as [`FovEdges`]) under a perspective
/// projection, in pixels: origin at the top-left corner, x right, y down.
/// Directions off screen give coordinates outside the image; one more than
/// 89 deg off the view axis (or behind) is taken at 89 deg; a zero or
/// non-finite direction gives the view axis.
pub fn direction_to_pixel_in_edges(
    direction_camera: DVec3,
    resolution_px: [u32; 2],
    edges_deg: [f64; 4],
) -> [f64; 2] {
    let [w, h] = resolution_px.map(f64::from);
    let [left, right, up, down] = edges_deg.map(|a| a.to_radians().tan());
    let lateral = direction_camera.x.hypot(direction_camera.y);
    let min_forward = lateral * (90.0 - MAX_SCREEN_ANGLE_DEG).to_radians().tan();
    let forward = (-direction_camera.z).max(min_forward);
    let (sx, sy) = if forward.is_finite() && forward > 0.0 {
        (direction_camera.x / forward, direction_camera.y / forward)
    } else {
        (0.0, 0.0)
    };
    [
        w * ((sx - left) / (right - left)),
        h * ((up - sy) / (up - down)),
    ]
}

/// The perspective projection (wgpu clip conventions: right-handed, -Z
/// forward, depth 0 at `near` and 1 at infinity) of a field of view with
/// the edges `edges_deg` (left, right, up, down, signed as [`FovEdges`]),
/// as the columns of a 4x4 matrix. Symmetric edges give the usual
/// infinite projection with separate x and y scales.
pub fn projection_columns(edges_deg: [f64; 4], near: f64) -> [[f64; 4]; 4] {
    let [left, right, up, down] = edges_deg.map(|a| a.to_radians().tan());
    let (sx, sy) = (2.0 / (right - left), 2.0 / (up - down));
    let (ox, oy) = ((right + left) / (right - left), (up + down) / (up - down));
    [
        [sx, 0.0, 0.0, 0.0],
        [0.0, sy, 0.0, 0.0],
        [ox, oy, -1.0, -1.0],
        [0.0, 0.0, -near, 0.0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reddy_1998_desktop_limit_is_12_5_cpd() {
        let d = Display::new([1280, 1024], [53.1, 41.1]).unwrap();
        assert!((d.max_frequency_cpd() - 12.5).abs() < 0.05);
    }

    #[test]
    fn physical_size_gives_the_same_limit_as_its_angles() {
        // 40 x 30 cm at 40 cm: 2 atan(0.5) = 53.13 deg, 2 atan(0.375) = 41.11 deg.
        let d = Display::from_physical([1280, 1024], [40.0, 30.0], 40.0).unwrap();
        assert!((d.fov_deg()[0] - 53.13).abs() < 0.01);
        assert!((d.fov_deg()[1] - 41.11).abs() < 0.01);
        assert!((d.max_frequency_cpd() - 12.45).abs() < 0.02);
    }

    #[test]
    fn degenerate_displays_are_refused() {
        assert!(Display::new([0, 1024], [50.0, 40.0]).is_err());
        assert!(Display::new([1280, 1024], [0.0, 40.0]).is_err());
        assert!(Display::new([1280, 1024], [180.0, 40.0]).is_err());
        assert!(Display::new([1280, 1024], [f32::NAN, 40.0]).is_err());
        assert!(Display::from_physical([1280, 1024], [40.0, 30.0], 0.0).is_err());
        assert!(Display::from_physical([1280, 1024], [-1.0, 30.0], 40.0).is_err());
        assert!(Display::new([1280, 1024], [179.9, 0.001]).is_ok());
    }

    #[test]
    fn asymmetric_edges_project_to_the_image_edges() {
        let edges = [-54.0, 50.0, 52.0, -40.0];
        let cols = projection_columns(edges, 0.1);
        let project = |d: DVec3| {
            let clip =
                [0, 1, 3].map(|r| (0..3).map(|c| cols[c][r] * [d.x, d.y, d.z][c]).sum::<f64>());
            [clip[0] / clip[2], clip[1] / clip[2]]
        };
        let at = |x_deg: f64, y_deg: f64| screen_angles_to_direction(DVec2::new(x_deg, y_deg));
        for (d, ndc) in [
            (at(-54.0, 0.0), [-1.0, f64::NAN]),
            (at(50.0, 0.0), [1.0, f64::NAN]),
            (at(0.0, 52.0), [f64::NAN, 1.0]),
            (at(0.0, -40.0), [f64::NAN, -1.0]),
        ] {
            let p = project(d);
            for k in 0..2 {
                assert!(
                    ndc[k].is_nan() || (p[k] - ndc[k]).abs() < 1e-9,
                    "{p:?} vs {ndc:?}"
                );
            }
        }
        let px = direction_to_pixel_in_edges(at(-54.0, 52.0), [1000, 800], edges);
        assert!(px[0].abs() < 1e-9 && px[1].abs() < 1e-9, "{px:?}");
        let px = direction_to_pixel_in_edges(at(50.0, -40.0), [1000, 800], edges);
        assert!(
            (px[0] - 1000.0).abs() < 1e-9 && (px[1] - 800.0).abs() < 1e-9,
            "{px:?}"
        );
    }
}

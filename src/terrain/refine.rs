//! One frame of terrain refinement: the top-down walk, the perceptual
//! split test, viewport culling and the crack-free triangulation.

use glam::{Quat, Vec3};

use super::{Terrain, Vertex, children, node_rect};
use crate::acuity::{Components, EccentricityModel, VelocityModel};
use crate::camera::Camera;
use crate::error::{Error, Result};

/// How a frame is refined: which criteria apply and the display they apply
/// to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerrainSettings {
    /// The perceptual criteria. Size off refines every drawn node to full
    /// resolution (velocity and eccentricity then have nothing to act on:
    /// they lower the frequency a node's error must reach, and without
    /// size the error is not consulted).
    pub components: Components,
    /// Skip nodes outside the field of view (not split, not drawn).
    pub viewport_cull: bool,
    /// The field of view, horizontal then vertical, deg: an equiangular
    /// box of azimuth and elevation about the camera's forward direction
    /// (a planar frustum cannot exceed 180 deg; Reddy's runs used 200 x
    /// 135). Each in `(0, 360]` and `(0, 180]`.
    pub fov_deg: [f32; 2],
    /// The display limit `xi`, c/deg (finite, > 0).
    pub display_limit_cpd: f32,
    /// Global scale factor `s` in `(0, 1]`.
    pub scale: f32,
    /// How acuity falls with eccentricity.
    pub eccentricity_model: EccentricityModel,
    /// How acuity falls with retinal velocity.
    pub velocity_model: VelocityModel,
}

impl TerrainSettings {
    fn validate(&self) -> Result<()> {
        let [h, v] = self.fov_deg;
        if !(h > 0.0 && h <= 360.0 && v > 0.0 && v <= 180.0) {
            return Err(Error::invalid(
                "fov_deg",
                format!("{h} x {v} deg is not in (0, 360] x (0, 180]"),
            ));
        }
        if !(self.display_limit_cpd.is_finite() && self.display_limit_cpd > 0.0) {
            return Err(Error::invalid(
                "display_limit_cpd",
                format!("{} is not a finite frequency > 0", self.display_limit_cpd),
            ));
        }
        if !(self.scale > 0.0 && self.scale <= 1.0) {
            return Err(Error::invalid(
                "scale",
                format!("{} is not in (0, 1]", self.scale),
            ));
        }
        Ok(())
    }
}

/// Where the viewer is this frame. The gaze is the centre of the view (no
/// tracking, as in Reddy's runs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TerrainView {
    /// The camera now.
    pub camera: Camera,
    /// The camera `dt_s` seconds earlier, for retinal velocity: a node's
    /// velocity is the angle its centre's direction turned through in the
    /// camera's frame over that time (taking it over several frames
    /// smooths it). `None`: velocity 0.
    pub previous: Option<Camera>,
    /// Seconds between `previous` and `camera` (finite, > 0 when
    /// `previous` is given).
    pub dt_s: f32,
}

/// Counts of one refinement.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RefineStats {
    /// Nodes the walk looked at.
    pub nodes_visited: usize,
    /// Nodes skipped as outside the field of view.
    pub nodes_culled: usize,
    /// Leaves drawn.
    pub leaves: usize,
    /// Triangles drawn.
    pub triangles: usize,
}

/// One frame's refined mesh and the buffers that make it; reuse it across
/// frames so that refinement allocates nothing once they have grown.
#[derive(Clone, Debug, Default)]
pub struct Refinement {
    /// Leaves as sample rectangles `[x0, y0, x1, y1]`.
    leaves: Vec<[u32; 4]>,
    triangles: Vec<[Vertex; 3]>,
    /// Per sample, the frame stamp of the last refinement that used it as a
    /// leaf corner.
    stamps: Vec<u32>,
    stamp: u32,
    /// Nodes to visit: level, column, row, and whether the node is kept
    /// whole by viewport culling (no further test).
    stack: Vec<(u32, u32, u32, bool)>,
    boundary: Vec<Vertex>,
    stats: RefineStats,
}

impl Refinement {
    /// An empty refinement.
    pub fn new() -> Self {
        Self::default()
    }

    /// The triangles, counter-clockwise seen from above (`+z`).
    pub fn triangles(&self) -> &[[Vertex; 3]] {
        &self.triangles
    }

    /// The leaves, as sample rectangles `[x0, y0, x1, y1]`.
    pub fn leaves(&self) -> &[[u32; 4]] {
        &self.leaves
    }

    /// The counts of the last refinement.
    pub fn stats(&self) -> RefineStats {
        self.stats
    }
}

/// Per-frame constants of the split test.
struct Frame {
    eye: Vec3,
    to_camera: Quat,
    previous: Option<(Vec3, Quat, f32)>,
    half_fov_deg: [f32; 2],
}

impl Terrain {
    /// Refines the terrain for one frame into `out` (its previous contents
    /// are replaced). A node splits while its geometric error, seen at the
    /// distance of its nearest point, is a feature of frequency `f = 1 /
    /// (2 alpha)` c/deg (`alpha` the error's angle) at or below `T = s *
    /// min(G(v) M(E), xi)` (Reddy 2001 eq. 4), with `E` the angle from the
    /// gaze to the node's bounding sphere and `v` its centre's retinal
    /// velocity; a component that is off sets its term as the model's
    /// orthogonality says. Fails on settings or a view outside their
    /// documented domains.
    pub fn refine(
        &self,
        view: &TerrainView,
        settings: &TerrainSettings,
        out: &mut Refinement,
    ) -> Result<()> {
        settings.validate()?;
        let to_camera = view.camera.validate()?.inverse();
        let previous = match view.previous {
            Some(p) if settings.components.velocity => {
                if !(view.dt_s.is_finite() && view.dt_s > 0.0) {
                    return Err(Error::invalid(
                        "dt_s",
                        format!("{} s is not a finite time > 0", view.dt_s),
                    ));
                }
                Some((p.position.as_vec3(), p.validate()?.inverse(), view.dt_s))
            }
            _ => None,
        };
        let frame = Frame {
            eye: view.camera.position.as_vec3(),
            to_camera,
            previous,
            half_fov_deg: settings.fov_deg.map(|a| 0.5 * a),
        };
        self.walk(&frame, settings, out);
        self.triangulate(out);
        Ok(())
    }

    fn walk(&self, frame: &Frame, settings: &TerrainSettings, out: &mut Refinement) {
        let cells = self.cells();
        out.leaves.clear();
        out.stack.clear();
        out.stats = RefineStats::default();
        out.stack.push((0, 0, 0, !settings.viewport_cull));
        let last = self.levels.len() as u32 - 1;
        while let Some((k, i, j, kept)) = out.stack.pop() {
            out.stats.nodes_visited += 1;
            let level = &self.levels[k as usize];
            let n = (j * level.nx + i) as usize;
            let rect = node_rect(level.size, i, j, cells);
            let node = self.node_geometry(rect, level.z_range[n], frame);
            // Culling decides from geometry alone (see `CULL_NODE_CELLS`).
            let (kept, forced) = if kept {
                (true, false)
            } else {
                match node.in_view(frame.half_fov_deg) {
                    InView::Outside => {
                        out.stats.nodes_culled += 1;
                        continue;
                    }
                    InView::Inside => (true, false),
                    InView::Straddling => {
                        let large = level.size > CULL_NODE_CELLS;
                        (!large, large)
                    }
                }
            };
            if k == last || !(forced || self.splits(&node, level.error[n], frame, settings)) {
                out.leaves.push(rect);
                continue;
            }
            let finer = &self.levels[k as usize + 1];
            for (ci, cj) in children(i, j, finer.nx, finer.ny) {
                out.stack.push((k + 1, ci, cj, kept));
            }
        }
        out.stats.leaves = out.leaves.len();
    }

    fn node_geometry(&self, [x0, y0, x1, y1]: [u32; 4], z: [f32; 2], frame: &Frame) -> Node {
        let s = self.field.spacing;
        let lo = Vec3::new(x0 as f32 * s, y0 as f32 * s, z[0]);
        let hi = Vec3::new(x1 as f32 * s, y1 as f32 * s, z[1]);
        let centre = 0.5 * (lo + hi);
        let nearest = frame.eye.clamp(lo, hi);
        Node {
            centre,
            radius: 0.5 * (hi - lo).length(),
            offset: centre - frame.eye,
            nearest_distance: (nearest - frame.eye).length(),
            to_camera: frame.to_camera,
        }
    }

    fn splits(&self, node: &Node, error: f32, frame: &Frame, settings: &TerrainSettings) -> bool {
        let c = settings.components;
        if !c.size {
            return true;
        }
        if error <= 0.0 {
            return false;
        }
        if node.nearest_distance <= 1e-6 * self.field.spacing {
            return true;
        }
        let alpha_deg = error.atan2(node.nearest_distance).to_degrees();
        let freq_cpd = 0.5 / alpha_deg;
        let eccentricity_deg = if c.eccentricity {
            node.eccentricity_deg()
        } else {
            0.0
        };
        let velocity_deg_per_s = match frame.previous {
            Some(prev) if c.velocity => node.velocity_deg_per_s(prev),
            _ => 0.0,
        };
        let acuity_cpd = settings.velocity_model.acuity_cpd(velocity_deg_per_s)
            * settings.eccentricity_model.factor(eccentricity_deg);
        let threshold_cpd =
            crate::acuity::threshold_cpd(acuity_cpd, settings.display_limit_cpd, settings.scale);
        freq_cpd <= threshold_cpd
    }

    /// Marks every leaf corner, then triangulates each leaf through the
    /// marked samples on its edges (see the module docs).
    fn triangulate(&self, out: &mut Refinement) {
        let [w, h] = self.field.size();
        if out.stamps.len() != w * h {
            out.stamps.clear();
            out.stamps.resize(w * h, 0);
            out.stamp = 0;
        }
        out.stamp = out.stamp.wrapping_add(1);
        if out.stamp == 0 {
            out.stamps.fill(0);
            out.stamp = 1;
        }
        let stamp = out.stamp;
        for &[x0, y0, x1, y1] in &out.leaves {
            for (x, y) in [(x0, y0), (x1, y0), (x0, y1), (x1, y1)] {
                out.stamps[y as usize * w + x as usize] = stamp;
            }
        }
        out.triangles.clear();
        let marked = |stamps: &[u32], x: u32, y: u32| stamps[y as usize * w + x as usize] == stamp;
        for &[x0, y0, x1, y1] in &out.leaves {
            let b = &mut out.boundary;
            b.clear();
            b.push([2 * x0, 2 * y0]);
            b.extend(
                ((x0 + 1)..x1)
                    .filter(|&x| marked(&out.stamps, x, y0))
                    .map(|x| [2 * x, 2 * y0]),
            );
            b.push([2 * x1, 2 * y0]);
            b.extend(
                ((y0 + 1)..y1)
                    .filter(|&y| marked(&out.stamps, x1, y))
                    .map(|y| [2 * x1, 2 * y]),
            );
            b.push([2 * x1, 2 * y1]);
            b.extend(
                ((x0 + 1)..x1)
                    .rev()
                    .filter(|&x| marked(&out.stamps, x, y1))
                    .map(|x| [2 * x, 2 * y1]),
            );
            b.push([2 * x0, 2 * y1]);
            b.extend(
                ((y0 + 1)..y1)
                    .rev()
                    .filter(|&y| marked(&out.stamps, x0, y))
                    .map(|y| [2 * x0, 2 * y]),
            );
            if b.len() == 4 {
                out.triangles.push([b[0], b[1], b[2]]);
                out.triangles.push([b[0], b[2], b[3]]);
            } else {
                let centre = [x0 + x1, y0 + y1];
                for t in 0..b.len() {
                    out.triangles.push([centre, b[t], b[(t + 1) % b.len()]]);
                }
            }
        }
        out.stats.triangles = out.triangles.len();
    }
}

/// Side of the nodes at which viewport culling stops, cells. A node
/// straddling the view's edge is split, whatever the criteria, until its
/// side is at most this; from there (or from a node wholly inside) the
/// subtree is kept whole, and only the criteria split it. So culling
/// decides from geometry alone and every row of criteria draws the same
/// region: adding a criterion only coarsens the mesh within it, as it
/// does without culling. A straddling node drawn whole under a coarse
/// criterion while a finer one dropped its children outside would break
/// that. The price: the forced splits along the view's edges, and the
/// strip beyond the edge (at most 16 cells deep) drawn as the criteria
/// say (measured in `docs/reddy2001.md`).
pub const CULL_NODE_CELLS: u32 = 16;

/// A node's bounding sphere against the field of view.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum InView {
    Outside,
    Straddling,
    Inside,
}

/// A node's bounding box as the eye sees it.
struct Node {
    centre: Vec3,
    radius: f32,
    /// Centre minus eye.
    offset: Vec3,
    /// Distance from the eye to the nearest point of the box.
    nearest_distance: f32,
    to_camera: Quat,
}

impl Node {
    /// Angular radius of the bounding sphere, deg (90 with the eye inside).
    fn angular_radius_deg(&self) -> f32 {
        let d = self.offset.length();
        if d <= self.radius {
            90.0
        } else {
            (self.radius / d).asin().to_degrees()
        }
    }

    /// Where the bounding sphere lies against the azimuth-elevation box.
    /// `Inside` only when every direction of the sphere is in the box;
    /// `Outside` only when none is.
    fn in_view(&self, half_fov_deg: [f32; 2]) -> InView {
        let d = self.offset.length();
        if d <= self.radius {
            return InView::Straddling;
        }
        let rho = self.angular_radius_deg();
        let c = self.to_camera * self.offset;
        let azimuth = c.x.atan2(-c.z).to_degrees().abs();
        let elevation = (c.y / d).clamp(-1.0, 1.0).asin().to_degrees().abs();
        if elevation - rho > half_fov_deg[1] {
            return InView::Outside;
        }
        if elevation + rho >= 90.0 {
            // The cap holds a pole: it spans every azimuth.
            return InView::Straddling;
        }
        // The azimuth half-span of a cap of radius rho at this elevation.
        let span = (rho.to_radians().sin() / elevation.to_radians().cos())
            .min(1.0)
            .asin()
            .to_degrees();
        if azimuth - span > half_fov_deg[0] {
            InView::Outside
        } else if elevation + rho <= half_fov_deg[1] && azimuth + span <= half_fov_deg[0] {
            InView::Inside
        } else {
            InView::Straddling
        }
    }

    /// Angle from the gaze (the view's centre) to the bounding sphere, deg.
    fn eccentricity_deg(&self) -> f32 {
        let c = self.to_camera * self.offset;
        let d = c.length();
        if d <= self.radius {
            return 0.0;
        }
        let to_centre = (-c.z / d).clamp(-1.0, 1.0).acos().to_degrees();
        (to_centre - self.angular_radius_deg()).max(0.0)
    }

    /// Angle the centre's direction turned in the camera's frame since the
    /// previous camera, over the time between them, deg/s (0 if undefined).
    fn velocity_deg_per_s(&self, (eye, to_camera, dt_s): (Vec3, Quat, f32)) -> f32 {
        let now = self.to_camera * self.offset;
        let before = to_camera * (self.centre - eye);
        let angle = now.cross(before).length().atan2(now.dot(before));
        let v = angle.to_degrees() / dt_s;
        if v.is_finite() { v } else { 0.0 }
    }
}

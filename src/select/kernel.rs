//! The selection loop over blocks of objects (one algorithm): cull each
//! block branch-free, queue the visible objects of sparse blocks, model
//! them in short vectorised passes (size, eccentricity, velocity, acuity),
//! find their rows and count their LODs, and write the outputs back.

#[cfg(not(target_feature = "sse2"))]
use glam::Quat;
use glam::Vec3;

use crate::acuity::{
    DRIFT_VELOCITY_DEG_PER_S, ECCENTRICITY_CEILING_DEG, ECCENTRICITY_FLOOR_DEG, EccentricityModel,
    MAX_ACUITY_CPD, MAX_ECCENTRICITY_DEG, MIN_ACUITY_CPD, VELOCITY_CEILING_DEG_PER_S,
    VELOCITY_FLOOR_DEG_PER_S, VelocityModel, cortical_factor_unchecked,
    kelly_velocity_acuity_unchecked, reddy_eccentricity_factor_unchecked, reddy_velocity_piece_cpd,
};
use crate::fastmath;
use crate::viewpoints;

use super::frame::FrameConsts;
use super::rule::{count_coarser_padded, count_rows, rung_and_judged_size, rung_of};
use super::store::{Block, BudgetEntry, MotionBlock};
use super::tables::RowLayout;
use super::{BLOCK, Diagnostics, MAX_VELOCITY_DEG_PER_S, NO_LOOKUP, RAD_TO_DEG, Selection};

/// Capacity of the queue of visible objects (of sparse blocks): it is
/// modelled when the next block's would not fit, and at the end.
const QUEUE: usize = BLOCK;

/// Objects to model, field by field: a block's lanes straight from
/// the cull pass, or a queue of visible objects gathered from sparse blocks.
struct Batch {
    /// Object index within the work item.
    index: [u32; QUEUE],
    /// Direction to the camera in the object's frame, not normalised
    /// (x, y, z; with the nearest-viewpoint rule).
    to_camera: [[f32; QUEUE]; 3],
    /// Centre in the eye's frame (x, y, z).
    p: [[f32; QUEUE]; 3],
    /// Squared distance.
    d2: [f32; QUEUE],
    radius: [f32; QUEUE],
    /// Start of the object's row (see [`Block::row0`]).
    row0: [u32; QUEUE],
    /// Last frame's direction and velocity (with the velocity component).
    dir_before: [[f32; QUEUE]; 3],
    velocity_before: [f32; QUEUE],
}

const EMPTY_BATCH: Batch = Batch {
    index: [0; QUEUE],
    to_camera: [[0.0; QUEUE]; 3],
    p: [[0.0; QUEUE]; 3],
    d2: [0.0; QUEUE],
    radius: [0.0; QUEUE],
    row0: [0; QUEUE],
    dir_before: [[0.0; QUEUE]; 3],
    velocity_before: [0.0; QUEUE],
};

/// Blocks with at least this many visible objects are modelled whole (the
/// culled lanes' results are dropped), which costs less than moving the
/// visible ones to the queue.
const DENSE_BLOCK: usize = 40;

/// The model's results for a batch.
struct Modelled {
    theta_deg: [f32; QUEUE],
    inv_d: [f32; QUEUE],
    eccentricity_deg: [f32; QUEUE],
    /// This frame's direction and smoothed velocity (the motion state).
    dir: [[f32; QUEUE]; 3],
    velocity: [f32; QUEUE],
    /// The velocity the model uses (0 for the pursued object).
    seen_velocity: [f32; QUEUE],
    threshold_cpd: [f32; QUEUE],
    k_cdiam: [f32; QUEUE],
    /// The viewpoint whose row applies.
    view: [u32; QUEUE],
    /// Start of the object's prefix-minimum row in the selector's rows.
    row: [u32; QUEUE],
    /// The chosen LOD.
    lod: [u32; QUEUE],
}

const EMPTY_MODELLED: Modelled = Modelled {
    theta_deg: [0.0; QUEUE],
    inv_d: [0.0; QUEUE],
    eccentricity_deg: [0.0; QUEUE],
    dir: [[0.0; QUEUE]; 3],
    velocity: [0.0; QUEUE],
    seen_velocity: [0.0; QUEUE],
    threshold_cpd: [0.0; QUEUE],
    k_cdiam: [0.0; QUEUE],
    view: [0; QUEUE],
    row: [0; QUEUE],
    lod: [0; QUEUE],
};

/// `conjugate(q) * -rel` (the direction to the camera in the object's
/// frame) with the operations of glam's SSE2 `Quat * Vec3`, in its order,
/// so that it rounds the same (`to_object_frame_rounds_like_glam` checks
/// this); `q` is `[x, y, z, w]`.
#[cfg(target_feature = "sse2")]
#[inline(always)]
pub(super) fn to_object_frame(q: [f32; 4], rel: [f32; 3]) -> [f32; 3] {
    let (bx, by, bz, w) = (-q[0], -q[1], -q[2], q[3]);
    let (vx, vy, vz) = (-rel[0], -rel[1], -rel[2]);
    let b2 = bx * bx + by * by + bz * bz;
    let vb2 = (vx * bx + vy * by + vz * bz) * 2.0;
    let (ww, w2) = (w * w - b2, w * 2.0);
    // glam's cross product is `a * b - c * d`, fused with FMA.
    #[cfg(target_feature = "fma")]
    let mul_sub = |a: f32, b: f32, c: f32, d: f32| (-c).mul_add(d, a * b);
    #[cfg(not(target_feature = "fma"))]
    let mul_sub = |a: f32, b: f32, c: f32, d: f32| a * b - c * d;
    let cx = mul_sub(by, vz, vy, bz);
    let cy = mul_sub(bz, vx, vz, bx);
    let cz = mul_sub(bx, vy, vx, by);
    [
        vx * ww + bx * vb2 + cx * w2,
        vy * ww + by * vb2 + cy * w2,
        vz * ww + bz * vb2 + cz * w2,
    ]
}

/// `conjugate(q) * -rel` by glam itself, where its `Quat` is not SSE2.
#[cfg(not(target_feature = "sse2"))]
#[inline(always)]
pub(super) fn to_object_frame(q: [f32; 4], rel: [f32; 3]) -> [f32; 3] {
    (Quat::from_array(q).conjugate() * -Vec3::from_array(rel)).to_array()
}

/// Culls a block into lanes `0..BLOCK` of `out`: branch-free over all
/// lanes, so it vectorises. With `NEAREST`, also the direction to the
/// camera in each object's frame. `visible` is 1 for each visible object
/// and 0 for each culled one and each lane past `live`.
#[inline(always)]
fn cull_block<const CULL: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    b: &Block,
    live: usize,
    out: &mut Batch,
    visible: &mut [u32; BLOCK],
) {
    let [cx, cy, cz] = c.cam_pos.to_array();
    let m = c.world_to_eye;
    let [n0, n1, n2, n3] = c.planes_eye;
    let f = c.forward_eye;
    // The `f64` subtraction in a loop of its own: the `f32` work below then
    // runs 4 lanes at a time.
    let mut rel = [[0.0f32; BLOCK]; 3];
    for i in 0..BLOCK {
        rel[0][i] = (b.x[i] - cx) as f32;
        rel[1][i] = (b.y[i] - cy) as f32;
        rel[2][i] = (b.z[i] - cz) as f32;
    }
    for i in 0..BLOCK {
        let (rx, ry, rz) = (rel[0][i], rel[1][i], rel[2][i]);
        // The operations of `Mat3 * Vec3` and `Vec3::dot`, in their order.
        let px = m.x_axis.x * rx + m.y_axis.x * ry + m.z_axis.x * rz;
        let py = m.x_axis.y * rx + m.y_axis.y * ry + m.z_axis.y * rz;
        let pz = m.x_axis.z * rx + m.y_axis.z * ry + m.z_axis.z * rz;
        let d2 = px * px + py * py + pz * pz;
        let r = b.radius[i] + c.radius_margin;
        if NEAREST {
            let q = [0, 1, 2, 3].map(|a| b.rotation[a][i]);
            let d = to_object_frame(q, [rx, ry, rz]);
            for a in 0..3 {
                out.to_camera[a][i] = d[a];
            }
        }
        out.p[0][i] = px;
        out.p[1][i] = py;
        out.p[2][i] = pz;
        out.d2[i] = d2;
        let seen = if CULL {
            let dot = |n: Vec3| n.x * px + n.y * py + n.z * pz;
            let outside = fastmath::max(
                fastmath::max(dot(n0), dot(n1)),
                fastmath::max(fastmath::max(dot(n2), dot(n3)), -dot(f)),
            ) > r;
            d2 <= r * r || !outside
        } else {
            true
        };
        visible[i] = (seen & (i < live)) as u32;
    }
}

/// The loop's outputs for a run of objects (all of them, or one parallel
/// work item of `dispatch`): selections, and diagnostics and budget
/// entries when asked for. Defined here, with the loop that writes them,
/// so `dispatch` depends on `kernel` and not the other way round.
pub(super) struct Outputs<'a> {
    pub(super) selections: &'a mut [Selection],
    pub(super) diagnostics: Option<&'a mut [Diagnostics]>,
    pub(super) budget: Option<&'a mut [BudgetEntry]>,
}

#[inline(always)]
pub(super) fn kernel<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    first_index: u32,
    out: Outputs<'_>,
) {
    let Outputs {
        selections,
        mut diagnostics,
        mut budget,
    } = out;
    let pursued = c.pursued.wrapping_sub(first_index);
    let object_profiles = &c.object_profiles[first_index as usize..];
    let mut block_batch = EMPTY_BATCH;
    let mut visible = [0u32; BLOCK];
    let mut lanes = [0u8; QUEUE];
    let mut queue = EMPTY_BATCH;
    let mut queued = 0;
    let mut m = EMPTY_MODELLED;
    let prefetch = Prefetch::new();
    let total = selections.len();
    let extras = diagnostics.is_some() || budget.is_some();
    for (bi, block) in blocks.iter().enumerate() {
        // A block's data is loaded at once and then worked on for long: the
        // hardware prefetcher does not run that far ahead on its own.
        if let Some(next) = blocks.get(bi + PREFETCH_BLOCKS) {
            prefetch.lines(next);
        }
        if VELOCITY && let Some(next) = motion.get(bi + PREFETCH_BLOCKS) {
            prefetch.lines(next);
        }
        if let Some(next) = selections.get((bi + PREFETCH_BLOCKS) * BLOCK) {
            prefetch.lines(next);
        }
        let base = bi * BLOCK;
        let live = (total - base).min(BLOCK);
        let bb = &mut block_batch;
        if c.cull {
            cull_block::<true, NEAREST>(c, block, live, bb, &mut visible);
        } else {
            cull_block::<false, NEAREST>(c, block, live, bb, &mut visible);
        }
        for i in 0..BLOCK {
            bb.index[i] = (base + i) as u32;
            bb.radius[i] = block.radius[i] + c.radius_margin;
            bb.row0[i] = block.row0[i];
        }
        if let Some(b) = budget.as_deref_mut() {
            for e in &mut b[base..base + live] {
                e.row = u32::MAX;
            }
        }
        let n = visible.iter().sum::<u32>() as usize;
        let dense = n >= DENSE_BLOCK;
        if !dense || extras {
            // The visible lanes, listed branch-free.
            let mut n = 0;
            for (lane, &v) in visible.iter().enumerate() {
                lanes[n] = lane as u8;
                n += v as usize;
            }
        }
        if dense {
            let mb = &motion[bi];
            let before = (
                mb.dir_eye.each_ref().map(|d| &d[..]),
                &mb.velocity_deg_per_s[..],
            );
            model::<VELOCITY, ECCENTRICITY, NEAREST>(
                c,
                bb,
                before,
                BLOCK,
                pursued,
                object_profiles,
                &mut m,
            );
            write_block::<VELOCITY>(
                bb,
                &m,
                &visible,
                &lanes[..n],
                &mut selections[base..base + live],
                &mut motion[bi],
                diagnostics.as_deref_mut(),
                budget.as_deref_mut(),
            );
            continue;
        }
        // Culled: LOD "culled" and no velocity history when next seen; the
        // visible objects' outputs follow when the queue is modelled.
        selections[base..base + live].fill(Selection::CULLED);
        if VELOCITY {
            let mb = &mut motion[bi];
            for i in 0..BLOCK {
                let v = mb.velocity_deg_per_s[i];
                mb.velocity_deg_per_s[i] = if visible[i] != 0 { v } else { -1.0 };
            }
        }
        // Model the queue first where these would not fit.
        if queued + n > QUEUE {
            let outputs = Outputs {
                selections: &mut *selections,
                diagnostics: diagnostics.as_deref_mut(),
                budget: budget.as_deref_mut(),
            };
            flush_queue::<VELOCITY, ECCENTRICITY, NEAREST>(
                c,
                &queue,
                queued,
                pursued,
                object_profiles,
                &mut m,
                motion,
                outputs,
            );
            queued = 0;
        }
        // Append the visible lanes to the queue.
        let mb = &motion[bi];
        for &lane in &lanes[..n] {
            let (lane, at) = (lane as usize % BLOCK, queued % QUEUE);
            queue.index[at] = bb.index[lane];
            queue.row0[at] = bb.row0[lane];
            for a in 0..3 {
                if NEAREST {
                    queue.to_camera[a][at] = bb.to_camera[a][lane];
                }
                queue.p[a][at] = bb.p[a][lane];
                if VELOCITY {
                    queue.dir_before[a][at] = mb.dir_eye[a][lane];
                }
            }
            queue.d2[at] = bb.d2[lane];
            queue.radius[at] = bb.radius[lane];
            if VELOCITY {
                queue.velocity_before[at] = mb.velocity_deg_per_s[lane];
            }
            queued += 1;
        }
    }
    if queued > 0 {
        let outputs = Outputs {
            selections,
            diagnostics,
            budget,
        };
        flush_queue::<VELOCITY, ECCENTRICITY, NEAREST>(
            c,
            &queue,
            queued,
            pursued,
            object_profiles,
            &mut m,
            motion,
            outputs,
        );
    }
}

/// Models the first `queued` objects of the queue (see [`model`]) and
/// writes their outputs.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn flush_queue<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    queue: &Batch,
    queued: usize,
    pursued: u32,
    object_profiles: &[u32],
    m: &mut Modelled,
    motion: &mut [MotionBlock],
    out: Outputs<'_>,
) {
    let before = (
        queue.dir_before.each_ref().map(|d| &d[..]),
        &queue.velocity_before[..],
    );
    model::<VELOCITY, ECCENTRICITY, NEAREST>(c, queue, before, queued, pursued, object_profiles, m);
    let Outputs {
        selections,
        diagnostics,
        budget,
    } = out;
    write_queue::<VELOCITY>(queue, m, queued, selections, motion, diagnostics, budget);
}

/// How many blocks ahead the loop asks for the next block's data.
const PREFETCH_BLOCKS: usize = 2;

/// Software prefetch: a hint, never a load, so any address is sound. On
/// x86-64 with the feature `simd-dispatch`, `prefetcht1` (into L2) through
/// pulp's safe wrapper; elsewhere nothing.
#[derive(Clone, Copy)]
struct Prefetch {
    #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
    sse: Option<pulp::core_arch::x86::Sse>,
}

impl Prefetch {
    fn new() -> Self {
        Self {
            #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
            sse: pulp::core_arch::x86::Sse::try_new(),
        }
    }

    /// Asks for every 64-byte cache line of `item`.
    #[inline(always)]
    fn lines<T>(self, item: &T) {
        #[cfg(all(feature = "simd-dispatch", target_arch = "x86_64"))]
        if let Some(sse) = self.sse {
            let start = (item as *const T).cast::<i8>();
            for offset in (0..size_of::<T>()).step_by(64) {
                sse._mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T1 }>(start.wrapping_add(offset));
            }
        }
        #[cfg(not(all(feature = "simd-dispatch", target_arch = "x86_64")))]
        let _ = item;
    }
}

/// Models lanes `0..n` of a batch into `m`, up to each object's LOD: short
/// passes over plain arrays (vectorised), then the viewpoint lookup and
/// the LOD count, in bulk where every profile shares one row layout.
/// `before` is the lanes' motion state (last frame's direction x, y, z and
/// smoothed velocity); `pursued` the pursued object's index within the
/// work item, and `object_profiles` its objects' profiles.
#[inline(always)]
fn model<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    q: &Batch,
    before: ([&[f32]; 3], &[f32]),
    n: usize,
    pursued: u32,
    object_profiles: &[u32],
    m: &mut Modelled,
) {
    let n = n.min(QUEUE);
    // The frame's constants as locals: `m` is written through a reference,
    // and loops that read `c` through one as well do not vectorise.
    let (margin_deg, inv_dt, alpha) = (c.margin_deg, c.inv_dt, c.alpha);
    let (scale, size_on, fill_deg) = (c.scale, c.size_on, c.fill_deg);
    for i in 0..n {
        let (d2, r) = (q.d2[i], q.radius[i]);
        let inv_d = 1.0 / fastmath::max(d2, f32::MIN_POSITIVE).sqrt();
        let sin_half = fastmath::min(r * inv_d, 1.0);
        let theta = 2.0 * fastmath::asin_unchecked(sin_half) * RAD_TO_DEG;
        m.inv_d[i] = inv_d;
        m.theta_deg[i] = if d2 <= r * r { 180.0 } else { theta };
    }
    if ECCENTRICITY {
        for i in 0..n {
            let cos = fastmath::clamp(-q.p[2][i] * m.inv_d[i], -1.0, 1.0);
            let angle_deg = fastmath::acos_unchecked(cos) * RAD_TO_DEG;
            m.eccentricity_deg[i] =
                fastmath::max(angle_deg - 0.5 * m.theta_deg[i] - margin_deg, 0.0);
        }
    }
    if VELOCITY {
        let (dir_before, velocity_before) = (before.0.map(|d| &d[..n]), &before.1[..n]);
        let mut chord = [0.0f32; QUEUE];
        for i in 0..n {
            let inv_d = m.inv_d[i];
            m.dir[0][i] = q.p[0][i] * inv_d;
            m.dir[1][i] = q.p[1][i] * inv_d;
            m.dir[2][i] = q.p[2][i] * inv_d;
        }
        if c.world_velocity {
            let [a, b, d] = c.eye_to_world.to_cols_array_2d();
            for i in 0..n {
                let (x, y, z) = (m.dir[0][i], m.dir[1][i], m.dir[2][i]);
                m.dir[0][i] = a[0] * x + b[0] * y + d[0] * z;
                m.dir[1][i] = a[1] * x + b[1] * y + d[1] * z;
                m.dir[2][i] = a[2] * x + b[2] * y + d[2] * z;
            }
        }
        for i in 0..n {
            let (x, y, z) = (m.dir[0][i], m.dir[1][i], m.dir[2][i]);
            let (ex, ey, ez) = (
                x - dir_before[0][i],
                y - dir_before[1][i],
                z - dir_before[2][i],
            );
            chord[i] = (ex * ex + ey * ey + ez * ez).sqrt();
        }
        if c.dt_valid {
            for i in 0..n {
                let before = velocity_before[i];
                let step_deg =
                    2.0 * fastmath::asin_unchecked(fastmath::min(0.5 * chord[i], 1.0)) * RAD_TO_DEG;
                let now = fastmath::min(step_deg * inv_dt, MAX_VELOCITY_DEG_PER_S);
                let smoothed = before + alpha * (now - before);
                m.velocity[i] = if before < 0.0 { 0.0 } else { smoothed };
            }
        } else {
            for i in 0..n {
                let before = velocity_before[i];
                m.velocity[i] = if before < 0.0 { 0.0 } else { before };
            }
        }
        for i in 0..n {
            m.seen_velocity[i] = if q.index[i] == pursued {
                0.0
            } else {
                m.velocity[i]
            };
        }
    }
    // G(v) in a pass of its own (its polynomial's constants then stay in
    // registers), into `threshold_cpd` until the threshold replaces it.
    if VELOCITY {
        let floor_cpd = c.motion_floor_cpd;
        match c.velocity_model {
            VelocityModel::Kelly1979 => {
                for i in 0..n {
                    let v = fastmath::max(m.seen_velocity[i], DRIFT_VELOCITY_DEG_PER_S);
                    let g = kelly_velocity_acuity_unchecked(v);
                    m.threshold_cpd[i] = fastmath::max(g, floor_cpd);
                }
            }
            VelocityModel::Reddy2001 => {
                for i in 0..n {
                    let v = fastmath::clamp(
                        m.seen_velocity[i],
                        VELOCITY_FLOOR_DEG_PER_S,
                        VELOCITY_CEILING_DEG_PER_S,
                    );
                    let g = fastmath::clamp(
                        reddy_velocity_piece_cpd(fastmath::log10(v)),
                        MIN_ACUITY_CPD,
                        MAX_ACUITY_CPD,
                    );
                    m.threshold_cpd[i] = fastmath::max(g, floor_cpd);
                }
            }
        }
    }
    // M(E) in a pass per model, so each vectorises on its own.
    let mut m_factor = [1.0f32; QUEUE];
    if ECCENTRICITY {
        match c.eccentricity_model {
            EccentricityModel::CorticalMagnification => {
                for i in 0..n {
                    let e = fastmath::clamp(m.eccentricity_deg[i], 0.0, MAX_ECCENTRICITY_DEG);
                    m_factor[i] = cortical_factor_unchecked(e);
                }
            }
            EccentricityModel::Reddy2001 => {
                for i in 0..n {
                    let e = fastmath::clamp(
                        m.eccentricity_deg[i],
                        ECCENTRICITY_FLOOR_DEG,
                        ECCENTRICITY_CEILING_DEG,
                    );
                    m_factor[i] = reddy_eccentricity_factor_unchecked(e);
                }
            }
        }
    }
    for i in 0..n {
        let g = if VELOCITY {
            m.threshold_cpd[i]
        } else {
            MAX_ACUITY_CPD
        };
        let threshold_cpd = scale * (g * m_factor[i]);
        // Inside the sphere: k = inf keeps every frequency visible (LOD 0).
        // The size it is judged at multiplies in once the rung is known.
        let (d2, r) = (q.d2[i], q.radius[i]);
        m.threshold_cpd[i] = threshold_cpd;
        m.k_cdiam[i] = if d2 <= r * r {
            f32::INFINITY
        } else {
            threshold_cpd
        };
    }
    // Each lane's rung of the size ladder and the size it is judged at.
    let mut rung = [0u32; QUEUE];
    let mut judged_deg = [0.0f32; QUEUE];
    match c.layout {
        RowLayout::Uniform {
            stride,
            lookup,
            ladder,
        } => {
            if NEAREST && lookup != NO_LOOKUP {
                let dirs = [0, 1, 2].map(|a| &q.to_camera[a][..n]);
                let lookup = &c.lookups[lookup as usize];
                lookup.nearest_batch(dirs, &mut m.view[..n], c.scan_max_views);
            } else {
                m.view[..n].fill(0);
            }
            let boundaries = &c.ladders[ladder as usize].boundaries_deg;
            let rungs = boundaries.len() as u32 + 1;
            rung_of(
                boundaries,
                &m.theta_deg[..n],
                size_on,
                fill_deg,
                &mut rung[..n],
                &mut judged_deg[..n],
            );
            for i in 0..n {
                m.row[i] = q.row0[i] + (m.view[i] * rungs + rung[i]) * stride;
                m.k_cdiam[i] *= judged_deg[i];
            }
            if stride == 4 {
                count_rows::<4>(c.rows, &m.row[..n], &m.k_cdiam[..n], &mut m.lod[..n]);
            } else {
                for i in 0..n {
                    let row = &c.rows[m.row[i] as usize..][..stride as usize];
                    m.lod[i] = count_coarser_padded(row, m.k_cdiam[i]) as u32;
                }
            }
        }
        RowLayout::Empty | RowLayout::Mixed => {
            // Each object's profile first, then its cube-map cell (in bulk:
            // it vectorises), its row, then the counts: short, independent
            // iterations overlap better than one long chain of loads.
            let mut strides = [0u32; QUEUE];
            let mut rungs = [0u32; QUEUE];
            let mut lookups = [NO_LOOKUP; QUEUE];
            let mut resolutions = [viewpoints::MIN_RESOLUTION; QUEUE];
            for i in 0..n {
                // Lanes past the last object (modelled, never written) take profile 0.
                let p = object_profiles
                    .get(q.index[i] as usize)
                    .copied()
                    .unwrap_or(0);
                let profile = c.profiles[p as usize];
                let boundaries = &c.ladders[profile.ladder as usize].boundaries_deg;
                let size_deg = if size_on { m.theta_deg[i] } else { fill_deg };
                (rung[i], judged_deg[i]) = rung_and_judged_size(boundaries, size_deg);
                m.k_cdiam[i] *= judged_deg[i];
                rungs[i] = boundaries.len() as u32 + 1;
                m.row[i] = profile.start + rung[i] * profile.stride;
                strides[i] = profile.stride;
                if NEAREST && profile.lookup != NO_LOOKUP {
                    lookups[i] = profile.lookup;
                    resolutions[i] = c.lookups[profile.lookup as usize].resolution();
                }
            }
            if NEAREST {
                let mut cells = [0u32; QUEUE];
                for i in 0..n {
                    let d = Vec3::new(q.to_camera[0][i], q.to_camera[1][i], q.to_camera[2][i]);
                    cells[i] = viewpoints::cell_index(d, resolutions[i]);
                }
                for i in 0..n {
                    if let Some(lookup) = c.lookups.get(lookups[i] as usize) {
                        let d = [0, 1, 2].map(|a| q.to_camera[a][i]);
                        let view = lookup.nearest_in_cell(cells[i], d) as u32;
                        m.row[i] += (1 + view) * rungs[i] * strides[i];
                    }
                }
            }
            for i in 0..n {
                let row = &c.rows[m.row[i] as usize..][..strides[i] as usize];
                m.lod[i] = count_coarser_padded(row, m.k_cdiam[i]) as u32;
            }
        }
    }
}

/// Writes a block's outputs after modelling it whole: every lane's
/// selection and motion state, blended with culled (`visible[i] == 0`),
/// branch-free; diagnostics and budget entries of the `lanes` listed.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn write_block<const VELOCITY: bool>(
    q: &Batch,
    m: &Modelled,
    visible: &[u32; BLOCK],
    lanes: &[u8],
    selections: &mut [Selection],
    mb: &mut MotionBlock,
    diagnostics: Option<&mut [Diagnostics]>,
    budget: Option<&mut [BudgetEntry]>,
) {
    // Blends by bit masks: the compiler turns `if` here into branches,
    // which mispredict on every culled lane.
    let mask = |i: usize| 0u32.wrapping_sub(visible[i]);
    let blend = |mask: u32, new: f32, old: f32| {
        f32::from_bits((new.to_bits() & mask) | (old.to_bits() & !mask))
    };
    // Culled is `u8::MAX`: every bit set.
    let lods: [Selection; BLOCK] = std::array::from_fn(|i| Selection((m.lod[i] | !mask(i)) as u8));
    let live = selections.len().min(BLOCK);
    selections[..live].copy_from_slice(&lods[..live]);
    if VELOCITY {
        for i in 0..BLOCK {
            let mask = mask(i);
            for a in 0..3 {
                mb.dir_eye[a][i] = blend(mask, m.dir[a][i], mb.dir_eye[a][i]);
            }
            mb.velocity_deg_per_s[i] = blend(mask, m.velocity[i], -1.0);
        }
    }
    if diagnostics.is_some() || budget.is_some() {
        write_extras(q, m, lanes.iter().map(|&l| l as usize), diagnostics, budget);
    }
}

/// Writes the outputs of lanes `0..n` of the queue, object by object.
#[inline(always)]
fn write_queue<const VELOCITY: bool>(
    q: &Batch,
    m: &Modelled,
    n: usize,
    selections: &mut [Selection],
    motion: &mut [MotionBlock],
    diagnostics: Option<&mut [Diagnostics]>,
    budget: Option<&mut [BudgetEntry]>,
) {
    let n = n.min(QUEUE);
    for i in 0..n {
        let index = q.index[i] as usize;
        selections[index] = Selection(m.lod[i] as u8);
        if VELOCITY {
            let mb = &mut motion[index / BLOCK];
            let lane = index % BLOCK;
            for a in 0..3 {
                mb.dir_eye[a][lane] = m.dir[a][i];
            }
            mb.velocity_deg_per_s[lane] = m.velocity[i];
        }
    }
    if diagnostics.is_some() || budget.is_some() {
        write_extras(q, m, 0..n, diagnostics, budget);
    }
}

/// Diagnostics and budget entries of the given lanes.
fn write_extras(
    q: &Batch,
    m: &Modelled,
    lanes: impl Iterator<Item = usize>,
    mut diagnostics: Option<&mut [Diagnostics]>,
    mut budget: Option<&mut [BudgetEntry]>,
) {
    for i in lanes {
        let i = i % QUEUE;
        let index = q.index[i] as usize;
        if let Some(d) = diagnostics.as_deref_mut() {
            d[index] = Diagnostics {
                angular_size_deg: m.theta_deg[i],
                eccentricity_deg: m.eccentricity_deg[i],
                velocity_deg_per_s: m.seen_velocity[i],
                threshold_cpd: m.threshold_cpd[i],
            };
        }
        if let Some(b) = budget.as_deref_mut() {
            b[index] = BudgetEntry {
                k_cdiam: m.k_cdiam[i],
                angular_size_deg: m.theta_deg[i],
                row: m.row[i],
            };
        }
    }
}

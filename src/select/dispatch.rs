//! Running the loop: the kernel compiled for the widest vector
//! instructions the CPU has (feature `simd-dispatch`), and split into work
//! items of whole blocks on rayon over large object sets (feature
//! `parallel`).

#[cfg(feature = "simd-dispatch")]
use crate::viewpoints;

#[cfg(feature = "parallel")]
use super::BLOCK;
#[cfg(feature = "simd-dispatch")]
use super::SimdLevel;
use super::frame::FrameConsts;
use super::kernel::{Outputs, kernel};
use super::store::{Block, MotionBlock};

/// Objects per parallel work item; a whole number of blocks.
#[cfg_attr(not(feature = "parallel"), allow(dead_code))]
pub(super) const CHUNK: usize = 4096;

type Kernel = fn(&FrameConsts<'_>, &[Block], &mut [MotionBlock], u32, Outputs<'_>);

/// [`kernel`] compiled for the widest vector instructions the CPU has
/// (pulp detects them once and runs the closure, with `kernel` inlined
/// into it, in a function compiled for them), or for the build's baseline.
pub(super) fn widest<const VELOCITY: bool, const ECCENTRICITY: bool, const NEAREST: bool>(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    first_index: u32,
    out: Outputs<'_>,
) {
    #[cfg(feature = "simd-dispatch")]
    if c.simd != SimdLevel::Baseline {
        let arch = match (c.simd, pulp::Arch::new()) {
            #[cfg(target_arch = "x86_64")]
            (SimdLevel::Avx2, pulp::Arch::V4(_)) => {
                pulp::x86::V3::try_new().map_or(pulp::Arch::Scalar, pulp::Arch::V3)
            }
            (_, arch) => arch,
        };
        let scan_max_views = match arch {
            #[cfg(target_arch = "x86_64")]
            pulp::Arch::V4(_) => viewpoints::SCAN_MAX_VIEWS_512,
            #[cfg(target_arch = "x86_64")]
            pulp::Arch::V3(_) => viewpoints::SCAN_MAX_VIEWS_256,
            _ => c.scan_max_views,
        };
        let c = &FrameConsts {
            scan_max_views,
            ..*c
        };
        return arch.dispatch(
            #[inline(always)]
            || kernel::<VELOCITY, ECCENTRICITY, NEAREST>(c, blocks, motion, first_index, out),
        );
    }
    kernel::<VELOCITY, ECCENTRICITY, NEAREST>(c, blocks, motion, first_index, out)
}

pub(super) fn dispatch(
    c: &FrameConsts<'_>,
    blocks: &[Block],
    motion: &mut [MotionBlock],
    out: Outputs<'_>,
    kernel: Kernel,
    parallel_min: usize,
) {
    #[cfg(feature = "parallel")]
    if out.selections.len() >= parallel_min.max(2 * CHUNK) {
        use rayon::prelude::*;
        let Outputs {
            selections,
            diagnostics,
            budget,
        } = out;
        let diag_iter = diagnostics.map(|d| d.par_chunks_mut(CHUNK));
        let budget_iter = budget.map(|b| b.par_chunks_mut(CHUNK));
        let base = blocks
            .par_chunks(CHUNK / BLOCK)
            .zip(motion.par_chunks_mut(CHUNK / BLOCK))
            .zip(selections.par_chunks_mut(CHUNK))
            .enumerate();
        match (diag_iter, budget_iter) {
            (Some(d), Some(b)) => base.zip(d).zip(b).for_each(|(((i, ((o, m), s)), d), b)| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: Some(d),
                        budget: Some(b),
                    },
                )
            }),
            (Some(d), None) => base.zip(d).for_each(|((i, ((o, m), s)), d)| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: Some(d),
                        budget: None,
                    },
                )
            }),
            (None, Some(b)) => base.zip(b).for_each(|((i, ((o, m), s)), b)| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: None,
                        budget: Some(b),
                    },
                )
            }),
            (None, None) => base.for_each(|(i, ((o, m), s))| {
                kernel(
                    c,
                    o,
                    m,
                    (i * CHUNK) as u32,
                    Outputs {
                        selections: s,
                        diagnostics: None,
                        budget: None,
                    },
                )
            }),
        }
        return;
    }
    let _ = parallel_min;
    kernel(c, blocks, motion, 0, out);
}

//! LOD chains: loading, generation by simplification, validation, and a
//! procedural test object.
//!
//! An LOD chain is a `Vec<Mesh>`, finest first, with strictly decreasing
//! triangle counts and 1 to [`MAX_LODS`] levels. This module holds every
//! rule of a chain ([`check_lod_count`], [`check_targets`],
//! [`check_chain`]); scene files, the command line and the offline pass
//! call these instead of restating them. A chain of one LOD is valid: it
//! has nothing to switch, so the offline pass measures nothing for it.
//!
//! # Generation
//! [`generate_lods`] makes one LOD per triangle target, each simplified
//! from the *source* mesh (not from the previous LOD, which would compound
//! errors) with meshoptimizer's edge-collapse simplifier at an unbounded
//! error: attribute-unaware for untextured meshes, attribute-aware (texture
//! coordinates, colours, normals) for textured ones, so texture seams, which
//! are vertices split at one position, are kept where the cost allows. A target at or above the source's triangle count
//! keeps the source as is, so the paper's 3928/834/254/76 on a
//! 3928-triangle mesh gives the mesh itself as LOD 0. When the topology-
//! preserving simplifier stops more than 10% above a target (closed
//! manifolds with few triangles can), the sloppy (vertex-clustering)
//! simplifier is used instead. Computed normals are recomputed on the result.

use std::path::{Path, PathBuf};

use crate::{Error, Mesh};

/// Loads an LOD chain from mesh files (OBJ or glTF), finest first, and
/// checks it. One glTF file stands for the chain it carries
/// ([`crate::render::gltf_mesh`]: `MSFT_lod` or `_LOD<n>` names); with
/// several files each is one LOD (a glTF's finest level, with a warning
/// when it carries more). Returns the chain and the loaders' warnings.
pub fn load_lod_files(object: &str, paths: &[PathBuf]) -> Result<(Vec<Mesh>, Vec<String>), Error> {
    if let [path] = paths {
        let loaded = crate::render::load_mesh_file(path)?;
        if loaded.lods.len() == 1 && crate::render::is_gltf(path) {
            return Err(Error::LodChain {
                object: object.into(),
                lod: 1,
                message: format!(
                    "{} carries one LOD (no MSFT_lod, no node named `*_LOD1`); give more files or generate LODs from it",
                    path.display()
                ),
            });
        }
        check_chain(object, &loaded.lods)?;
        return Ok((loaded.lods, loaded.warnings));
    }
    let mut lods = Vec::with_capacity(paths.len());
    let mut warnings = Vec::new();
    for p in paths {
        let (mesh, w) = load_finest(p)?;
        warnings.extend(w);
        lods.push(mesh);
    }
    check_chain(object, &lods)?;
    Ok((lods, warnings))
}

/// The finest mesh of a file (OBJ or glTF) and the loader's warnings, with
/// one more when the file carries a chain of which only LOD 0 is used.
pub fn load_finest(path: &Path) -> Result<(Mesh, Vec<String>), Error> {
    let mut loaded = crate::render::load_mesh_file(path)?;
    let n = loaded.lods.len();
    if n > 1 {
        loaded.warnings.push(format!(
            "{}: carries {n} LODs; only its LOD 0 is used here",
            path.display()
        ));
    }
    let mesh = loaded.lods.swap_remove(0);
    Ok((mesh, loaded.warnings))
}

/// Most LODs in a chain: what a profile holds ([`acuity::profile::MAX_LODS`]).
pub const MAX_LODS: usize = acuity::profile::MAX_LODS;

/// Checks that a chain of `count` LODs has 1 to [`MAX_LODS`] of them.
pub fn check_lod_count(count: usize) -> Result<(), String> {
    if (1..=MAX_LODS).contains(&count) {
        Ok(())
    } else {
        Err(format!("{count} LODs; a chain has 1 to {MAX_LODS}"))
    }
}

/// What is wrong with a list of triangle targets ([`check_targets`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TargetsError {
    /// The bad entry, or `None` when the list as a whole is wrong.
    pub index: Option<usize>,
    /// Why.
    pub message: String,
}

impl std::fmt::Display for TargetsError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.index {
            Some(i) => write!(f, "entry {i}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

/// Checks the triangle targets of a chain, finest first: 1 to [`MAX_LODS`]
/// of them, each positive, strictly decreasing.
pub fn check_targets(triangle_targets: &[u32]) -> Result<(), TargetsError> {
    check_lod_count(triangle_targets.len()).map_err(|message| TargetsError {
        index: None,
        message,
    })?;
    for (k, &n) in triangle_targets.iter().enumerate() {
        let message = if n == 0 {
            "0 triangles".to_string()
        } else if k > 0 && n >= triangle_targets[k - 1] {
            format!(
                "{n} must be below the previous LOD's {} (finest first)",
                triangle_targets[k - 1]
            )
        } else {
            continue;
        };
        return Err(TargetsError {
            index: Some(k),
            message,
        });
    }
    Ok(())
}

/// [`check_targets`] as the offline pass's error.
pub(crate) fn check_targets_setting(triangle_targets: &[u32]) -> Result<(), Error> {
    check_targets(triangle_targets).map_err(|e| Error::Settings {
        field: "triangle_targets",
        message: e.to_string(),
    })
}

/// Checks that `lods` has 1 to [`MAX_LODS`] levels, each a valid mesh, with
/// strictly decreasing triangle counts. The error names the first bad LOD.
pub fn check_chain(object: &str, lods: &[Mesh]) -> Result<(), Error> {
    let err = |lod: usize, message: String| Error::LodChain {
        object: object.to_string(),
        lod,
        message,
    };
    check_lod_count(lods.len()).map_err(|m| err(lods.len().min(MAX_LODS), m))?;
    for (i, m) in lods.iter().enumerate() {
        m.check().map_err(|e| err(i, e))?;
        if i > 0 && m.triangle_count() >= lods[i - 1].triangle_count() {
            return Err(err(
                i,
                format!(
                    "has {} triangles, not fewer than LOD {}'s {}; LODs must get strictly coarser",
                    m.triangle_count(),
                    i - 1,
                    lods[i - 1].triangle_count()
                ),
            ));
        }
    }
    Ok(())
}

/// Generates a chain from `source` at `triangle_targets` (finest first, see
/// the module docs) and checks it.
pub fn generate_lods(
    object: &str,
    source: &Mesh,
    triangle_targets: &[u32],
) -> Result<Vec<Mesh>, Error> {
    check_targets_setting(triangle_targets)?;
    let lods: Vec<Mesh> = triangle_targets
        .iter()
        .map(|&t| simplify(source, t as usize))
        .collect();
    check_chain(object, &lods)?;
    Ok(lods)
}

/// Weights of a textured mesh's vertex attributes in meshoptimizer's
/// collapse cost (`u v`, `r g b`, normal `x y z`): texture coordinates
/// count fully (a texel shift is what a texture LOD loses), colours and
/// normals half, as meshoptimizer's documentation suggests for normals.
const ATTRIBUTE_WEIGHTS: [f32; 8] = [1.0, 1.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5];

/// Simplifies `mesh` to at most about `target_triangles` (see the module
/// docs); returns a clone when the mesh is already small enough. Unused
/// vertices are dropped (kept vertices stay in their original order).
pub fn simplify(mesh: &Mesh, target_triangles: usize) -> Mesh {
    if target_triangles >= mesh.triangle_count() {
        return mesh.clone();
    }
    let bytes: Vec<u8> = mesh
        .positions
        .iter()
        .flatten()
        .flat_map(|f| f.to_le_bytes())
        .collect();
    let Ok(adapter) = meshopt::VertexDataAdapter::new(&bytes, 12, 0) else {
        return mesh.clone();
    };
    let target_indices = target_triangles * 3;
    let mut idx = if mesh.texture.is_none() {
        meshopt::simplify(
            &mesh.indices,
            &adapter,
            target_indices,
            f32::MAX,
            meshopt::SimplifyOptions::None,
            None,
        )
    } else {
        // Textured: texture coordinates, colours and normals weigh in the
        // collapse cost, so seams and what the texture shows stay put.
        let attrs: Vec<f32> = (0..mesh.positions.len())
            .flat_map(|i| {
                let [u, v] = mesh.uvs[i];
                let [r, g, b] = mesh.colors[i];
                let [x, y, z] = mesh.normals[i];
                [u, v, r, g, b, x, y, z]
            })
            .collect();
        let locks = vec![false; mesh.positions.len()];
        meshopt::simplify_with_attributes_and_locks(
            &mesh.indices,
            &adapter,
            &attrs,
            &ATTRIBUTE_WEIGHTS,
            ATTRIBUTE_WEIGHTS.len() * 4,
            &locks,
            target_indices,
            f32::MAX,
            meshopt::SimplifyOptions::None,
            None,
        )
    };
    if idx.len() > target_indices + target_indices / 10 {
        let sloppy =
            meshopt::simplify_sloppy(&mesh.indices, &adapter, target_indices, f32::MAX, None);
        if !sloppy.is_empty() && sloppy.len() < idx.len() {
            idx = sloppy;
        }
    }
    // Compact: keep used vertices in original order.
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut used: Vec<usize> = idx.iter().map(|&i| i as usize).collect();
    used.sort_unstable();
    used.dedup();
    let mut out = Mesh {
        positions: Vec::with_capacity(used.len()),
        normals: Vec::with_capacity(used.len()),
        colors: Vec::with_capacity(used.len()),
        uvs: Vec::with_capacity(if mesh.uvs.is_empty() { 0 } else { used.len() }),
        texture: mesh.texture.clone(),
        indices: Vec::with_capacity(idx.len()),
        normals_computed: mesh.normals_computed,
    };
    for (new, &old) in used.iter().enumerate() {
        remap[old] = new as u32;
        out.positions.push(mesh.positions[old]);
        out.normals.push(mesh.normals[old]);
        out.colors.push(mesh.colors[old]);
        if let Some(uv) = mesh.uvs.get(old) {
            out.uvs.push(*uv);
        }
    }
    out.indices = idx.iter().map(|&i| remap[i as usize]).collect();
    if mesh.normals_computed {
        out.compute_smooth_normals();
    }
    out
}

/// Parameters of the procedural test object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ProceduralParams {
    /// Wanted triangle count of the generated mesh; the result has the
    /// smallest grid with at least this many (and at least 18) triangles.
    pub triangles: u32,
    /// Varies bump phases and colours; the same seed gives the same mesh.
    pub seed: u32,
}

/// A bumpy, colour-banded torus (major radius 1, minor radius 0.4, model
/// units; centred at the origin, axis +Y) with bumps at three scales (large
/// lobes, medium bumps, fine ripples) and colour varying at two scales, so
/// that successive simplifications remove features of growing size.
/// Deterministic (pure f32/f64 arithmetic, no randomness beyond `seed`).
pub fn procedural_object(params: ProceduralParams) -> Mesh {
    let want = params.triangles.max(18) as f64;
    // Triangles = 2 · nu · nv with nu ≈ 2.5 nv (the torus' circumferences).
    let nv = ((want / 5.0).sqrt().ceil() as u32).max(3);
    let nu = ((want / (2.0 * nv as f64)).ceil() as u32).max(3);
    let s = params.seed as f64;
    let ph = |k: f64| (s * 0.618_033_988_7 * k).fract() * std::f64::consts::TAU;
    let (major, minor) = (1.0f64, 0.4f64);
    let mut positions = Vec::with_capacity((nu * nv) as usize);
    let mut colors = Vec::with_capacity((nu * nv) as usize);
    for i in 0..nu {
        let u = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let v = std::f64::consts::TAU * j as f64 / nv as f64;
            let bump = 0.22 * (3.0 * u + ph(1.0)).sin() * (2.0 * v + ph(2.0)).cos()
                + 0.06 * (8.0 * u + ph(3.0)).sin() * (3.0 * v + ph(4.0)).sin()
                + 0.025 * (24.0 * u + ph(5.0)).cos() * (9.0 * v + ph(6.0)).sin();
            let r = minor * (1.0 + bump);
            let ring = major + r * v.cos();
            positions.push([
                (ring * u.cos()) as f32,
                (r * v.sin()) as f32,
                (ring * u.sin()) as f32,
            ]);
            let band = 0.5 + 0.5 * (2.0 * u + ph(7.0)).sin();
            let spot = 0.5 + 0.5 * (v + ph(8.0)).cos();
            colors.push([
                (0.15 + 0.7 * band) as f32,
                (0.2 + 0.5 * spot) as f32,
                (0.75 - 0.55 * band) as f32,
            ]);
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    let mut indices = Vec::with_capacity((6 * nu * nv) as usize);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            indices.extend_from_slice(&[a, c, b, a, d, c]);
        }
    }
    let mut m = Mesh {
        normals: vec![[0.0, 0.0, 1.0]; positions.len()],
        positions,
        colors,
        uvs: Vec::new(),
        texture: None,
        indices,
        normals_computed: true,
    };
    m.compute_smooth_normals();
    m
}

/// The paper's test object LOD triangle counts (Reddy 1998 §5).
pub const PAPER_TRIANGLE_TARGETS: [u32; 4] = [3928, 834, 254, 76];

/// Each coarser LOD of a mesh kept whole has this share of the previous
/// one's triangles (a quarter: about the steps of the paper's chain,
/// 3928/834/254/76, whose ratios are 3.3 to 4.7).
pub const WHOLE_MESH_STEP: u64 = 4;

/// No LOD of a mesh kept whole goes below this many triangles.
pub const WHOLE_MESH_FLOOR_TRIANGLES: u64 = 32;

/// LODs in a mesh kept whole, at most (the paper's chain has four).
pub const WHOLE_MESH_MAX_LODS: usize = 4;

/// The triangle targets of a mesh of `triangles` kept whole: the mesh's
/// own count, then a quarter of the previous target
/// ([`WHOLE_MESH_STEP`]) while it stays at or above
/// [`WHOLE_MESH_FLOOR_TRIANGLES`], at most [`WHOLE_MESH_MAX_LODS`]
/// levels. A mesh of fewer than four times the floor is one LOD; counts
/// above `u32::MAX` are clamped.
pub fn whole_mesh_targets(triangles: u64) -> Vec<u32> {
    let first = triangles.clamp(1, u64::from(u32::MAX));
    std::iter::successors(Some(first), |&t| Some(t / WHOLE_MESH_STEP))
        .enumerate()
        .take_while(|&(k, t)| k == 0 || t >= WHOLE_MESH_FLOOR_TRIANGLES)
        .take(WHOLE_MESH_MAX_LODS)
        .map(|(_, t)| t as u32)
        .collect()
}

/// A short description of the procedural parameters, used in input hashes
/// and as the pseudo-path in messages.
pub fn procedural_description(params: ProceduralParams) -> PathBuf {
    Path::new(&format!(
        "procedural:bumpy-torus:triangles={}:seed={}",
        params.triangles, params.seed
    ))
    .to_owned()
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_whole_mesh_is_lod_0_then_quarters_down_to_the_floor() {
        use super::whole_mesh_targets as t;
        assert_eq!(t(5120), [5120, 1280, 320, 80]);
        assert_eq!(t(100_000), [100_000, 25_000, 6250, 1562]);
        assert_eq!(t(3928), [3928, 982, 245, 61]);
        assert_eq!(t(128), [128, 32]);
        assert_eq!(t(127), [127]);
        assert_eq!(t(1), [1]);
        assert_eq!(t(0), [1]);
        assert_eq!(t(u64::MAX)[0], u32::MAX);
        for n in [1u64, 31, 32, 200, 4097, 1 << 40] {
            let targets = t(n);
            assert!(super::check_targets(&targets).is_ok(), "{n}: {targets:?}");
        }
    }

    use super::*;

    #[test]
    fn procedural_object_is_deterministic_and_valid() {
        let p = ProceduralParams {
            triangles: 3928,
            seed: 7,
        };
        let a = procedural_object(p);
        assert_eq!(a, procedural_object(p));
        a.check().unwrap();
        assert!(
            a.triangle_count() >= 3928 && a.triangle_count() < 4300,
            "{}",
            a.triangle_count()
        );
    }

    #[test]
    fn the_paper_chain_is_generated_close_to_its_targets() {
        let src = procedural_object(ProceduralParams {
            triangles: 3928,
            seed: 1,
        });
        let lods = generate_lods("t", &src, &PAPER_TRIANGLE_TARGETS).unwrap();
        let counts: Vec<usize> = lods.iter().map(Mesh::triangle_count).collect();
        for (c, t) in counts.iter().zip(PAPER_TRIANGLE_TARGETS) {
            assert!(
                *c as f64 <= t as f64 * 1.1 && *c as f64 >= t as f64 * 0.7,
                "{counts:?}"
            );
        }
    }

    #[test]
    fn a_chain_that_does_not_get_coarser_names_the_lod() {
        let a = procedural_object(ProceduralParams {
            triangles: 200,
            seed: 1,
        });
        let e = check_chain("obj", &[a.clone(), simplify(&a, 50), simplify(&a, 50)]).unwrap_err();
        assert!(matches!(e, Error::LodChain { lod: 2, .. }), "{e}");
        assert!(check_chain("obj", std::slice::from_ref(&a)).is_ok());
        assert!(matches!(
            check_chain("obj", &[]),
            Err(Error::LodChain { lod: 0, .. })
        ));
    }

    #[test]
    fn targets_follow_one_rule() {
        assert!(check_targets(&[100]).is_ok());
        assert!(check_targets(&[100, 50, 1]).is_ok());
        assert_eq!(check_targets(&[]).unwrap_err().index, None);
        assert_eq!(check_targets(&[0]).unwrap_err().index, Some(0));
        assert_eq!(check_targets(&[100, 100]).unwrap_err().index, Some(1));
        assert_eq!(check_targets(&[100, 50, 60]).unwrap_err().index, Some(2));
        let too_many: Vec<u32> = (1..=MAX_LODS as u32 + 1).rev().collect();
        assert_eq!(check_targets(&too_many).unwrap_err().index, None);
        assert!(check_targets(&too_many[1..]).is_ok());
    }
}

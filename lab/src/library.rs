//! Asset libraries for `acuity preprocess`: a folder of mesh files or a
//! manifest listing them, deterministic shards of the list for batch
//! systems that already exist (a Kubernetes Job array, GNU parallel, a CI
//! matrix: each runs `--shard K/N`), and the check that merges them.
//!
//! - **Folder**: every `.obj`, `.gltf` and `.glb` below it (hidden folders
//!   such as `.acuity-cache` skipped), in sorted order; an asset is named
//!   by its path relative to the folder without the extension
//!   (`rocks/granite`), so names are unique where file stems are not.
//! - **Manifest** (`.txt`): one mesh path per line, relative to the
//!   manifest's folder; `#` starts a comment; the name is the path as
//!   written without its extension.
//! - **Shard `K/N`** keeps the assets whose name hashes (BLAKE3, first 8
//!   bytes) to `K - 1` modulo `N`: the same asset lands in the same shard
//!   on every machine and whatever else the library holds, and the shards
//!   of one `N` partition it.

use std::path::{Path, PathBuf};

use acuity_preprocess::pipeline::ObjectSource;

use crate::profiles::CacheState;
use crate::scene::is_mesh_path;

/// One object to preprocess.
#[derive(Debug, Clone, PartialEq)]
pub struct Job {
    /// The object's name.
    pub name: String,
    /// Its LOD source.
    pub source: ObjectSource,
}

/// A shard `K/N` of a job list (1-based `k`, `1 <= k <= n`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which shard, 1..=`n`.
    pub k: u32,
    /// How many shards, 1..=[`MAX_SHARDS`].
    pub n: u32,
}

/// The largest shard count accepted.
pub const MAX_SHARDS: u32 = 1 << 20;

impl Shard {
    /// Whether the object named `name` belongs to this shard (see the
    /// module docs).
    pub fn contains(&self, name: &str) -> bool {
        let hex = acuity_preprocess::input_files::hash_hex(name.as_bytes());
        let h = u64::from_str_radix(&hex[..16], 16).unwrap_or(0);
        h % u64::from(self.n) == u64::from(self.k - 1)
    }
}

/// Parses `K/N` (1 <= K <= N <= [`MAX_SHARDS`]); the message says what is
/// wrong.
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("`{s}` is not K/N (e.g. 2/8)"))?;
    let num = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{s}`: `{t}` is not a whole number"))
    };
    let (k, n) = (num(k)?, num(n)?);
    if !(1..=MAX_SHARDS).contains(&n) || !(1..=n).contains(&k) {
        return Err(format!("`{s}`: need 1 <= K <= N <= {MAX_SHARDS}"));
    }
    Ok(Shard { k, n })
}

/// `path` relative to its base without the extension, `/`-separated: an
/// asset's name.
fn asset_name(relative: &Path) -> String {
    relative
        .with_extension("")
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join("/")
}

/// The assets of a folder, `(name, path)` in sorted order (see the module
/// docs). Unreadable folders are an error naming them.
pub fn folder_assets(dir: &Path) -> Result<Vec<(String, PathBuf)>, String> {
    let mut files = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        let entries = std::fs::read_dir(&d)
            .map_err(|e| format!("{}: cannot list folder: {e}", d.display()))?;
        for entry in entries {
            let entry = entry.map_err(|e| format!("{}: {e}", d.display()))?;
            let path = entry.path();
            let hidden = entry.file_name().to_string_lossy().starts_with('.');
            if path.is_dir() {
                if !hidden {
                    stack.push(path);
                }
            } else if is_mesh_path(&path) {
                files.push(path);
            }
        }
    }
    files.sort();
    Ok(files
        .into_iter()
        .map(|p| (asset_name(p.strip_prefix(dir).unwrap_or(&p)), p))
        .collect())
}

/// The assets a manifest lists, `(name, path)` in its order; a line that
/// is not a mesh path is an error naming the line.
pub fn manifest_assets(manifest: &Path) -> Result<Vec<(String, PathBuf)>, String> {
    let text = std::fs::read_to_string(manifest)
        .map_err(|e| format!("{}: cannot read manifest: {e}", manifest.display()))?;
    let dir = manifest.parent().unwrap_or(Path::new(""));
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let entry = line.split('#').next().unwrap_or("").trim();
        if entry.is_empty() {
            continue;
        }
        if !is_mesh_path(Path::new(entry)) {
            return Err(format!(
                "{}:{}: `{entry}` is not a mesh file (.obj, .gltf, .glb)",
                manifest.display(),
                i + 1
            ));
        }
        out.push((asset_name(Path::new(entry)), dir.join(entry)));
    }
    Ok(out)
}

/// The merge check: every job has an up-to-date profile in `out_dir`
/// (its recorded input hashes and settings equal the current ones), and,
/// when `all` jobs are given (not one shard), no profile there belongs to
/// no job. Prints one line per problem and a summary; an error (exit 1)
/// when any job lacks an up-to-date profile. Renders nothing.
pub fn check_profiles(
    jobs: &[Job],
    settings: &acuity_preprocess::AnalysisSettings,
    out_dir: &Path,
    all: bool,
) -> anyhow::Result<()> {
    let mut bad = 0usize;
    let mut expected = std::collections::HashSet::new();
    for j in jobs {
        let path = crate::profiles::cache_path(out_dir, &j.source);
        expected.insert(path.clone());
        match crate::profiles::cache_state(&j.source, settings, out_dir) {
            Ok(CacheState::Fresh(_)) => {}
            Ok(CacheState::Stale) => {
                bad += 1;
                println!(
                    "{}: stale profile {} (inputs or settings changed); `acuity preprocess` without --check analyses it again",
                    j.name,
                    path.display()
                );
            }
            Ok(CacheState::Unusable(why)) => {
                bad += 1;
                println!(
                    "{}: profile {} {why}; `acuity preprocess` without --check replaces it",
                    j.name,
                    path.display()
                );
            }
            Ok(CacheState::Missing) => {
                bad += 1;
                println!("{}: no profile ({} missing)", j.name, path.display());
            }
            Err(e) => {
                bad += 1;
                println!("{}: cannot check: {}", j.name, crate::error::error_line(&e));
            }
        }
    }
    if all && let Ok(entries) = std::fs::read_dir(out_dir) {
        let mut stray: Vec<PathBuf> = entries
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "acp") && !expected.contains(p))
            .collect();
        stray.sort();
        for p in stray {
            println!(
                "warning: {} belongs to no object of this library",
                p.display()
            );
        }
    }
    println!(
        "{} of {} objects have an up-to-date profile",
        jobs.len() - bad,
        jobs.len()
    );
    anyhow::ensure!(
        bad == 0,
        "{bad} of {} objects lack an up-to-date profile",
        jobs.len()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_names_and_parse_strictly() {
        let names: Vec<String> = (0..200).map(|i| format!("asset{i}")).collect();
        let mut seen = vec![0; names.len()];
        for k in 1..=4 {
            let s = parse_shard(&format!("{k}/4")).unwrap();
            for (i, n) in names.iter().enumerate() {
                seen[i] += usize::from(s.contains(n));
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
        for bad in ["0/4", "5/4", "1/0", "x/2", "3", "1/2/3"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
        assert!(parse_shard("1/1").unwrap().contains("anything"));
    }

    #[test]
    fn names_are_relative_paths_without_extensions() {
        assert_eq!(asset_name(Path::new("rocks/granite.glb")), "rocks/granite");
        assert_eq!(asset_name(Path::new("bunny.obj")), "bunny");
    }
}

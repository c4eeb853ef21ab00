//! MTL material libraries as the OBJ loader uses them: each material's
//! diffuse colour `Kd` and base-colour texture `map_Kd` (rules in
//! [`crate::mesh`]'s module docs).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::Error;
use crate::obj_text::{decode_text, parse_numbers, split_lines};
use crate::texture::{Texture, Wrap};

/// How [`parse_obj`](crate::mesh::parse_obj) finds an MTL file named by
/// `mtllib` (and this module a texture named by `map_Kd`): given the name
/// as written, return the resolved path and its bytes, or an I/O error
/// (which becomes a warning). Re-exported as `mesh::MtlResolver`.
pub type MtlResolver<'a> = dyn FnMut(&str) -> std::io::Result<(PathBuf, Vec<u8>)> + 'a;

/// A material as the loader uses it: diffuse colour `Kd` (linear RGB) and
/// base-colour texture `map_Kd`, each if any.
#[derive(Debug, Clone, Default)]
pub(crate) struct MtlEntry {
    pub(crate) kd: Option<[f32; 3]>,
    pub(crate) texture: Option<Arc<Texture>>,
}

/// A material: its name, diffuse colour and texture.
pub(crate) type Material = (String, MtlEntry);

/// Parses an MTL file into materials; `resolve` reads a texture file named
/// by `map_Kd` (relative to the MTL file's folder).
pub(crate) fn parse_mtl(
    bytes: &[u8],
    path: &Path,
    resolve: &mut MtlResolver<'_>,
    warnings: &mut Vec<String>,
) -> Result<Vec<Material>, Error> {
    let text = decode_text(bytes, path)?;
    let perr = |line: usize, message: String| Error::Parse {
        path: path.to_owned(),
        line,
        message,
    };
    let mut out: Vec<Material> = Vec::new();
    for (line_idx, raw) in split_lines(&text).enumerate() {
        let line_no = line_idx + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut toks = content.split_whitespace();
        let Some(kw) = toks.next() else { continue };
        match kw {
            "newmtl" => {
                let name = content
                    .trim_start()
                    .strip_prefix("newmtl")
                    .unwrap_or("")
                    .trim();
                if name.is_empty() {
                    return Err(perr(line_no, "`newmtl` without a name".into()));
                }
                out.push((name.to_string(), MtlEntry::default()));
            }
            "Kd" => {
                let Some(last) = out.last_mut() else {
                    return Err(perr(line_no, "`Kd` before any `newmtl`".into()));
                };
                let rest: Vec<&str> = toks.collect();
                if matches!(rest.first(), Some(&"spectral") | Some(&"xyz")) {
                    warnings.push(format!(
                        "{}:{line_no}: `Kd {}` is not supported; default colour used",
                        path.display(),
                        rest[0]
                    ));
                    continue;
                }
                let nums = parse_numbers(rest.into_iter(), line_no, "Kd", path)?;
                let kd = match nums.len() {
                    1 => [nums[0]; 3],
                    3 => [nums[0], nums[1], nums[2]],
                    n => {
                        return Err(perr(
                            line_no,
                            format!("`Kd` needs 1 or 3 numbers, found {n}"),
                        ));
                    }
                };
                last.1.kd = Some(kd.map(|x| x.clamp(0.0, 1.0)));
            }
            "map_Kd" => {
                let Some(last) = out.last_mut() else {
                    return Err(perr(line_no, "`map_Kd` before any `newmtl`".into()));
                };
                let (name, clamp) = map_kd_file(toks.collect())
                    .ok_or_else(|| perr(line_no, "`map_Kd` without a file name".into()))?;
                match resolve(name) {
                    Ok((tex_path, tex_bytes)) => {
                        let source = tex_path.display().to_string();
                        let mut t = Texture::decode(&tex_bytes, path, &source)?;
                        if clamp {
                            t.wrap = [Wrap::ClampToEdge; 2];
                        }
                        last.1.texture = Some(Arc::new(t));
                    }
                    Err(e) => warnings.push(format!(
                        "{}:{line_no}: texture `{name}` not read ({e}); the material's colour is used alone",
                        path.display()
                    )),
                }
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The file name of a `map_Kd` statement (its last token: options come
/// first, and names with spaces are not supported) and whether `-clamp on`
/// was given.
fn map_kd_file(toks: Vec<&str>) -> Option<(&str, bool)> {
    let clamp = toks.windows(2).any(|w| w == ["-clamp", "on"]);
    let name = *toks.last()?;
    let is_option_argument = toks.len() >= 2 && toks[toks.len() - 2] == "-clamp";
    (!name.starts_with('-') && !is_option_argument).then_some((name, clamp))
}

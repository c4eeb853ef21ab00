//! Writing a mesh as OBJ text the loader in [`crate::mesh`] reads back to
//! the same triangles: `v x y z r g b` (linear vertex colours), `vt u v`
//! (OBJ's `v` up: `1 - v`), `vn`, and `f a/a/a` corners; with a texture, an
//! MTL material `Kd 1 1 1` and `map_Kd`. Numbers are written in Rust's
//! shortest form that parses back to the same `f32`.

use std::fmt::Write as _;

use crate::Mesh;

/// The OBJ text of `mesh`. When `material` is given (`(mtl file, material
/// name)`), the text names it with `mtllib` and `usemtl`.
pub fn obj_text(mesh: &Mesh, material: Option<(&str, &str)>) -> String {
    let mut s = String::with_capacity(mesh.positions.len() * 96 + mesh.indices.len() * 12);
    s.push_str("# written by acuity\n");
    if let Some((mtl, name)) = material {
        let _ = writeln!(s, "mtllib {mtl}\nusemtl {name}");
    }
    for (p, c) in mesh.positions.iter().zip(&mesh.colors) {
        let _ = writeln!(s, "v {} {} {} {} {} {}", p[0], p[1], p[2], c[0], c[1], c[2]);
    }
    for uv in &mesh.uvs {
        let _ = writeln!(s, "vt {} {}", uv[0], 1.0 - uv[1]);
    }
    for n in &mesh.normals {
        let _ = writeln!(s, "vn {} {} {}", n[0], n[1], n[2]);
    }
    let with_uv = !mesh.uvs.is_empty();
    for t in mesh.indices.chunks_exact(3) {
        s.push('f');
        for &i in t {
            let i = i + 1;
            let _ = if with_uv {
                write!(s, " {i}/{i}/{i}")
            } else {
                write!(s, " {i}//{i}")
            };
        }
        s.push('\n');
    }
    s
}

/// The MTL text of one material with a white `Kd` and, when given, the
/// texture file as `map_Kd` (`-clamp on` when `clamp`).
pub fn mtl_text(name: &str, texture_file: Option<&str>, clamp: bool) -> String {
    let mut s = format!("# written by acuity\nnewmtl {name}\nKd 1 1 1\n");
    if let Some(t) = texture_file {
        let opt = if clamp { "-clamp on " } else { "" };
        let _ = writeln!(s, "map_Kd {opt}{t}");
    }
    s
}

//! No import circles between the modules of any workspace crate.
//!
//! Crates: the folders at depth 2 or less under the repository root
//! (`target/`, `fuzz/` and hidden ones skipped) whose `Cargo.toml` has a
//! `[package]`; of each, every `.rs` file under `src/` (`src/bin/`
//! skipped) is one module, named by where it lies: `select/mod.rs` and
//! `select.rs` are `select`, `select/kernel.rs` is `select::kernel`,
//! `lib.rs` and `main.rs` the root. Files included by `#[path]` and
//! test-only files such as `select/tests.rs` count as modules too, named by
//! where they lie. Inline modules are read as part of their file, except
//! `#[cfg(test)] mod name { … }` blocks, which are skipped.
//!
//! References: paths starting `crate::`, `self::` or `super::`, in `use`
//! trees (nested groups included) and anywhere in code. Comments (doc
//! comments and their intra-doc links too), string and char literals are
//! dropped first; `$crate`, `pub(in …)` and bare paths (extern crates, or
//! a module's own children) are not read. A path names the longest module
//! it has as a prefix (`crate::a::b::C` is `a::b`, else `a`).
//!
//! Edges: module A referring to B is an edge A -> B unless B is A or one
//! of its descendants (a parent declares and re-exports its children) or
//! the crate root (lib.rs and main.rs are the crate's table of contents:
//! `crate::Error` names a re-export). Child-to-parent, sibling and
//! cross-tree edges count. Every strongly connected component (Tarjan) of
//! more than one module is a circle: two or more files that cannot be
//! read, tested or moved apart. The test names one cycle through each,
//! with the first reference of each edge; break it by moving the shared
//! item to a leaf module or to the module that owns its concept.

use std::collections::{BTreeMap, VecDeque};
use std::path::{Path, PathBuf};

type ModPath = Vec<String>;
type Tok = (String, usize);

/// A crate's name and its modules' files.
struct Crate {
    name: String,
    modules: BTreeMap<ModPath, PathBuf>,
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// The tokens of `src` with their lines: identifiers, `::` and single
/// marks; whitespace, comments, string and char literals dropped.
fn tokens(src: &str) -> Vec<Tok> {
    let c: Vec<char> = src.chars().collect();
    let (n, at) = (c.len(), |i: usize| c.get(i).copied().unwrap_or('\0'));
    let (mut toks, mut i, mut line) = (Vec::new(), 0, 1);
    while i < n {
        let start = i;
        // A raw string `r#"…"#`, `br"…"` or `cr"…"`, not an identifier's tail.
        let r = i + (matches!(c[i], 'b' | 'c') && at(i + 1) == 'r') as usize;
        let hashes = c[(r + 1).min(n)..]
            .iter()
            .take_while(|&&h| h == '#')
            .count();
        let raw = at(r) == 'r' && (i == 0 || !is_ident(c[i - 1])) && at(r + 1 + hashes) == '"';
        if c[i] == '/' && at(i + 1) == '/' {
            i += c[i..].iter().position(|&ch| ch == '\n').unwrap_or(n - i);
        } else if c[i] == '/' && at(i + 1) == '*' {
            let mut depth = 0;
            while i < n {
                match (c[i], at(i + 1)) {
                    ('/', '*') => (depth, i) = (depth + 1, i + 2),
                    ('*', '/') => (depth, i) = (depth - 1, i + 2),
                    _ => i += 1,
                }
                if depth == 0 {
                    break;
                }
            }
        } else if raw {
            i = r + 2 + hashes;
            while i < n && !(c[i] == '"' && (1..=hashes).all(|k| at(i + k) == '#')) {
                i += 1;
            }
            i += 1 + hashes;
        } else if c[i] == '"' {
            i += 1;
            while i < n && c[i] != '"' {
                i += if c[i] == '\\' { 2 } else { 1 };
            }
            i += 1;
        } else if c[i] == '\'' && (at(i + 1) == '\\' || at(i + 2) == '\'') {
            // A char literal, not a lifetime or a label.
            i += if at(i + 1) == '\\' { 4 } else { 3 };
            while i < n && c[i - 1] != '\'' {
                i += 1;
            }
        } else {
            if is_ident(c[i]) {
                while is_ident(at(i + 1)) {
                    i += 1;
                }
            } else if c[i] == ':' && at(i + 1) == ':' {
                i += 1;
            }
            if !c[i].is_whitespace() {
                toks.push((c[start..=i].iter().collect(), line));
            }
            i += 1;
        }
        line += c[start..i.min(n)].iter().filter(|&&ch| ch == '\n').count();
    }
    toks
}

/// A path or `use` tree from `toks[i]` on, after `path`: its paths go to
/// `out`; returns the index after it.
fn use_tree(toks: &[Tok], mut i: usize, mut path: ModPath, out: &mut Vec<ModPath>) -> usize {
    let t = |i: usize| toks.get(i).map_or("", |x| x.0.as_str());
    loop {
        match t(i) {
            "{" => {
                i += 1;
                while !matches!(t(i), "}" | "") {
                    let item = i;
                    i = use_tree(toks, i, path.clone(), out);
                    i += (t(i) == "," || i == item) as usize;
                }
                return i + 1;
            }
            "*" => i += 1,
            s if s.starts_with(is_ident) && s != "as" => {
                path.push(s.to_owned());
                i += 1;
                if t(i) == "::" {
                    i += 1;
                    continue;
                }
                i += 2 * (t(i) == "as") as usize;
            }
            _ => {}
        }
        out.push(path);
        return i;
    }
}

/// Every `crate::`, `self::` and `super::` path in `src` with its line,
/// outside inline `#[cfg(test)] mod name { … }` blocks.
fn references(src: &str) -> Vec<(ModPath, usize)> {
    let toks = tokens(src);
    let t = |i: usize| toks.get(i).map_or("", |x| x.0.as_str());
    let (mut refs, mut i) = (Vec::new(), 0);
    while i < toks.len() {
        if (i..i + 7)
            .map(t)
            .eq(["#", "[", "cfg", "(", "test", ")", "]"])
        {
            let j = (i..toks.len()).find(|&j| matches!(t(j), "{" | ";"));
            if let Some(j) = j.filter(|&j| t(j) == "{" && t(j - 2) == "mod") {
                let mut depth = 0;
                let end = (j..toks.len()).find(|&k| {
                    depth += (t(k) == "{") as i32 - (t(k) == "}") as i32;
                    depth == 0
                });
                i = end.map_or(toks.len(), |k| k + 1);
                continue;
            }
        }
        let (prev, in_vis) = (t(i.wrapping_sub(1)), t(i.wrapping_sub(2)) == "(");
        let start = matches!(t(i), "crate" | "self" | "super") && t(i + 1) == "::";
        if start && !matches!(prev, "::" | "$") && !(prev == "in" && in_vis) {
            let mut paths = Vec::new();
            use_tree(&toks, i, Vec::new(), &mut paths);
            refs.extend(paths.into_iter().map(|p| (p, toks[i].1)));
        }
        i += 1;
    }
    refs
}

/// The module a path names from module `cur`: its longest existing prefix.
fn resolve(
    cur: &[String],
    path: &[String],
    modules: &BTreeMap<ModPath, PathBuf>,
) -> Option<ModPath> {
    let mut full = cur.to_vec();
    for (k, seg) in path.iter().enumerate() {
        match seg.as_str() {
            "crate" if k == 0 => full.clear(),
            "super" => _ = full.pop()?,
            "self" => {}
            _ => full.push(seg.clone()),
        }
    }
    let prefixes = (0..=full.len()).rev().map(|k| full[..k].to_vec());
    prefixes.into_iter().find(|m| modules.contains_key(m))
}

/// `dir` and the folders under it to depth 2 (hidden ones, `target/` and
/// `fuzz/` skipped).
fn folders(dir: &Path, depth: usize) -> Vec<PathBuf> {
    let mut out = vec![dir.to_owned()];
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let skip = name.starts_with('.') || name == "target" || name == "fuzz";
        if depth < 2 && !skip && e.path().is_dir() {
            out.extend(folders(&e.path(), depth + 1));
        }
    }
    out
}

/// Every crate of the workspace, with its `src/` files mapped to modules.
fn crates(root: &Path) -> Vec<Crate> {
    let mut out = Vec::new();
    for dir in folders(root, 0) {
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap_or_default();
        let Some(package) = manifest.split("[package]").nth(1) else {
            continue;
        };
        let name = package.lines().find_map(|l| l.trim().strip_prefix("name"));
        let name = name.unwrap_or("?").trim_matches([' ', '=', '"']).to_owned();
        let (src, mut modules) = (dir.join("src"), BTreeMap::new());
        let mut stack = vec![src.clone()];
        while let Some(d) = stack.pop() {
            for p in std::fs::read_dir(&d)
                .into_iter()
                .flatten()
                .flatten()
                .map(|e| e.path())
            {
                if p.is_dir() && p != src.join("bin") {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    let rel = p.strip_prefix(&src).unwrap().with_extension("");
                    let mut m: ModPath = rel.iter().map(|s| s.to_string_lossy().into()).collect();
                    let root_file = m.len() == 1 && (m[0] == "lib" || m[0] == "main");
                    if root_file || m.last().is_some_and(|s| s == "mod") {
                        m.pop();
                    }
                    modules.insert(m, p);
                }
            }
        }
        out.push(Crate { name, modules });
    }
    out
}

/// Strongly connected components (Tarjan) of the graph `next`.
fn components(next: &[Vec<usize>]) -> Vec<Vec<usize>> {
    struct T<'a> {
        next: &'a [Vec<usize>],
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        stack: Vec<usize>,
        out: Vec<Vec<usize>>,
    }
    fn visit(t: &mut T<'_>, v: usize) {
        let i = t.stack.len() + t.out.iter().map(Vec::len).sum::<usize>();
        (t.index[v], t.low[v]) = (Some(i), i);
        t.stack.push(v);
        let next = t.next;
        for &w in &next[v] {
            if t.index[w].is_none() {
                visit(t, w);
                t.low[v] = t.low[v].min(t.low[w]);
            } else if t.stack.contains(&w) {
                t.low[v] = t.low[v].min(t.index[w].unwrap());
            }
        }
        if Some(t.low[v]) == t.index[v] {
            let at = t.stack.iter().rposition(|&w| w == v).unwrap();
            let scc = t.stack.split_off(at);
            t.out.push(scc);
        }
    }
    let (n, out) = (next.len(), Vec::new());
    let mut t = T {
        next,
        index: vec![None; n],
        low: vec![0; n],
        stack: vec![],
        out,
    };
    for v in 0..n {
        if t.index[v].is_none() {
            visit(&mut t, v);
        }
    }
    t.out
}

/// The shortest cycle from `start` back to it within `scc`.
fn cycle(start: usize, scc: &[usize], next: &[Vec<usize>]) -> Vec<usize> {
    let (mut from, mut queue) = (vec![None; next.len()], VecDeque::from([start]));
    while let Some(v) = queue.pop_front() {
        for &w in next[v].iter().filter(|w| scc.contains(w)) {
            if from[w].is_none() {
                from[w] = Some(v);
                queue.push_back(w);
            }
        }
    }
    let mut cycle = vec![start, from[start].unwrap()];
    while *cycle.last().unwrap() != start {
        cycle.push(from[*cycle.last().unwrap()].unwrap());
    }
    cycle.reverse();
    cycle
}

#[test]
fn no_import_circles_between_modules() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let crates = crates(root);
    let acuity = crates
        .iter()
        .find(|c| c.name == "acuity")
        .expect("the root crate");
    let kernel = vec!["select".to_owned(), "kernel".to_owned()];
    assert!(
        acuity.modules.contains_key(&kernel),
        "no src/select/kernel.rs found"
    );
    let mut report = String::new();
    for c in &crates {
        let names: Vec<&ModPath> = c.modules.keys().collect();
        let id = |m: &ModPath| names.iter().position(|n| *n == m).unwrap();
        let mut edges = BTreeMap::new();
        for (cur, file) in &c.modules {
            for (path, line) in references(&std::fs::read_to_string(file).unwrap()) {
                let to = resolve(cur, &path, &c.modules);
                if let Some(to) = to.filter(|to| !to.is_empty() && !to.starts_with(cur)) {
                    let name = file.file_name().unwrap().to_string_lossy();
                    let first = format!("{name}:{line} {}", path.join("::"));
                    edges.entry((id(cur), id(&to))).or_insert(first);
                }
            }
        }
        let mut next = vec![Vec::new(); names.len()];
        edges.keys().for_each(|&(a, b)| next[a].push(b));
        for scc in components(&next).into_iter().filter(|s| s.len() > 1) {
            let cycle = cycle(*scc.iter().min().unwrap(), &scc, &next);
            let path: Vec<_> = cycle.iter().map(|&v| names[v].join("::")).collect();
            let rest: Vec<_> = scc
                .iter()
                .filter(|v| !cycle.contains(v))
                .map(|&v| names[v].join("::"))
                .collect();
            let also = if rest.is_empty() {
                String::new()
            } else {
                format!(" (with {})", rest.join(", "))
            };
            report += &format!("{}: {}{also}\n", c.name, path.join(" -> "));
            for (k, w) in cycle.windows(2).enumerate() {
                let file = c.modules[names[w[0]]].strip_prefix(root).unwrap().display();
                let to = &path[k + 1];
                report += &format!("    {file} -> {to}: {}\n", edges[&(w[0], w[1])]);
            }
        }
    }
    assert!(
        report.is_empty(),
        "import circles between modules:\n{report}"
    );
}

#[test]
fn scanner_reads_code_paths_only() {
    let src = "/// [`crate::docs`] /* crate::block */\nuse crate::a::{b::{C, d as D}, self, e::*};\n\
               fn f<'a>(x: &'a str) -> char { _ = r#\"crate::s\"#; super::e::f(); '{' }\n\
               pub(in crate::vis) struct S;\n#[cfg(test)]\nmod tests { use crate::t; }\n";
    let found: Vec<String> = references(src)
        .iter()
        .map(|(p, l)| format!("{l} {}", p.join("::")))
        .collect();
    let want = [
        "2 crate::a::b::C",
        "2 crate::a::b::d",
        "2 crate::a::self",
        "2 crate::a::e",
        "3 super::e::f",
    ];
    assert_eq!(found, want);
}

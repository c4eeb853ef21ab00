//! What the tests share: the demo profile of `examples/minimal.rs`, and
//! building and linking the C examples against this crate's static library.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// `examples/common`'s `demo_profile`: 4 LODs of 4000 to 60 triangles, one
/// viewpoint, one size rung (also embedded as JSON in `minimal.c`).
#[path = "../../../examples/common/mod.rs"]
mod examples_common;
#[allow(unused_imports)]
pub use examples_common::demo_profile;

/// The C compiler: `$CC`, else `cc`. `None` (after printing why) when
/// there is none and `ACUITY_SKIP_C=1` says that is fine; a panic with a
/// clear message when there is none otherwise.
pub fn c_compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    let found = Command::new(&cc)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if found {
        return Some(cc);
    }
    if std::env::var_os("ACUITY_SKIP_C").is_some_and(|v| v == "1") {
        eprintln!("skipped: no C compiler `{cc}` (ACUITY_SKIP_C=1)");
        return None;
    }
    panic!(
        "no C compiler: `{cc} --version` failed. Install one (cc, gcc or clang), \
         set CC to it, or set ACUITY_SKIP_C=1 to skip the C tests"
    );
}

/// This crate's static library from the same build as the running test:
/// cargo builds the lib's every crate type (cdylib, staticlib, rlib) into
/// `target/<profile>/deps` before it builds the tests that link the rlib.
pub fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    let deps = exe.parent().expect("deps folder");
    let name = if cfg!(windows) {
        "acuity_capi.lib"
    } else {
        "libacuity_capi.a"
    };
    [
        deps.join(name),
        deps.parent().expect("profile folder").join(name),
    ]
    .into_iter()
    .find(|p| p.is_file())
    .unwrap_or_else(|| {
        panic!(
            "no {name} in {} or beside it; `cargo build -p acuity-capi` builds it",
            deps.display()
        )
    })
}

/// Compiles `examples/c/<source>` with `-O2` against the header and the
/// static library into `out`, and returns the executable's path.
pub fn build_c(cc: &str, source: &str, out: &Path) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = out.join(source.trim_end_matches(".c"));
    let mut cmd = Command::new(cc);
    cmd.args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2", "-I"])
        .arg(root.join("include"))
        .arg(root.join("../examples/c").join(source))
        .arg(static_lib())
        .arg("-o")
        .arg(&exe);
    if cfg!(target_os = "linux") {
        // What Rust's standard library needs from the system (from
        // `rustc --print native-static-libs`; -lgcc_s comes with cc).
        cmd.args(["-lpthread", "-ldl", "-lm"]);
    }
    let output = cmd.output().expect("running the C compiler");
    assert!(
        output.status.success(),
        "{cmd:?} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    exe
}

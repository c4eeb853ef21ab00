//! The committed header `include/acuity.h` is what cbindgen generates from
//! this crate's source now. `ACUITY_BLESS=1 cargo test -p acuity-capi
//! --test header` writes it.

use std::path::Path;

#[test]
fn header_is_up_to_date() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    // From the crate root and the modules it declares: no `cargo
    // metadata`, so no lock on the workspace, no network, and fast.
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src").join("lib.rs"))
        .generate()
        .expect("cbindgen failed");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let generated = String::from_utf8(generated).expect("UTF-8 header");

    let path = dir.join("include").join("acuity.h");
    if std::env::var_os("ACUITY_BLESS").is_some_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &generated).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    // Line endings as checked out (a Windows checkout may have CRLF).
    if committed.replace("\r\n", "\n") != generated {
        panic!(
            "{} is out of date with capi/src; \
             run `ACUITY_BLESS=1 cargo test -p acuity-capi --test header` to regenerate",
            path.display()
        );
    }
}

//! `acuity preprocess` end to end: the binary on small inputs in a temp
//! folder (128 px, 6 viewpoints, so the suite stays fast on llvmpipe), and
//! once on the real bunny at 256 px, 18 viewpoints.

mod common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::SystemTime;

use common::stderr;

use acuity::{
    Camera, Display, FrameInput, Gaze, ObjectDesc, Profile, Selector, SelectorSettings, Tracker,
};
use glam::{DVec3, Quat};

const FAST: [&str; 4] = ["--resolution", "128", "--viewpoints", "0"];

fn temp_dir(test: &str) -> PathBuf {
    common::scratch("preprocess_cli", test)
}

fn acuity(args: &[&str]) -> Output {
    common::acuity_logged(&[&["preprocess"][..], args].concat())
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// A lumpy UV sphere as OBJ text (`2 * lat * lon` triangles, some
/// degenerate at the poles), lumps varied by `seed`, vertex colours.
fn lumpy_sphere_obj(lat: u32, lon: u32, seed: u32) -> String {
    let s = f64::from(seed);
    let mut text = String::from("# lumpy sphere\n");
    for i in 0..=lat {
        let th = std::f64::consts::PI * f64::from(i) / f64::from(lat);
        for j in 0..lon {
            let ph = std::f64::consts::TAU * f64::from(j) / f64::from(lon);
            let r = 1.0
                + 0.15 * (3.0 * ph + s).sin() * (2.0 * th).sin()
                + 0.05 * (9.0 * ph + 2.0 * s).cos() * (5.0 * th).sin();
            let (x, y, z) = (
                r * th.sin() * ph.cos(),
                r * th.cos(),
                r * th.sin() * ph.sin(),
            );
            let c = 0.5 + 0.4 * (2.0 * ph + s).sin();
            writeln!(text, "v {x:.6} {y:.6} {z:.6} {c:.3} 0.5 {:.3}", 1.0 - c).unwrap();
        }
    }
    let id = |i: u32, j: u32| i * lon + (j % lon) + 1;
    for i in 0..lat {
        for j in 0..lon {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            writeln!(text, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
        }
    }
    text
}

/// A scene of three objects: two generated from OBJ files in `dir`
/// (`ball.obj`, `blob.obj`, ~1000 triangles each) and one procedural.
fn write_scene(dir: &Path, extra_objects: &str) -> PathBuf {
    std::fs::write(dir.join("ball.obj"), lumpy_sphere_obj(16, 32, 1)).unwrap();
    std::fs::write(dir.join("blob.obj"), lumpy_sphere_obj(16, 32, 2)).unwrap();
    let scene = format!(
        r#"
[display]
resolution = [640, 480]
fov_deg = [43.6, 33.4]

[[objects]]
name = "ball"
mesh = "ball.obj"
generate_triangles = [1000, 300, 80]

[[objects]]
name = "blob"
mesh = "blob.obj"
generate_triangles = [1000, 250, 60]

[[objects]]
name = "rock"
procedural = {{ kind = "rock", triangles = [800, 200, 50] }}
{extra_objects}
[camera]
duration_s = 1.0
forward_speed_m_per_s = 1.0
"#
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    path
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

#[test]
fn two_runs_give_identical_profile_bytes() {
    let dir = temp_dir("determinism");
    let scene = write_scene(&dir, "");
    let (a, b) = (dir.join("out-a"), dir.join("out-b"));
    // Different thread counts too: the result must not depend on them.
    let oa = acuity(&[&[s(&scene), "--out", s(&a), "--jobs", "1"][..], &FAST].concat());
    let ob = acuity(&[&[s(&scene), "--out", s(&b), "--jobs", "2"][..], &FAST].concat());
    assert_eq!(oa.status.code(), Some(0));
    assert_eq!(ob.status.code(), Some(0));
    for name in ["ball", "blob", "rock"] {
        let fa = std::fs::read(a.join(format!("{name}.acp"))).unwrap();
        let fb = std::fs::read(b.join(format!("{name}.acp"))).unwrap();
        assert!(fa == fb, "{name}.acp differs between two runs");
        assert!(stdout(&oa).contains(&format!("{name}: analysed")));
    }
}

#[test]
fn second_run_is_cached_and_renders_nothing() {
    let dir = temp_dir("cache");
    let scene = write_scene(&dir, "");
    let out = dir.join("out");
    let first = acuity(&[&[s(&scene), "--out", s(&out), "--json"][..], &FAST].concat());
    assert_eq!(first.status.code(), Some(0));
    let files: Vec<PathBuf> = ["ball", "blob", "rock"]
        .iter()
        .flat_map(|n| [out.join(format!("{n}.acp")), out.join(format!("{n}.json"))])
        .collect();
    let before: Vec<(Vec<u8>, SystemTime)> = files
        .iter()
        .map(|f| (std::fs::read(f).unwrap(), mtime(f)))
        .collect();
    // Coarse file-system clocks: make a rewrite visible in the mtime.
    std::thread::sleep(std::time::Duration::from_millis(1100));

    let second = acuity(&[&[s(&scene), "--out", s(&out), "--json"][..], &FAST].concat());
    assert_eq!(second.status.code(), Some(0));
    let text = stdout(&second);
    for name in ["ball", "blob", "rock"] {
        assert!(
            text.contains(&format!("{name}: cached")),
            "{name} not cached"
        );
    }
    assert!(!text.contains("analysed"));
    // No rendering: the renderer (one device) is not even created.
    assert!(!stderr(&second).contains("renderer:"));
    for (f, (bytes, t)) in files.iter().zip(&before) {
        assert_eq!(&std::fs::read(f).unwrap(), bytes, "{} changed", f.display());
        assert_eq!(mtime(f), *t, "{} was rewritten", f.display());
    }
    // The JSON form is the same profile.
    let bin = Profile::load(&files[0]).unwrap();
    let json = Profile::load(&files[1]).unwrap();
    assert_eq!(bin, json);
}

#[test]
fn scene_profile_settings_apply_and_flags_override_them() {
    let dir = temp_dir("scene_settings");
    let scene = write_scene(
        &dir,
        "\n[profiles]\nresolution = 96\nviewpoints = 0\nstatistic = \"thickness\"\nthreshold_delta_e = 4.5\n",
    );
    let out = dir.join("out");
    let setting = |key: &str| {
        let p = Profile::load(out.join("rock.acp")).unwrap();
        p.settings.get(key).cloned().unwrap_or_default()
    };
    let first = acuity(&[s(&scene), "--out", s(&out)]);
    assert_eq!(first.status.code(), Some(0));
    assert_eq!(setting("resolution_px"), "96");
    assert_eq!(setting("viewpoint_level"), "0");
    assert_eq!(setting("statistic"), "Thickness");
    assert_eq!(setting("threshold_delta_e"), "4.5");
    assert_eq!(setting("min_change_delta_e"), "1");
    assert_eq!(
        Profile::load(out.join("rock.acp"))
            .unwrap()
            .viewpoints
            .len(),
        6
    );

    // A flag overrides its key only; the changed settings invalidate the cache.
    let second = acuity(&[
        s(&scene),
        "--out",
        s(&out),
        "--resolution",
        "112",
        "--min-change",
        "0",
    ]);
    assert_eq!(second.status.code(), Some(0));
    assert!(stdout(&second).contains("rock: analysed"));
    assert_eq!(setting("resolution_px"), "112");
    assert_eq!(setting("min_change_delta_e"), "0");
    assert_eq!(setting("statistic"), "Thickness");
    assert_eq!(setting("threshold_delta_e"), "4.5");
}

#[test]
fn a_changed_input_file_invalidates_only_its_object() {
    let dir = temp_dir("invalidate");
    let scene = write_scene(&dir, "");
    let out = dir.join("out");
    assert_eq!(
        acuity(&[&[s(&scene), "--out", s(&out)][..], &FAST].concat())
            .status
            .code(),
        Some(0)
    );
    let acp = |n: &str| out.join(format!("{n}.acp"));
    let before: Vec<(Vec<u8>, SystemTime)> = ["ball", "blob", "rock"]
        .iter()
        .map(|n| (std::fs::read(acp(n)).unwrap(), mtime(&acp(n))))
        .collect();
    std::thread::sleep(std::time::Duration::from_millis(1100));
    // A different blob: other lumps.
    std::fs::write(dir.join("blob.obj"), lumpy_sphere_obj(16, 32, 5)).unwrap();

    let o = acuity(&[&[s(&scene), "--out", s(&out)][..], &FAST].concat());
    assert_eq!(o.status.code(), Some(0));
    let text = stdout(&o);
    assert!(text.contains("ball: cached"), "{text}");
    assert!(text.contains("blob: analysed"), "{text}");
    assert!(text.contains("rock: cached"), "{text}");
    for (i, n) in ["ball", "blob", "rock"].iter().enumerate() {
        let unchanged =
            std::fs::read(acp(n)).unwrap() == before[i].0 && mtime(&acp(n)) == before[i].1;
        assert_eq!(unchanged, *n != "blob", "{n}");
    }
    // Changing a setting invalidates everything.
    let o = acuity(&[
        s(&scene),
        "--out",
        s(&out),
        "--resolution",
        "96",
        "--viewpoints",
        "0",
    ]);
    assert_eq!(o.status.code(), Some(0));
    assert!(!stdout(&o).contains("cached"), "{}", stdout(&o));
}

#[test]
fn a_broken_object_fails_alone_with_its_file_and_line() {
    let dir = temp_dir("broken");
    std::fs::write(
        dir.join("nan.obj"),
        "v 0 0 0\nv 1 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 2 4\nf 2 3 4\n",
    )
    .unwrap();
    let scene = write_scene(
        &dir,
        r#"
[[objects]]
name = "broken"
mesh = "nan.obj"
generate_triangles = [4, 2]

[[objects]]
name = "absent"
lods = ["missing0.obj", "missing1.obj"]

[[objects]]
name = "ball2"
procedural = { kind = "sphere", triangles = [320, 80] }
"#,
    );
    let out = dir.join("out");
    let o = acuity(&[&[s(&scene), "--out", s(&out)][..], &FAST].concat());
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    // The NaN is on line 3 of nan.obj; the missing file is named.
    assert!(err.contains("nan.obj:3:"), "{err}");
    assert!(err.contains("object `broken`"), "{err}");
    assert!(err.contains("missing0.obj"), "{err}");
    assert!(err.contains("2 of 6 objects failed"), "{err}");
    // A procedural sphere is tessellated and analysed like the others.
    for n in ["ball", "blob", "rock", "ball2"] {
        Profile::load(out.join(format!("{n}.acp"))).unwrap();
    }
    assert!(!out.join("broken.acp").exists());
}

#[test]
fn written_profile_loads_and_selects() {
    let dir = temp_dir("select");
    // A single OBJ: LODs generated at --triangles, profile in the default
    // folder beside it.
    let obj = dir.join("ball.obj");
    std::fs::write(&obj, lumpy_sphere_obj(16, 32, 3)).unwrap();
    let inspect = dir.join("inspect");
    let o = acuity(
        &[
            &[
                s(&obj),
                "--triangles",
                "1000,300,80",
                "--inspect",
                s(&inspect),
            ][..],
            &FAST,
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(0));
    // Every rung's renderings and the features of LOD 0 against each
    // coarser LOD.
    assert!(inspect.join("ball/d016_view000_lod0.png").is_file());
    assert!(
        inspect
            .join("ball/d128_view005_t0-2_features.png")
            .is_file()
    );
    let p = Profile::load(dir.join(".acuity-cache/ball.acp")).unwrap();
    assert_eq!(p.lod_count(), 3);
    assert_eq!(p.viewpoints.len(), 6);
    assert_eq!(p.rung_diameters_px, [16.0, 32.0, 64.0, 128.0]);
    assert_eq!(p.transitions.len(), 6 * 4 * 2);

    let display = Display::new([1280, 1024], [53.1, 41.1]).unwrap();
    let mut sel = Selector::new(display, SelectorSettings::default());
    let pid = sel.add_profile(&p).unwrap();
    let ids: Vec<_> = [2.0, 200.0, 2e4, 2e6]
        .iter()
        .map(|&d| {
            sel.add_object(ObjectDesc {
                center: DVec3::new(0.0, 0.0, -d),
                radius: p.bounding_radius,
                rotation: Quat::IDENTITY,
                profile: pid,
            })
            .unwrap()
        })
        .collect();
    sel.select(&FrameInput {
        camera: Camera {
            position: DVec3::ZERO,
            orientation: Quat::IDENTITY,
        },
        gaze: Gaze::screen_centre(Tracker::None),
        dt_s: 1.0 / 60.0,
        scale: 1.0,
    })
    .unwrap();
    let lods: Vec<usize> = ids
        .iter()
        .map(|&id| sel.selection(id).lod().unwrap_or(usize::MAX))
        .collect();
    eprintln!("LOD at distance 2, 200, 2e4, 2e6 (culled = usize::MAX): {lods:?}");
    assert_eq!(lods[0], 0, "close up: full detail");
    assert!(lods.windows(2).all(|w| w[0] <= w[1]), "{lods:?}");
    assert!(lods[3] > 0, "far away: coarser than LOD 0 ({lods:?})");
}

#[test]
fn bad_arguments_exit_with_2() {
    let dir = temp_dir("args");
    let obj = dir.join("ball.obj");
    std::fs::write(&obj, lumpy_sphere_obj(8, 16, 1)).unwrap();
    let txt = dir.join("notes.txt");
    std::fs::write(&txt, "hello").unwrap();
    let bad_scene = dir.join("bad.toml");
    std::fs::write(&bad_scene, "[display]\nresolution = 5\n").unwrap();
    for args in [
        vec![s(&obj), "--viewpoints", "9"],
        vec![s(&obj), "--threshold", "-1"],
        vec![s(&obj), "--jobs", "0"],
        vec![s(&obj), "--triangles", "100,200"],
        vec![s(&txt)],
        vec!["nowhere/none.obj"],
        vec![s(&bad_scene)],
    ] {
        let o = acuity(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!stderr(&o).is_empty());
    }
    assert!(!dir.join(".acuity-cache").exists());
}

/// The real bunny (3674 triangles; 3928 keeps it as LOD 0), the paper's
/// generated chain, 256 px, 18 viewpoints: coarser LODs lack more, so the
/// first transition's critical frequency should be above the last's on
/// most viewpoints.
#[test]
fn bunny_critical_frequency_falls_from_finest_to_coarsest_transition() {
    let dir = temp_dir("bunny");
    let bunny = Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/bunny.obj");
    let out = dir.join("out");
    let o = acuity(&[
        s(&bunny),
        "--out",
        s(&out),
        "--resolution",
        "256",
        "--viewpoints",
        "1",
    ]);
    assert_eq!(o.status.code(), Some(0));
    let p = Profile::load(out.join("bunny.acp")).unwrap();
    assert_eq!(p.lod_count(), 4);
    assert_eq!(p.rung_diameters_px, [16.0, 32.0, 64.0, 128.0, 256.0]);
    let n = p.viewpoints.len();
    assert_eq!(n, 18);
    let photometry = acuity::Photometry::default();
    let csf = acuity::csf::Csf::new(&photometry, &acuity::Observer::default()).unwrap();
    let mut csfs = acuity::rows::FieldCsfs::new(&csf);
    let top = p.rung_diameters_px.len() - 1;
    // The largest rung on a display of 30 pixels per degree.
    let diameter_deg = p.rung_diameters_px[top] / 30.0;
    let (mut falls, mut monotone) = (0, 0);
    for v in 0..n {
        let critical: Vec<f32> = p
            .transitions_at(v, top)
            .iter()
            .map(|t| {
                acuity::rows::transition_critical_cdiam(
                    &t.features,
                    diameter_deg,
                    &photometry,
                    &mut csfs,
                )
            })
            .collect();
        eprintln!("view {v:2}: critical c/diam {critical:?}");
        falls += usize::from(critical[0] > critical[2]);
        monotone += usize::from(critical.windows(2).all(|w| w[0] >= w[1]));
    }
    eprintln!(
        "bunny {:?}: finest > coarsest on {falls}/{n} viewpoints; non-increasing over all 3 on {monotone}/{n}",
        p.lod_triangles
    );
    // The coarser the LOD, the more it lacks compared with full detail,
    // so the sooner (the larger the object) that is visible. Stated
    // fraction: at least 75% of the viewpoints.
    assert!(falls * 4 >= n * 3, "only {falls}/{n}");
}

#[test]
fn a_mesh_without_triangles_is_kept_whole_and_quartered() {
    let dir = temp_dir("whole");
    // 16 x 32 quads of a lumpy sphere: 960 triangles at least; LOD 0 must
    // be all of them, whatever the count.
    let obj = dir.join("lumpy.obj");
    std::fs::write(&obj, lumpy_sphere_obj(16, 32, 5)).unwrap();
    let o = acuity(&[&[s(&obj)][..], &FAST].concat());
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let p = Profile::load(dir.join(".acuity-cache/lumpy.acp")).unwrap();
    let faces = lumpy_sphere_obj(16, 32, 5)
        .lines()
        .filter(|l| l.starts_with("f "))
        .map(|l| l.split_whitespace().count() as u32 - 3)
        .sum::<u32>();
    assert_eq!(p.lod_triangles[0], faces, "{:?}", p.lod_triangles);
    assert!(p.lod_count() >= 3, "{:?}", p.lod_triangles);
    for w in p.lod_triangles.windows(2) {
        // A quarter each, within the simplifier's tolerance.
        let ratio = f64::from(w[0]) / f64::from(w[1]);
        assert!((3.0..=5.5).contains(&ratio), "{:?}", p.lod_triangles);
    }
    // A target above the mesh's own count keeps the mesh and says so.
    let o = acuity(
        &[
            &[s(&obj), "--triangles", "100000,500", "--force"][..],
            &FAST,
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", stdout(&o));
    let text = format!("{}{}", stdout(&o), String::from_utf8_lossy(&o.stderr));
    assert!(
        text.contains("fewer than the first target 100000"),
        "{text}"
    );
}

#[test]
fn the_cache_hits_from_any_folder_spelling_and_checkout() {
    let dir = temp_dir("spelling");
    let checkout = dir.join("checkout");
    let sub = checkout.join("scenes");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(sub.join("ball.obj"), lumpy_sphere_obj(12, 24, 9)).unwrap();
    std::fs::write(
        sub.join("s.toml"),
        "[display]\nresolution = [160, 120]\nfov_deg = [43.6, 33.4]\n\n\
         [[objects]]\nname = \"ball\"\nmesh = \"ball.obj\"\ngenerate_triangles = [400, 100]\n\n\
         [camera]\nduration_s = 1.0\nforward_speed_m_per_s = 1.0\n",
    )
    .unwrap();
    let link = dir.join("elsewhere");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(&checkout, &link).unwrap();
    let run = |cwd: &Path, scene: &str, extra: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_acuity"))
            .current_dir(cwd)
            .args([&["preprocess", scene][..], &FAST, extra].concat())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        stdout(&o)
    };
    assert!(run(&checkout, "scenes/s.toml", &[]).contains("analysed"));
    let absolute = sub.join("s.toml");
    for (cwd, scene) in [
        (checkout.clone(), "scenes/s.toml"),
        (sub.clone(), "s.toml"),
        (dir.clone(), absolute.to_str().unwrap()),
        (link.clone(), "scenes/s.toml"),
        (link.join("scenes"), "./s.toml"),
    ] {
        let text = run(&cwd, scene, &[]);
        assert!(
            text.contains("cached"),
            "{} from {}: {text}",
            scene,
            cwd.display()
        );
        let text = run(&cwd, scene, &["--check"]);
        assert!(
            text.contains("1 of 1 objects have an up-to-date profile"),
            "{text}"
        );
    }
}

#[test]
fn a_scene_takes_a_ready_profile_and_shares_one_analysis() {
    let dir = temp_dir("ready");
    let (a, b) = (dir.join("a"), dir.join("b"));
    std::fs::create_dir_all(&a).unwrap();
    std::fs::create_dir_all(&b).unwrap();
    std::fs::write(a.join("ball.obj"), lumpy_sphere_obj(12, 24, 9)).unwrap();
    std::fs::write(b.join("other.obj"), lumpy_sphere_obj(12, 24, 4)).unwrap();
    let head = "[display]\nresolution = [160, 120]\nfov_deg = [43.6, 33.4]\n\n";
    let tail = "[camera]\nduration_s = 1.0\nforward_speed_m_per_s = 1.0\n\n\
                [profiles]\nresolution = 128\nviewpoints = 0\n";
    let scene = |folder: &Path, name: &str, objects: &str| {
        let path = folder.join(name);
        std::fs::write(&path, format!("{head}{objects}\n{tail}")).unwrap();
        path
    };
    // A profile and its exported chain, made in one folder...
    let made = scene(
        &a,
        "a.toml",
        "[[objects]]\nname = \"ball\"\nmesh = \"ball.obj\"\ngenerate_triangles = [400, 100]\n",
    );
    let o = acuity(&[s(&made), "--export-lods"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    // ...played from another, with nothing analysed there.
    let ready = scene(
        &b,
        "b.toml",
        "[[objects]]\nname = \"ball\"\nlods = [\"../a/.acuity-cache/ball.lods.glb\"]\n\
         profile = \"../a/.acuity-cache/ball.acp\"\n",
    );
    let play = |scene: &Path| {
        common::acuity_logged(&[
            "run",
            s(scene),
            "--frames",
            "2",
            "--policies",
            "full,acuity_all",
            "--out",
            s(&dir.join("out")),
        ])
    };
    let o = play(&ready);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("profile given by the scene"),
        "{}",
        stderr(&o)
    );
    assert!(!b.join(".acuity-cache/ball.acp").exists());
    // The profile of another mesh is refused, naming what differs.
    let wrong = scene(
        &b,
        "wrong.toml",
        "[[objects]]\nname = \"ball\"\nmesh = \"other.obj\"\ngenerate_triangles = [400, 100]\n\
         profile = \"../a/.acuity-cache/ball.acp\"\n",
    );
    let o = play(&wrong);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("a profile of other inputs"),
        "{}",
        stderr(&o)
    );
    // Two objects of one mesh and settings: one analysis.
    let twins = scene(
        &a,
        "twins.toml",
        "[[objects]]\nname = \"left\"\nmesh = \"ball.obj\"\ngenerate_triangles = [400, 100]\n\n\
         [[objects]]\nname = \"right\"\nmesh = \"ball.obj\"\ngenerate_triangles = [400, 100]\n\
         transform = { position = [1.0, 0.0, 0.0] }\n",
    );
    let o = play(&twins);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("object `right`: 2 LODs, profile shared"),
        "{}",
        stderr(&o)
    );
    // `preprocess` shares too, with the cached twin or with the one it
    // analyses, and writes the profile under both names for `--check`.
    for (flags, left) in [
        (&[][..], "left: cached"),
        (&["--force"][..], "left: analysed"),
    ] {
        let mut args = vec![s(&twins)];
        args.extend_from_slice(flags);
        let o = acuity(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains(left), "{out}");
        assert!(out.contains("right: shared with `left`"), "{out}");
    }
    let o = acuity(&[s(&twins), "--check"]);
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{out}{}", stderr(&o));
    assert!(
        out.contains("2 of 2 objects have an up-to-date profile"),
        "{out}"
    );
}

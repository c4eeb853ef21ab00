//! The whole analysis on the procedural test object: coarser LODs change
//! coarser features, determinism, error isolation, input hashes.

use std::time::Instant;

use acuity_preprocess::features::Grouping;
use acuity_preprocess::frequency::FrequencyStatistic;
use acuity_preprocess::lods::{PAPER_TRIANGLE_TARGETS, ProceduralParams};
use acuity_preprocess::{
    AnalysisSettings, ObjectSource, Renderer, RendererOptions, RunOptions, analyse,
};

fn renderer() -> Renderer {
    Renderer::new(&RendererOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

fn paper_object() -> ObjectSource {
    ObjectSource::Procedural {
        name: "paper-object".into(),
        params: ProceduralParams {
            triangles: 3928,
            seed: 1,
        },
        triangle_targets: PAPER_TRIANGLE_TARGETS.to_vec(),
    }
}

#[test]
fn lowest_contrasted_frequency_falls_as_the_lods_coarsen() {
    let r = renderer();
    let settings = AnalysisSettings::default();
    let inspect = std::env::var_os("ACUITY_INSPECT_DIR");
    let run = RunOptions {
        inspect_dir: inspect.as_deref().map(std::path::Path::new),
        progress: None,
    };
    let t0 = Instant::now();
    let a = analyse(&r, &paper_object(), &settings, &run).unwrap();
    eprintln!(
        "adapter {}; {:?} triangles, {} views: {:.3} s",
        r.adapter_info(),
        a.lod_triangles,
        a.viewpoints.len(),
        t0.elapsed().as_secs_f64()
    );
    let nt = a.lod_triangles.len() - 1;
    let top = a.diameters_px.len() - 1;
    assert_eq!(a.diameters_px, [16, 32, 64, 128, 256, 512]);
    let mut first_above_last = 0;
    let mut monotone = 0;
    for v in 0..a.viewpoints.len() {
        let t = a.transitions_at(v, top);
        // The lowest frequency among features of at least 10% contrast.
        let low: Vec<f32> = t
            .iter()
            .map(|x| {
                x.features
                    .iter()
                    .filter(|f| {
                        (f.luminance[1] - f.luminance[0]) >= 0.1 * (f.luminance[1] + f.luminance[0])
                    })
                    .map(|f| f.freq_cdiam)
                    .fold(f32::INFINITY, f32::min)
            })
            .collect();
        let counts: Vec<u32> = t.iter().map(|x| x.feature_count).collect();
        eprintln!(
            "view {v:2} {:?}: lowest c/diam {low:?}, features {counts:?}",
            a.viewpoints[v]
        );
        if low[0] > low[nt - 1] {
            first_above_last += 1;
        }
        if low.windows(2).all(|w| w[0] >= w[1]) {
            monotone += 1;
        }
    }
    let n = a.viewpoints.len();
    eprintln!(
        "finest > coarsest on {first_above_last}/{n} views; non-increasing over all 3 transitions on {monotone}/{n}"
    );
    // Stated fraction: among features of at least 10% contrast, the first
    // transition's lowest frequency is above the last's on at least 75% of
    // the viewpoints.
    assert!(first_above_last * 4 >= n * 3, "only {first_above_last}/{n}");
}

#[test]
fn two_runs_give_identical_results() {
    let r = renderer();
    let settings = AnalysisSettings {
        resolution_px: 128,
        viewpoint_level: 0,
        ..Default::default()
    };
    let a = analyse(&r, &paper_object(), &settings, &RunOptions::default()).unwrap();
    let b = analyse(
        &renderer(),
        &paper_object(),
        &settings,
        &RunOptions::default(),
    )
    .unwrap();
    assert_eq!(a, b);
    assert_eq!(a.diameters_px, [16, 32, 64, 128]);
    assert_eq!(a.transitions.len(), 6 * 4 * 3);
    assert!(a.transitions.iter().all(|t| {
        t.features
            .windows(2)
            .all(|w| w[0].freq_cdiam <= w[1].freq_cdiam)
            && t.features.len() <= t.feature_count as usize
    }));
}

#[test]
fn a_mesh_of_any_scale_is_analysed_like_one_of_unit_size() {
    use acuity_preprocess::lods::{procedural_object, simplify};
    use acuity_preprocess::pipeline::analyse_lods;
    let r = renderer();
    let m = procedural_object(ProceduralParams {
        triangles: 800,
        seed: 2,
    });
    let chain = [m.clone(), simplify(&m, 200)];
    let settings = AnalysisSettings {
        resolution_px: 64,
        viewpoint_level: 0,
        ..Default::default()
    };
    let lowest = |scale: f32| {
        let scaled: Vec<_> = chain
            .iter()
            .map(|lod| {
                let mut lod = lod.clone();
                for p in &mut lod.positions {
                    *p = p.map(|c| c * scale);
                }
                lod
            })
            .collect();
        let a = analyse_lods(&r, "x", &scaled, &settings, &RunOptions::default()).unwrap();
        let r = a.bounding_sphere.1;
        (
            a.transitions
                .iter()
                .map(|t| t.lowest_cdiam())
                .collect::<Vec<_>>(),
            r,
        )
    };
    let (unit, r1) = lowest(1.0);
    assert!(unit.iter().any(Option::is_some), "{unit:?}");
    for scale in [1e-30, 1e30] {
        let (scaled, r) = lowest(scale);
        assert!(
            (r / (r1 * scale) - 1.0).abs() < 1e-5,
            "radius {r} at {scale}"
        );
        assert_eq!(scaled, unit, "at scale {scale}");
    }
}

#[test]
fn identical_lods_have_no_unique_features() {
    use acuity_preprocess::lods::{procedural_object, simplify};
    use acuity_preprocess::pipeline::analyse_lods;
    let r = renderer();
    let m = procedural_object(ProceduralParams {
        triangles: 800,
        seed: 2,
    });
    let coarse = simplify(&m, 200);
    let settings = AnalysisSettings {
        resolution_px: 64,
        viewpoint_level: 0,
        ..Default::default()
    };
    let a = analyse_lods(
        &r,
        "x",
        &[m.clone(), coarse.clone()],
        &settings,
        &RunOptions::default(),
    )
    .unwrap();
    assert!(a.transitions.iter().any(|t| t.lowest_cdiam().is_some()));
    // Render the same LOD twice through the pipeline's own path: no features.
    let img = |mesh: &acuity_preprocess::Mesh| {
        let cam = acuity_preprocess::views::camera_for([0.0, 1.0, 0.0], [0.0; 3], 1.6, 64);
        let id = r.upload_mesh(mesh).unwrap();
        let out = r
            .render(&acuity_preprocess::RenderRequest {
                width: 64,
                height: 64,
                view_proj: cam.view_proj,
                instances: &[(id, glam::Mat4::IDENTITY)],
                dither: &[],
                albedo: &[],
                lighting: Default::default(),
                background_srgb: [0; 3],
            })
            .unwrap();
        acuity_preprocess::segment::rgba_to_luv(64, 64, &out.rgba).unwrap()
    };
    let settings = acuity_preprocess::features::FeatureSettings {
        grouping: Default::default(),
        threshold_delta_e: 2.3,
        min_change_delta_e: 1.0,
        feret_directions: 8,
        statistic: Default::default(),
    };
    let (f, _) =
        acuity_preprocess::features::unique_features_of(&img(&coarse), &img(&coarse), &settings)
            .unwrap();
    assert!(f.is_empty());
}

#[test]
fn one_bad_object_does_not_stop_the_others() {
    let r = renderer();
    let settings = AnalysisSettings {
        resolution_px: 64,
        viewpoint_level: 0,
        ..Default::default()
    };
    let fixtures =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../render/tests/fixtures/bad_obj");
    let objects = [
        ObjectSource::Files {
            name: "nan".into(),
            lod_paths: vec![
                fixtures.join("nan_coordinate.obj"),
                fixtures.join("good_mtl.obj"),
            ],
        },
        paper_object(),
        ObjectSource::Procedural {
            name: "not-coarser".into(),
            params: ProceduralParams {
                triangles: 300,
                seed: 1,
            },
            triangle_targets: vec![300, 300],
        },
        ObjectSource::Files {
            name: "absent".into(),
            lod_paths: vec![fixtures.join("no_such_file.obj")],
        },
    ];
    let res = acuity_preprocess::analyse_many(&r, &objects, &settings, &RunOptions::default());
    assert_eq!(res.len(), 4);
    let e0 = res[0].as_ref().unwrap_err().to_string();
    assert!(e0.contains("nan_coordinate.obj:2"), "{e0}");
    assert!(res[1].is_ok());
    assert!(res[2].is_err());
    assert!(
        res[3]
            .as_ref()
            .unwrap_err()
            .to_string()
            .contains("no_such_file.obj")
    );
}

#[test]
fn input_hashes_cover_files_mtls_parameters_and_settings() {
    use acuity_preprocess::input_hashes;
    let dir = std::env::temp_dir().join(format!("acuity-hash-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("a.obj");
    std::fs::write(&obj, "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.join("a.mtl"), "newmtl m\nKd 1 0 0\n").unwrap();
    let src = ObjectSource::Generated {
        name: "a".into(),
        path: obj.clone(),
        triangle_targets: vec![1, 0],
    };
    let s = AnalysisSettings::default();
    let h1 = input_hashes(&src, &s).unwrap();
    let whats: Vec<&str> = h1.iter().map(|h| h.what.as_str()).collect();
    assert_eq!(h1.len(), 4, "{whats:?}");
    assert!(whats[1].ends_with("a.mtl") && whats[2] == "lod-generation" && whats[3] == "settings");
    assert_eq!(h1, input_hashes(&src, &s).unwrap());
    // Changing the MTL changes only its hash.
    std::fs::write(dir.join("a.mtl"), "newmtl m\nKd 0 1 0\n").unwrap();
    let h2 = input_hashes(&src, &s).unwrap();
    let changed: Vec<usize> = (0..4).filter(|&i| h1[i] != h2[i]).collect();
    assert_eq!(changed, vec![1]);
    // Settings are part of the hash.
    let h3 = input_hashes(
        &src,
        &AnalysisSettings {
            resolution_px: 256,
            ..s.clone()
        },
    )
    .unwrap();
    assert_ne!(h2[3], h3[3]);
    std::fs::remove_file(dir.join("a.mtl")).unwrap();
    assert_eq!(input_hashes(&src, &s).unwrap()[1].hash_hex, "missing");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn default_settings_have_a_pinned_cache_key() {
    // Changing this string invalidates every cached profile: do it only
    // with a new ANALYSIS_VERSION or a new setting.
    assert_eq!(
        AnalysisSettings::default().cache_key(),
        "analysis v4; resolution_px=512; min_diameter_px=16; viewpoint_level=1; \
         grouping=change_sign; threshold_delta_e_bits=0x40133333; \
         min_change_delta_e_bits=0x3f800000; feret_directions=8; \
         msaa_samples=4; statistic=mean; background_srgb=0,0,0"
    );
}

#[test]
fn every_setting_changes_the_cache_key() {
    let base = AnalysisSettings::default();
    let variants = [
        AnalysisSettings {
            resolution_px: 256,
            ..base.clone()
        },
        AnalysisSettings {
            min_diameter_px: 32,
            ..base.clone()
        },
        AnalysisSettings {
            viewpoint_level: 2,
            ..base.clone()
        },
        AnalysisSettings {
            grouping: Grouping::Regions,
            ..base.clone()
        },
        AnalysisSettings {
            threshold_delta_e: f32::from_bits(base.threshold_delta_e.to_bits() + 1),
            ..base.clone()
        },
        AnalysisSettings {
            min_change_delta_e: 0.0,
            ..base.clone()
        },
        AnalysisSettings {
            feret_directions: 16,
            ..base.clone()
        },
        AnalysisSettings {
            msaa_samples: 1,
            ..base.clone()
        },
        AnalysisSettings {
            statistic: FrequencyStatistic::Thickness,
            ..base.clone()
        },
        AnalysisSettings {
            background_srgb: [0, 0, 1],
            ..base.clone()
        },
    ];
    let mut keys: Vec<String> = variants.iter().map(AnalysisSettings::cache_key).collect();
    keys.push(base.cache_key());
    let n = keys.len();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), n, "two settings share a cache key");
}

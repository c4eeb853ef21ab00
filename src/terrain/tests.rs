use std::collections::{HashMap, HashSet};

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::*;
use crate::acuity::{Components, EccentricityModel, VelocityModel};
use crate::camera::Camera;

/// A rough heightfield of `w` x `h` samples, 10 units apart: two slopes,
/// ridges and hashed bumps up to 40 units.
fn field(w: usize, h: usize, seed: u32) -> Heightfield {
    let heights = (0..w * h)
        .map(|n| {
            let (x, y) = ((n % w) as f32, (n / w) as f32);
            let hash = ((n as u32 ^ seed).wrapping_mul(2_654_435_761) >> 16) as f32 / 65536.0;
            3.0 * x + 2.0 * y + 15.0 * (0.7 * x).sin() * (0.4 * y).cos() + 40.0 * hash
        })
        .collect();
    Heightfield::new(w, h, 10.0, heights).unwrap()
}

fn settings(components: Components, viewport_cull: bool) -> TerrainSettings {
    TerrainSettings {
        components,
        viewport_cull,
        fov_deg: [100.0, 70.0],
        display_limit_cpd: 8.0,
        scale: 1.0,
        eccentricity_model: EccentricityModel::Reddy2001,
        velocity_model: VelocityModel::Reddy2001,
    }
}

fn view(eye: [f64; 3], yaw_deg: f32, turn_deg: f32) -> TerrainView {
    let dir = |yaw: f32| {
        let (s, c) = yaw.to_radians().sin_cos();
        Vec3::new(s, c, -0.3)
    };
    let at = |yaw| Camera::look_to(DVec3::from(eye), dir(yaw), Vec3::Z).unwrap();
    TerrainView {
        camera: at(yaw_deg),
        previous: Some(at(yaw_deg - turn_deg)),
        dt_s: 0.1,
    }
}

fn triangles(t: &Terrain, v: &TerrainView, s: &TerrainSettings) -> Refinement {
    let mut out = Refinement::new();
    t.refine(v, s, &mut out).unwrap();
    out
}

/// Every edge of the mesh: how many triangles use it.
fn edges(mesh: &Refinement) -> HashMap<(Vertex, Vertex), usize> {
    let mut count = HashMap::new();
    for tri in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    count
}

/// No mesh vertex lies strictly inside an axis-aligned edge (a
/// T-junction, where a crack opens).
fn assert_no_t_junctions(mesh: &Refinement) {
    let vertices: HashSet<Vertex> = mesh.triangles().iter().flatten().copied().collect();
    for (a, b) in edges(mesh).keys() {
        if a[0] == b[0] {
            for y in a[1].min(b[1]) + 1..a[1].max(b[1]) {
                assert!(
                    !vertices.contains(&[a[0], y]),
                    "T-junction at {:?}",
                    [a[0], y]
                );
            }
        } else if a[1] == b[1] {
            for x in a[0].min(b[0]) + 1..a[0].max(b[0]) {
                assert!(
                    !vertices.contains(&[x, a[1]]),
                    "T-junction at {:?}",
                    [x, a[1]]
                );
            }
        }
    }
}

fn twice_area(t: &[Vertex; 3]) -> i64 {
    let p = t.map(|v| [v[0] as i64, v[1] as i64]);
    (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1])
}

#[test]
fn without_criteria_the_mesh_is_full_resolution() {
    let t = Terrain::new(field(37, 29, 1));
    assert_eq!(t.depth(), 7); // 36 cells -> a root of 64
    let mesh = triangles(
        &t,
        &view([0.0, 0.0, 500.0], 45.0, 0.0),
        &settings(Components::NONE, false),
    );
    assert_eq!(mesh.stats().triangles, t.heightfield().full_triangles());
    assert_eq!(mesh.stats().leaves, 36 * 28);
}

#[test]
fn an_exact_plane_needs_one_node() {
    let heights = (0..17 * 9)
        .map(|n| (n % 17) as f32 + 2.0 * (n / 17) as f32)
        .collect();
    let t = Terrain::new(Heightfield::new(17, 9, 1.0, heights).unwrap());
    let mesh = triangles(
        &t,
        &view([0.0, 0.0, 5.0], 45.0, 0.0),
        &settings(Components::ALL, false),
    );
    assert_eq!(mesh.stats().leaves, 1);
    assert_eq!(mesh.stats().triangles, 2);
}

#[test]
fn the_refined_mesh_is_crack_free_and_covers_the_grid() {
    let t = Terrain::new(field(41, 33, 3));
    let s = settings(Components::ALL, false);
    let mesh = triangles(&t, &view([50.0, 40.0, 120.0], 30.0, 2.0), &s);
    assert!(
        mesh.stats().leaves > 20,
        "too coarse to test: {:?}",
        mesh.stats()
    );
    assert!(mesh.stats().triangles < t.heightfield().full_triangles());
    // Counter-clockwise, and together exactly the grid (doubled units).
    let area: i64 = mesh.triangles().iter().map(twice_area).sum();
    assert!(mesh.triangles().iter().all(|t| twice_area(t) > 0));
    assert_eq!(area, 2 * (80 * 64));
    // Interior edges are shared by two triangles, border edges by one.
    for ((a, b), n) in edges(&mesh) {
        let border = |c: usize, max: u32| a[c] == b[c] && (a[c] == 0 || a[c] == max);
        let expected = if border(0, 80) || border(1, 64) { 1 } else { 2 };
        assert_eq!(n, expected, "edge {a:?}-{b:?}");
    }
    assert_no_t_junctions(&mesh);
}

#[test]
fn viewport_culling_drops_what_is_behind() {
    // Nodes larger than `CULL_NODE_CELLS` for culling to act within.
    let t = Terrain::new(field(129, 97, 4));
    let v = view([640.0, -100.0, 60.0], 180.0, 0.0); // looking away, south
    let mesh = triangles(&t, &v, &settings(Components::NONE, true));
    assert_eq!(mesh.stats().triangles, 0);
    let v = view([640.0, -100.0, 60.0], 0.0, 0.0);
    let mesh = triangles(&t, &v, &settings(Components::NONE, true));
    assert!(mesh.stats().triangles > 0 && mesh.stats().nodes_culled > 0);
    assert_no_t_junctions(&mesh);
}

/// Cells covered by the leaves.
fn leaf_cells(mesh: &Refinement) -> u64 {
    mesh.leaves()
        .iter()
        .map(|&[x0, y0, x1, y1]| u64::from(x1 - x0) * u64::from(y1 - y0))
        .sum()
}

#[test]
fn culling_keeps_the_same_region_under_every_criterion() {
    // 129 x 97 samples: a root of 128 cells, so nodes above
    // `CULL_NODE_CELLS` straddle the view's edges.
    let t = Terrain::new(field(129, 97, 5));
    for (eye, yaw) in [([640.0, 480.0, 80.0], 30.0), ([640.0, 480.0, 900.0], 200.0)] {
        let v = view(eye, yaw, 5.0);
        let region = |c| {
            let mesh = triangles(&t, &v, &settings(c, true));
            assert_no_t_junctions(&mesh);
            (leaf_cells(&mesh), mesh.stats())
        };
        let (none, stats) = region(Components::NONE);
        assert!(stats.nodes_culled > 0 && none < 128 * 96, "{stats:?}");
        let size = Components {
            size: true,
            eccentricity: false,
            velocity: false,
        };
        for c in [size, Components::ALL] {
            let (cells, stats) = region(c);
            assert_eq!(cells, none, "{c:?}: {stats:?}");
        }
    }
}

#[test]
fn bad_input_is_refused() {
    assert!(Heightfield::new(1, 5, 1.0, vec![0.0; 5]).is_err());
    assert!(Heightfield::new(2, 2, 0.0, vec![0.0; 4]).is_err());
    let e = Heightfield::new(2, 2, 1.0, vec![0.0, f32::NAN, 0.0, 0.0]).unwrap_err();
    assert!(e.to_string().contains("sample (1, 0) is NaN"), "{e}");
    assert!(Heightfield::new(2, 2, 1.0, vec![0.0; 3]).is_err());
    let t = Terrain::new(field(9, 9, 0));
    let mut out = Refinement::new();
    let v = view([0.0, 0.0, 10.0], 0.0, 1.0);
    let bad = TerrainSettings {
        fov_deg: [0.0, 10.0],
        ..settings(Components::ALL, true)
    };
    assert!(t.refine(&v, &bad, &mut out).is_err());
    let nan_dt = TerrainView {
        dt_s: f32::NAN,
        ..v
    };
    let e = t
        .refine(&nan_dt, &settings(Components::ALL, true), &mut out)
        .unwrap_err();
    assert!(e.to_string().contains("dt_s"), "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    // Each added criterion removes splits and so triangles, with or
    // without culling: culling decides from geometry alone
    // (`CULL_NODE_CELLS`), so every row draws the same region.
    #[test]
    fn each_added_criterion_never_adds_triangles(
        seed in 0u32..1000,
        x in -100.0f64..500.0, y in -100.0f64..400.0, z in 20.0f64..400.0,
        yaw in -180.0f32..180.0, turn in 0.0f32..15.0,
    ) {
        let t = Terrain::new(field(81, 65, seed));
        let v = view([x, y, z], yaw, turn);
        let run = |size, eccentricity, velocity, cull| {
            let c = Components { size, eccentricity, velocity };
            let mesh = triangles(&t, &v, &settings(c, cull));
            assert_no_t_junctions(&mesh);
            mesh.stats()
        };
        let full = t.heightfield().full_triangles();
        for cull in [false, true] {
            let none = run(false, false, false, cull);
            let size = run(true, false, false, cull);
            let peripheral = run(true, true, false, cull);
            let velocity = run(true, false, true, cull);
            let all = run(true, true, true, cull);
            let rows = [none, size, peripheral, velocity, all];
            if cull {
                prop_assert!(none.triangles <= full);
            } else {
                prop_assert_eq!(none.triangles, full);
            }
            for n in [rows.map(|r| r.triangles), rows.map(|r| r.nodes_visited)] {
                prop_assert!(n[1] <= n[0] && n[2] <= n[1] && n[3] <= n[1], "{:?}", n);
                prop_assert!(n[4] <= n[2] && n[4] <= n[3], "{:?}", n);
            }
        }
    }
}

//! The bunny among rocks: `bevy_acuity` in a window. A camera circles the
//! Stanford bunny (`models/bunny.obj`) among 60 rocks, coming close and
//! going far; every entity's LOD is chosen by acuity each frame and shown,
//! on demand, as a colour (LOD 0 green, 1 yellow, 2 orange, 3 red).
//!
//! ```sh
//! cargo run --release -p bevy_acuity --features window --example bunny_rocks
//! ```
//!
//! Keys: `[` / `]` halve / double `s`; C the LOD colours; F a fixed 60 Hz
//! (the reactive scheduler on Bevy's frame time) or the fixed `s`; Space
//! pause the camera; Esc quit. The title shows `s`, the triangles drawn
//! against full detail, and the frame rate.
//!
//! The bunny's LODs are child entities (an HLOD group: switches
//! cross-fade by dithering), made here by vertex clustering; the rocks'
//! are meshes swapped on the entity: icospheres of 4, 2, 1 and 0
//! subdivisions. Their profiles are stand-ins built in code (as in
//! `examples/minimal.rs`); `--profile FILE.acp` gives every entity one
//! from `acuity preprocess` through the asset loader instead.
//!
//! Scripted runs: `--frames N --screenshot FILE.png` saves the Nth frame
//! and quits; `--lod-colours` starts with the colours on; `--time S`
//! starts the camera's path S seconds in.

use std::collections::HashMap;
use std::path::PathBuf;

// The runtime's examples' stand-in profile (`demo_profile` and `finish`
// are not used here).
#[allow(dead_code)]
#[path = "../../examples/common/mod.rs"]
mod common;

use bevy::asset::RenderAssetUsages;
use bevy::core_pipeline::tonemapping::Tonemapping;
use bevy::mesh::{Indices, PrimitiveTopology};
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy_acuity::{
    AcuityLod, AcuityPlugin, AcuityProfile, AcuityScheduler, AcuitySettings, AcuityStats,
    LodLevels, SelectedLod,
};
use common::stand_in_profile;

/// The command line.
#[derive(Resource, Clone, Debug, Default)]
struct Args {
    screenshot: Option<PathBuf>,
    frames: u32,
    colours: bool,
    profile: Option<String>,
    start_s: f32,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        frames: 120,
        ..default()
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = |name: &str| it.next().ok_or(format!("{name} needs a value"));
        match arg.as_str() {
            "--screenshot" => args.screenshot = Some(value("--screenshot")?.into()),
            "--frames" => {
                args.frames = value("--frames")?
                    .parse()
                    .map_err(|e| format!("--frames: {e}"))?
            }
            "--time" => {
                args.start_s = value("--time")?
                    .parse()
                    .map_err(|e| format!("--time: {e}"))?
            }
            "--profile" => args.profile = Some(value("--profile")?),
            "--lod-colours" => args.colours = true,
            other => return Err(format!("unknown argument {other}")),
        }
    }
    Ok(args)
}

fn main() -> AppExit {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("error: {e}");
            return AppExit::from_code(2);
        }
    };
    let root = std::env::current_dir().unwrap_or_default();
    App::new()
        .add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: Some(Window {
                        title: "bevy_acuity: the bunny among rocks".into(),
                        resolution: (960, 540).into(),
                        ..default()
                    }),
                    ..default()
                })
                .set(AssetPlugin {
                    file_path: root.to_string_lossy().into_owned(),
                    ..default()
                }),
        )
        .add_plugins(AcuityPlugin)
        .insert_resource(args)
        .insert_resource(GlobalAmbientLight {
            brightness: 400.0,
            ..default()
        })
        .add_systems(Startup, setup)
        .add_systems(Update, (keys, fly, title, screenshot))
        .add_systems(PostUpdate, colour_lods.after(bevy_acuity::AcuitySystems))
        .run()
}

/// The OBJ's positions and triangles (`v` and `f` lines; polygons fanned).
fn read_obj(path: &str) -> Result<(Vec<Vec3>, Vec<[u32; 3]>), String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        let bad = |what: &str| format!("{path}:{}: {what}", n + 1);
        match words.next() {
            Some("v") => {
                let v: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                let [x, y, z] = v[..] else {
                    return Err(bad("a vertex needs three numbers"));
                };
                positions.push(Vec3::new(x, y, z));
            }
            Some("f") => {
                let idx: Vec<u32> = words
                    .filter_map(|w| w.split('/').next()?.parse::<u32>().ok())
                    .collect();
                if idx.len() < 3 || idx.iter().any(|&i| i == 0 || i as usize > positions.len()) {
                    return Err(bad("a face needs three 1-based vertex indices"));
                }
                for k in 1..idx.len() - 1 {
                    triangles.push([idx[0] - 1, idx[k] - 1, idx[k + 1] - 1]);
                }
            }
            _ => {}
        }
    }
    Ok((positions, triangles))
}

/// A coarser copy by vertex clustering: vertices in one cell of a grid of
/// `cell` units merge at their mean; collapsed triangles go.
fn cluster(positions: &[Vec3], triangles: &[[u32; 3]], cell: f32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut cells: HashMap<[i32; 3], u32> = HashMap::new();
    let (mut sums, mut counts, mut remap) = (Vec::new(), Vec::new(), Vec::new());
    for p in positions {
        let key = (*p / cell).floor().as_ivec3().to_array();
        let id = *cells.entry(key).or_insert_with(|| {
            sums.push(Vec3::ZERO);
            counts.push(0.0);
            sums.len() as u32 - 1
        });
        sums[id as usize] += *p;
        counts[id as usize] += 1.0;
        remap.push(id);
    }
    let merged = sums.iter().zip(&counts).map(|(s, c)| *s / *c).collect();
    let kept = triangles
        .iter()
        .map(|t| t.map(|i| remap[i as usize]))
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .collect();
    (merged, kept)
}

fn to_mesh(positions: Vec<Vec3>, triangles: &[[u32; 3]]) -> Mesh {
    Mesh::new(
        PrimitiveTopology::TriangleList,
        RenderAssetUsages::default(),
    )
    .with_inserted_attribute(Mesh::ATTRIBUTE_POSITION, positions)
    .with_inserted_indices(Indices::U32(triangles.concat()))
    .with_computed_smooth_normals()
}

fn triangle_count(mesh: &Mesh) -> u32 {
    mesh.indices().map_or(0, |i| i.len() as u32 / 3)
}

/// The colour of each LOD: green, yellow, orange, red, magenta.
const LOD_COLOURS: [Color; 5] = [
    Color::srgb(0.1, 0.8, 0.1),
    Color::srgb(0.9, 0.9, 0.1),
    Color::srgb(1.0, 0.5, 0.0),
    Color::srgb(0.9, 0.1, 0.1),
    Color::srgb(0.9, 0.1, 0.9),
];

/// The entity's own material, restored when the colours go off.
#[derive(Component)]
struct OwnMaterial(Handle<StandardMaterial>);

/// The materials of the LOD colours.
#[derive(Resource)]
struct LodMaterials(Vec<Handle<StandardMaterial>>);

/// Whether the camera flies, and where on its path it is (s).
#[derive(Resource)]
struct Path {
    paused: bool,
    t_s: f32,
}

fn setup(
    mut commands: Commands,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
    mut profiles: ResMut<Assets<AcuityProfile>>,
    server: Res<AssetServer>,
    args: Res<Args>,
    mut settings: ResMut<AcuitySettings>,
) {
    settings.selector.fade_time_s = 0.3;
    commands.insert_resource(LodMaterials(
        LOD_COLOURS
            .iter()
            .map(|c| materials.add(StandardMaterial::from_color(*c)))
            .collect(),
    ));
    commands.insert_resource(Path {
        paused: false,
        t_s: args.start_s,
    });
    let loaded = args
        .profile
        .as_ref()
        .map(|p| server.load::<AcuityProfile>(p.clone()));

    // The bunny: recentred on its bounding box, 1 unit tall, four LODs.
    let (mut positions, triangles) = match read_obj("models/bunny.obj") {
        Ok(mesh) => mesh,
        Err(e) => {
            error!("{e} (run from the repository's root)");
            (vec![Vec3::ZERO; 3], vec![[0, 1, 2]])
        }
    };
    let (lo, hi) = positions
        .iter()
        .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        });
    let (centre, height) = ((lo + hi) / 2.0, (hi.y - lo.y).max(1e-6));
    for p in &mut positions {
        *p = (*p - centre) / height;
    }
    let radius = positions.iter().map(|p| p.length()).fold(0.0, f32::max);
    let bunny_material = materials.add(StandardMaterial::from_color(Color::srgb(0.85, 0.8, 0.75)));
    let mut bunny_meshes = vec![to_mesh(positions.clone(), &triangles)];
    for cell in [0.045, 0.09, 0.18] {
        let (p, t) = cluster(&positions, &triangles, cell);
        bunny_meshes.push(to_mesh(p, &t));
    }
    let bunny_tris: Vec<u32> = bunny_meshes.iter().map(triangle_count).collect();
    info!("bunny LODs: {bunny_tris:?} triangles");
    let bunny_profile = loaded.clone().unwrap_or_else(|| {
        profiles.add(AcuityProfile(stand_in_profile("bunny", radius, bunny_tris)))
    });
    let bunny = commands
        .spawn((
            Transform::from_xyz(0.0, 0.72, 0.0).with_scale(Vec3::splat(1.5)),
            Visibility::default(),
        ))
        .id();
    let children: Vec<Entity> = bunny_meshes
        .into_iter()
        .map(|m| {
            commands
                .spawn((
                    Mesh3d(meshes.add(m)),
                    MeshMaterial3d(bunny_material.clone()),
                    OwnMaterial(bunny_material.clone()),
                    Transform::default(),
                    ChildOf(bunny),
                ))
                .id()
        })
        .collect();
    commands
        .entity(bunny)
        .insert(AcuityLod::children(bunny_profile, children));

    // 60 rocks: icospheres of 4, 2, 1, 0 subdivisions, squashed and turned.
    let rock_meshes: Vec<Handle<Mesh>> = [4, 2, 1, 0]
        .into_iter()
        .map(|n| {
            let m = Sphere::new(1.0)
                .mesh()
                .ico(n)
                .unwrap_or_else(|_| Sphere::new(1.0).mesh().build());
            meshes.add(m)
        })
        .collect();
    let rock_tris = [4u32, 2, 1, 0].map(|n| 20 * 4u32.pow(n)).to_vec();
    let rock_profile = loaded
        .unwrap_or_else(|| profiles.add(AcuityProfile(stand_in_profile("rock", 1.0, rock_tris))));
    let rock_material = materials.add(StandardMaterial::from_color(Color::srgb(0.45, 0.4, 0.35)));
    let mut state = 7u64;
    let mut random = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    for _ in 0..60 {
        let (angle, distance) = (random() * std::f32::consts::TAU, 2.5 + 35.0 * random());
        let size = 0.3 + 0.9 * random();
        commands.spawn((
            Transform::from_xyz(angle.cos() * distance, 0.3 * size, angle.sin() * distance)
                .with_rotation(Quat::from_rotation_y(random() * 6.0))
                .with_scale(Vec3::new(size, 0.6 * size, 0.8 * size)),
            Mesh3d(rock_meshes[3].clone()),
            MeshMaterial3d(rock_material.clone()),
            OwnMaterial(rock_material.clone()),
            AcuityLod::meshes(rock_profile.clone(), rock_meshes.clone()),
        ));
    }
    commands.spawn((
        Mesh3d(meshes.add(Plane3d::default().mesh().size(100.0, 100.0))),
        MeshMaterial3d(materials.add(StandardMaterial::from_color(Color::srgb(0.3, 0.35, 0.3)))),
    ));
    commands.spawn((
        DirectionalLight {
            illuminance: 8000.0,
            shadow_maps_enabled: false,
            ..default()
        },
        Transform::from_xyz(4.0, 10.0, 6.0).looking_at(Vec3::ZERO, Vec3::Y),
    ));
    // No tonemapping lookup tables (a Bevy feature of their own): plain
    // Reinhard.
    commands.spawn((
        Camera3d::default(),
        Tonemapping::Reinhard,
        Transform::default(),
    ));
}

/// The camera circles the bunny at 3 to 40 units, once a minute.
fn fly(time: Res<Time>, mut path: ResMut<Path>, mut camera: Query<&mut Transform, With<Camera3d>>) {
    if !path.paused {
        path.t_s += time.delta_secs();
    }
    let t = path.t_s;
    let distance = 21.5 - 18.5 * (0.21 * t).cos();
    let angle = 0.1 * t;
    for mut tf in &mut camera {
        *tf = Transform::from_xyz(
            angle.sin() * distance,
            1.0 + 0.08 * distance,
            angle.cos() * distance,
        )
        .looking_at(Vec3::new(0.0, 0.6, 0.0), Vec3::Y);
    }
}

fn keys(
    input: Res<ButtonInput<KeyCode>>,
    mut settings: ResMut<AcuitySettings>,
    mut scheduler: ResMut<AcuityScheduler>,
    mut args: ResMut<Args>,
    mut path: ResMut<Path>,
    mut exit: MessageWriter<AppExit>,
) {
    if input.just_pressed(KeyCode::BracketLeft) {
        settings.scale = (settings.scale * 0.5).max(1.0 / 64.0);
    }
    if input.just_pressed(KeyCode::BracketRight) {
        settings.scale = (settings.scale * 2.0).min(1.0);
    }
    if input.just_pressed(KeyCode::KeyC) {
        args.colours = !args.colours;
    }
    if input.just_pressed(KeyCode::KeyF) {
        *scheduler = match *scheduler {
            AcuityScheduler::Off => AcuityScheduler::reactive(60.0).unwrap_or_default(),
            _ => AcuityScheduler::Off,
        };
    }
    if input.just_pressed(KeyCode::Space) {
        path.paused = !path.paused;
    }
    if input.just_pressed(KeyCode::Escape) {
        exit.write(AppExit::Success);
    }
}

/// Each entity in its own material, or its LOD's colour.
fn colour_lods(
    args: Res<Args>,
    colours: Res<LodMaterials>,
    changed: Query<(Entity, &SelectedLod, &AcuityLod, Ref<SelectedLod>)>,
    mut materials: Query<(&mut MeshMaterial3d<StandardMaterial>, &OwnMaterial)>,
) {
    for (entity, selected, lod, tick) in &changed {
        if !(args.is_changed() || tick.is_changed()) {
            continue;
        }
        let targets: Vec<Entity> = match &lod.levels {
            LodLevels::Meshes(_) => vec![entity],
            LodLevels::Children(c) => c.clone(),
        };
        for target in targets {
            let Ok((mut material, own)) = materials.get_mut(target) else {
                continue;
            };
            material.0 = match (args.colours, selected.0) {
                (true, Some(l)) => colours.0[l.min(colours.0.len() - 1)].clone(),
                _ => own.0.clone(),
            };
        }
    }
}

fn title(
    stats: Res<AcuityStats>,
    scheduler: Res<AcuityScheduler>,
    time: Res<Time<Real>>,
    lods: Query<&AcuityLod>,
    profiles: Res<Assets<AcuityProfile>>,
    mut windows: Query<&mut Window>,
    mut fps: Local<f32>,
) {
    let dt = time.delta_secs();
    if dt > 0.0 {
        *fps = if *fps == 0.0 {
            1.0 / dt
        } else {
            0.95 * *fps + 0.05 / dt
        };
    }
    let full: u64 = lods
        .iter()
        .filter_map(|l| profiles.get(&l.profile))
        .map(|p| u64::from(p.0.lod_triangles[0]))
        .sum();
    let mode = match *scheduler {
        AcuityScheduler::Off => "fixed s",
        _ => "60 Hz",
    };
    for mut window in &mut windows {
        window.title = format!(
            "bevy_acuity  s {:.3} ({mode})  triangles {} of {} ({:.0}%)  {:.0} fps  [ ] s, C colours, F 60 Hz, Space pause",
            stats.scale,
            stats.triangles,
            full,
            100.0 * stats.triangles as f64 / full.max(1) as f64,
            *fps
        );
    }
}

/// `--screenshot`: the Nth frame saved, then quit.
fn screenshot(
    mut commands: Commands,
    args: Res<Args>,
    mut frame: Local<u32>,
    mut exit: MessageWriter<AppExit>,
) {
    let Some(path) = &args.screenshot else { return };
    *frame += 1;
    if *frame == args.frames {
        commands
            .spawn(Screenshot::primary_window())
            .observe(save_to_disk(path.clone()));
    }
    // The capture is read back a few frames later.
    if *frame == args.frames + 30 {
        exit.write(AppExit::Success);
    }
}

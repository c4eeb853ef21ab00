//! Profiles as assets: binary and JSON files load; corrupt, truncated and
//! empty files fail through Bevy's `AssetLoadFailedEvent`, never a panic,
//! and the entity that uses one stays unregistered.

mod common;

use std::path::PathBuf;

use bevy::asset::{AssetLoadFailedEvent, LoadState};
use bevy::prelude::*;
use bevy_acuity::{AcuityCameras, AcuityLod, AcuityProfile, ProfileLoadError};
use common::*;

/// A fresh folder of profile files for one test.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bevy_acuity-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// The headless app reading assets from `dir`.
fn app_reading(dir: &std::path::Path) -> App {
    let mut app = App::new();
    app.add_plugins((
        MinimalPlugins,
        TransformPlugin,
        AssetPlugin {
            file_path: dir.to_string_lossy().into_owned(),
            ..default()
        },
        bevy_acuity::AcuityPlugin,
    ));
    app.world_mut().spawn((
        Window {
            resolution: bevy::window::WindowResolution::new(1920, 1080),
            ..default()
        },
        bevy::window::PrimaryWindow,
    ));
    app
}

/// Updates until every handle has loaded or failed (at most 10 s).
fn settle(
    app: &mut App,
    handles: &[Handle<AcuityProfile>],
) -> Vec<AssetLoadFailedEvent<AcuityProfile>> {
    let mut failed = Vec::new();
    let mut reader = Reader::<AssetLoadFailedEvent<AcuityProfile>>::new();
    let start = std::time::Instant::now();
    loop {
        app.update();
        failed.extend(reader.read(app));
        let server = app.world().resource::<AssetServer>();
        let done = handles.iter().all(|h| {
            matches!(
                server.load_state(h.id()),
                LoadState::Loaded | LoadState::Failed(_)
            )
        });
        if done || start.elapsed().as_secs() > 10 {
            return failed;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

#[test]
fn binary_and_json_profiles_load_as_assets() {
    let dir = folder("good");
    demo_profile().save(dir.join("rock.acp")).expect("binary");
    demo_profile()
        .save(dir.join("rock.acp.json"))
        .expect("JSON");
    let mut app = app_reading(&dir);
    let server = app.world().resource::<AssetServer>().clone();
    let handles = [server.load("rock.acp"), server.load("rock.acp.json")];
    let failed = settle(&mut app, &handles);
    assert!(failed.is_empty(), "{failed:?}");
    let assets = app.world().resource::<Assets<AcuityProfile>>();
    for h in &handles {
        assert_eq!(assets.get(h).expect("loaded").0, demo_profile());
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn corrupt_profiles_fail_through_asset_events_and_register_nothing() {
    let dir = folder("bad");
    let good = acuity::profile::binary::encode(&demo_profile()).expect("encodes");
    let files: [(&str, Vec<u8>); 5] = [
        ("truncated.acp", good[..good.len() / 2].to_vec()),
        ("flipped.acp", {
            let mut b = good.clone();
            let at = b.len() / 2;
            b[at] ^= 0x5a;
            b
        }),
        ("empty.acp", Vec::new()),
        (
            "garbage.acp.json",
            b"{ \"format_version\": 3, \"name\": [".to_vec(),
        ),
        (
            "random.acp",
            (0..4096u32)
                .map(|i| (i.wrapping_mul(2654435761) >> 24) as u8)
                .collect(),
        ),
    ];
    for (name, bytes) in &files {
        std::fs::write(dir.join(name), bytes).expect("written");
    }
    let mut app = app_reading(&dir);
    let camera = spawn_camera(&mut app, 20.0);
    let server = app.world().resource::<AssetServer>().clone();
    let handles: Vec<Handle<AcuityProfile>> =
        files.iter().map(|(name, _)| server.load(*name)).collect();
    let entity = app
        .world_mut()
        .spawn((
            Transform::default(),
            AcuityLod::children(handles[0].clone(), vec![]),
        ))
        .id();
    let failed = settle(&mut app, &handles);
    assert_eq!(failed.len(), files.len(), "{failed:?}");
    for event in &failed {
        let message = event.error.to_string();
        assert!(!message.is_empty());
        // The loader's own error, not a missing loader.
        assert!(
            matches!(
                event.error,
                bevy::asset::AssetLoadError::AssetLoaderError(_)
            ),
            "{}: {message}",
            event.path
        );
    }
    for h in &handles {
        assert!(matches!(server.load_state(h.id()), LoadState::Failed(_)));
    }
    app.update();
    assert_eq!(
        app.world()
            .resource::<AcuityCameras>()
            .get(camera)
            .map(|c| c.object_count()),
        Some(0)
    );
    assert_eq!(lod(&app, entity), None);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn the_loader_error_names_the_fault() {
    let e = ProfileLoadError::Profile(
        acuity::Profile::from_bytes(b"not a profile").expect_err("refused"),
    );
    assert!(!e.to_string().is_empty());
    assert!(std::error::Error::source(&e).is_some());
}

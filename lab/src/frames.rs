//! The scene player's world: a scene's LOD chains uploaded once to the
//! shared renderer, their profiles (cached), every placement as a
//! selectable instance, and one function that renders a frame with chosen
//! LODs.
//!
//! Rendering is camera-relative: instance matrices are built from
//! `position - eye` in `f64` and only then narrowed to `f32`, so scenes far
//! from the origin render as precisely as near it.

use std::path::{Path, PathBuf};
use std::time::Instant;

use acuity::display::projection_columns;
use acuity_preprocess::pipeline::{AnalysisSettings, RunOptions};
use acuity_render::{
    DitherMask, Lighting, MeshId, RenderOutput, RenderRequest, Renderer, RendererOptions,
};
use anyhow::Context;
use glam::{DMat4, DQuat, DVec3, Mat4};

use crate::crossfade::FadeOut;
use crate::limits::check_scene_triangles;
use crate::placement::Placement;
use crate::profiles::object_source;
use crate::profiles::{
    CacheOutcome, check_distinct_cache_paths, ensure_profile, given_profile, input_key,
};
use crate::scene::{ProfileSpec, Scene};
use acuity::{Camera, Display, Gaze, Profile, Tracker};

/// Near clipping plane of the player's projection, metres.
pub const NEAR_PLANE_M: f32 = 0.05;

/// Background colour of rendered frames, sRGB8: black, as in the offline
/// pass, so silhouettes have the contrast the profiles measured.
pub const BACKGROUND_SRGB: [u8; 3] = [0, 0, 0];

/// One object of the world: its LOD meshes on the GPU and its profile.
#[derive(Debug, Clone)]
pub struct WorldObject {
    /// The scene's object name.
    pub name: String,
    /// The uploaded LOD meshes, finest first.
    pub meshes: Vec<MeshId>,
    /// Triangles per LOD, finest first.
    pub lod_triangles: Vec<u32>,
    /// The object's profile.
    pub profile: Profile,
    /// Whether the profile came from the cache.
    pub cache: CacheOutcome,
    /// Centre of LOD 0's bounding sphere, mesh units.
    pub center_mesh: DVec3,
}

/// One placed instance of an object.
#[derive(Debug, Clone, Copy)]
pub struct Instance {
    /// Index into [`World::objects`].
    pub object: usize,
    /// Index of the copy within its object (0 for a single transform).
    pub copy: usize,
    /// Where it stands.
    pub placement: Placement,
    /// Centre of its bounding sphere, world metres.
    pub center_m: DVec3,
    /// Radius of its bounding sphere, metres (profile radius x scale).
    pub radius_m: f64,
}

/// Options of [`World::load`]; the default analyses with the offline
/// pass's default settings.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Where profiles are cached; default `<scene dir>/.acuity-cache/`.
    pub cache_dir: Option<PathBuf>,
    /// Analysis settings for profiles that must be made.
    pub settings: AnalysisSettings,
    /// Print progress lines to stderr.
    pub verbose: bool,
}

/// The profile options `acuity run` and the experiments share: where
/// profiles are cached and how those that must be made are analysed, plus
/// whether to print progress.
#[derive(Debug, Clone, Default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct ProfileArgs {
    /// Profile cache folder (default `<scene dir>/.acuity-cache/`).
    #[cfg_attr(feature = "clap", arg(long))]
    pub cache_dir: Option<PathBuf>,
    /// Image size of profiles that must be made, pixels (16..=8192)
    /// [default: the scene's `[profiles]`, else 512].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(AnalysisSettings::MIN_RESOLUTION_PX as i64..=AnalysisSettings::MAX_RESOLUTION_PX as i64)))]
    pub profile_resolution: Option<u32>,
    /// Smallest rung of the size ladder of profiles that must be made,
    /// pixels [default: the scene's `[profiles]`, else 16].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(AnalysisSettings::MIN_DIAMETER_PX as i64..=AnalysisSettings::MAX_RESOLUTION_PX as i64)))]
    pub profile_min_diameter: Option<u32>,
    /// MSAA samples of the analysis and of the rendered frames (1: none)
    /// [default: the scene's `[profiles]`, else 4].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(1..=16)))]
    pub msaa: Option<u32>,
    /// View-sphere level of profiles that must be made (0: 6 viewpoints,
    /// 1: 18, 2: 66) [default: the scene's `[profiles]`, else 1].
    #[cfg_attr(feature = "clap", arg(long, value_parser = clap::value_parser!(u32).range(0..=AnalysisSettings::MAX_VIEWPOINT_LEVEL as i64)))]
    pub profile_viewpoints: Option<u32>,
    /// Feature-size statistic of profiles that must be made: `mean` (a
    /// feature's extent averaged over orientations), `longest`,
    /// `thickness` (inscribed-disc diameter: its width) or `shortest`
    /// [default: the scene's `[profiles]`, else mean].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_statistic))]
    pub profile_statistic: Option<acuity_preprocess::FrequencyStatistic>,
    /// Just-noticeable colour difference (ΔE*uv, > 0) of profiles that
    /// must be made [default: the scene's `[profiles]`, else 2.3].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_threshold))]
    pub profile_threshold: Option<f32>,
    /// A pixel counts as changed where two LODs differ by more than this
    /// (ΔE*uv, >= 0), for profiles that must be made [default: the
    /// scene's `[profiles]`, else 1].
    #[cfg_attr(feature = "clap", arg(long, value_parser = crate::parse::parse_min_change))]
    pub profile_min_change: Option<f32>,
    /// Print no progress bar or progress lines on stderr (warnings and
    /// errors still print).
    #[cfg_attr(feature = "clap", arg(long))]
    pub quiet: bool,
}

impl ProfileArgs {
    /// The settings these flags give (unset flags give `None`).
    pub fn spec(&self) -> ProfileSpec {
        ProfileSpec {
            resolution_px: self.profile_resolution,
            min_diameter_px: self.profile_min_diameter,
            msaa_samples: self.msaa,
            viewpoint_level: self.profile_viewpoints,
            statistic: self.profile_statistic,
            threshold_delta_e: self.profile_threshold,
            min_change_delta_e: self.profile_min_change,
        }
    }

    /// The [`LoadOptions`] for a scene whose `[profiles]` are `scene`: each
    /// flag given overrides the scene's key.
    pub fn load_options(&self, scene: &ProfileSpec) -> LoadOptions {
        LoadOptions {
            cache_dir: self.cache_dir.clone(),
            verbose: !self.quiet,
            settings: scene.overridden_by(self.spec()).analysis_settings(),
        }
    }
}

/// A loaded scene, ready to play.
pub struct World {
    /// The scene.
    pub scene: Scene,
    /// The shared renderer (every LOD mesh uploaded once).
    pub renderer: Renderer,
    /// The objects, in scene order.
    pub objects: Vec<WorldObject>,
    /// Every instance, objects in scene order and copies in index order.
    pub instances: Vec<Instance>,
    /// The display selection runs over (for a headset, both eyes').
    pub display: Display,
    /// The radius margin selection needs ([`acuity::SelectorSettings::radius_margin`]):
    /// for a headset, the eyes' offset from the head; else 0.
    pub radius_margin: f32,
    /// The display frames are rendered for (for a headset, the left eye).
    pub eye_display: Display,
    /// Seconds spent making or loading profiles.
    pub profile_time_s: f64,
}

fn instances_of(scene: &Scene, objects: &[WorldObject]) -> Vec<Instance> {
    let mut instances = Vec::with_capacity(scene.instance_count());
    for (object, (spec, o)) in scene.objects.iter().zip(objects).enumerate() {
        for (copy, placement) in spec.placements().into_iter().enumerate() {
            instances.push(Instance {
                object,
                copy,
                placement,
                center_m: placement.transform_point(o.center_mesh),
                radius_m: f64::from(o.profile.bounding_radius) * placement.scale,
            });
        }
    }
    instances
}

/// Checks the scene's triangles at full detail ([`check_scene_triangles`])
/// given the LOD 0 triangles of its first objects.
fn check_full_detail(scene: &Scene, lod0_triangles: &[u32]) -> anyhow::Result<()> {
    let counts = scene
        .objects
        .iter()
        .zip(lod0_triangles)
        .map(|(o, &t)| (o.name.as_str(), u64::from(t), o.placement.count() as u64));
    check_scene_triangles(counts).map_err(|(_, reason)| {
        crate::error::input_error(format!("{}: {reason}", scene.source_path.display()))
    })
}

/// The colour of LOD `lod` in a palette of [`World::render_coloured`]:
/// its entry, the last one for a LOD past the end, `None` for an empty
/// palette.
pub fn lod_colour(palette: &[[f32; 3]], lod: usize) -> Option<[f32; 3]> {
    palette.get(lod).or(palette.last()).copied()
}

/// The camera and gaze of one frame.
#[derive(Debug, Clone, Copy)]
pub struct FrameView {
    /// Frame index.
    pub index: u32,
    /// Simulated time, seconds.
    pub t_s: f64,
    /// Eye position, world metres.
    pub eye_m: DVec3,
    /// Camera orientation, camera-to-world.
    pub orientation: DQuat,
    /// Gaze direction in camera space (unit, -Z is the display centre),
    /// as the selector models it.
    pub gaze_camera: DVec3,
    /// Where the viewer's eyes actually point, camera space (unit): the
    /// error metrics' fixation; `gaze_camera` unless the scene says
    /// otherwise ([`crate::gaze::GazeSpec::viewer`]).
    pub fixation_camera: DVec3,
}

impl World {
    /// Loads a scene's LOD chains, uploads them to a new renderer and gets
    /// every profile (cached under `options.cache_dir`). Errors name the
    /// object at fault.
    pub fn load(scene: Scene, options: &LoadOptions) -> anyhow::Result<World> {
        // Frames are drawn as the profiles were analysed (anti-aliasing).
        let renderer = Renderer::new(&RendererOptions {
            msaa_samples: options.settings.msaa_samples,
        })
        .context("starting the renderer")?;
        Self::load_with(scene, renderer, options)
    }

    /// As [`World::load`], with a renderer the caller made.
    pub fn load_with(
        scene: Scene,
        renderer: Renderer,
        options: &LoadOptions,
    ) -> anyhow::Result<World> {
        let cache_dir = options.cache_dir.clone().unwrap_or_else(|| {
            scene
                .source_path
                .parent()
                .unwrap_or(Path::new("."))
                .join(".acuity-cache")
        });
        let displays = scene
            .display
            .eye_display()
            .and_then(|eye| Ok((eye, scene.display.selection_display()?)))
            .with_context(|| format!("{}: display", scene.source_path.display()))?;
        let (eye_display, (display, radius_margin)) = displays;
        let sources = scene
            .objects
            .iter()
            .map(|o| object_source(&o.name, &o.source))
            .collect::<Vec<_>>();
        check_distinct_cache_paths(&cache_dir, &sources).map_err(crate::error::input_error)?;
        crate::limits::check_generated_meshes(&sources).map_err(crate::error::input_error)?;
        let started = Instant::now();
        // Every object's LODs first, so the scene's size at full detail is
        // checked before anything is analysed.
        let mut uploaded = Vec::with_capacity(scene.objects.len());
        let mut full_detail = Vec::with_capacity(scene.objects.len());
        for (spec, source) in scene.objects.iter().zip(&sources) {
            let what = || format!("object `{}`", spec.name);
            let (lods, warnings) = source
                .load_lods()
                .with_context(|| format!("{}: loading its LODs", what()))?;
            if options.verbose {
                for w in warnings {
                    eprintln!("warning: object `{}`: {w}", spec.name);
                }
            }
            let lod_triangles: Vec<u32> = lods.iter().map(|m| m.triangle_count() as u32).collect();
            full_detail.push(lod_triangles[0]);
            check_full_detail(&scene, &full_detail)?;
            let meshes = lods
                .iter()
                .map(|m| renderer.upload_mesh(m))
                .collect::<Result<Vec<_>, _>>()
                .with_context(|| format!("{}: uploading its LODs", what()))?;
            let (c, _) = lods[0].bounding_sphere();
            uploaded.push((meshes, lod_triangles, c));
        }
        let mut objects = Vec::with_capacity(scene.objects.len());
        // Objects with the same inputs and settings (the same mesh under two
        // names) share one analysis.
        let mut analysed: Vec<(Vec<String>, Profile)> = Vec::new();
        for ((spec, source), (meshes, lod_triangles, c)) in
            scene.objects.iter().zip(&sources).zip(uploaded)
        {
            let what = || format!("object `{}`: making its profile", spec.name);
            let key = input_key(source, &options.settings).with_context(what)?;
            let (profile, cache) = if let Some(path) = &spec.profile {
                let profile = given_profile(source, path)
                    .with_context(|| format!("object `{}`: its profile", spec.name))?;
                (profile, CacheOutcome::Given)
            } else if let Some((_, p)) = analysed.iter().find(|(k, _)| *k == key) {
                (p.clone(), CacheOutcome::Shared)
            } else {
                ensure_profile(
                    &renderer,
                    source,
                    &key,
                    &options.settings,
                    &cache_dir,
                    &RunOptions::default(),
                )
                .with_context(what)?
            };
            if profile.lod_triangles != lod_triangles {
                return Err(crate::error::input_error(format!(
                    "object `{}`: its profile is of LODs of {:?} triangles, its LODs have {lod_triangles:?}",
                    spec.name, profile.lod_triangles
                )));
            }
            if cache != CacheOutcome::Given {
                analysed.push((key, profile.clone()));
            }
            if options.verbose {
                eprintln!(
                    "object `{}`: {} LOD{}, profile {}",
                    spec.name,
                    profile.lod_count(),
                    if profile.lod_count() == 1 { "" } else { "s" },
                    match cache {
                        CacheOutcome::Cached => "cached",
                        CacheOutcome::Analysed => "analysed",
                        CacheOutcome::Given => "given by the scene",
                        CacheOutcome::Shared => "shared with an object of the same inputs",
                    }
                );
            }
            objects.push(WorldObject {
                name: spec.name.clone(),
                meshes,
                lod_triangles,
                profile,
                cache,
                center_mesh: DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64),
            });
        }
        let instances = instances_of(&scene, &objects);
        Ok(World {
            scene,
            renderer,
            objects,
            instances,
            display,
            radius_margin,
            eye_display,
            profile_time_s: started.elapsed().as_secs_f64(),
        })
    }

    /// Moves every object to the placements of `scene`, which must have the
    /// same objects (names and LOD sources) as the loaded one: new copy
    /// counts and seeds without loading or analysing anything again.
    pub fn replace_placements(&mut self, scene: Scene) -> anyhow::Result<()> {
        let same = scene.objects.len() == self.scene.objects.len()
            && scene
                .objects
                .iter()
                .zip(&self.scene.objects)
                .all(|(a, b)| a.name == b.name && a.source == b.source);
        if !same {
            anyhow::bail!("replace_placements: the scene's objects differ from the loaded ones");
        }
        let full_detail: Vec<u32> = self.objects.iter().map(|o| o.lod_triangles[0]).collect();
        check_full_detail(&scene, &full_detail)?;
        self.instances = instances_of(&scene, &self.objects);
        self.scene = scene;
        Ok(())
    }

    /// The instance the gaze tracks, if the scene's gaze tracks one.
    pub fn tracked_instance(&self) -> Option<usize> {
        use crate::gaze::GazeMode;
        let GazeMode::Track { object, copy } = &self.scene.gaze.mode else {
            return None;
        };
        let o = self.objects.iter().position(|o| &o.name == object)?;
        self.instances
            .iter()
            .position(|i| i.object == o && i.copy == *copy as usize)
    }

    /// The runtime's tracker for the scene's gaze: its margin, deg.
    pub fn tracker(&self) -> Tracker {
        use crate::gaze::Tracker as T;
        let g = &self.scene.gaze;
        match g.tracker {
            T::None => Tracker::None,
            T::Head => Tracker::Head,
            T::Eye => Tracker::Eye {
                error_deg: g.tracker_error_deg as f32,
            },
        }
    }

    /// Camera and gaze at simulated time `t_s` (frame `index`): `gaze` as
    /// the selector models it, `viewer` where the eyes actually are.
    pub fn view_at(
        &self,
        index: u32,
        t_s: f64,
        gaze: &crate::gaze::Gaze,
        viewer: &crate::gaze::Gaze,
    ) -> FrameView {
        let (eye_m, orientation) = self.scene.camera.sample(t_s);
        FrameView {
            index,
            t_s,
            eye_m,
            orientation,
            gaze_camera: gaze.sample(t_s),
            fixation_camera: viewer.sample(t_s),
        }
    }

    /// The runtime camera of a view.
    pub fn camera(view: &FrameView) -> Camera {
        Camera {
            position: view.eye_m,
            orientation: view.orientation.as_quat(),
        }
    }

    /// The runtime gaze of a view (pursuing `pursued`, if any).
    pub fn gaze(&self, view: &FrameView, pursued: Option<acuity::ObjectId>) -> Gaze {
        Gaze {
            direction_camera: view.gaze_camera.as_vec3(),
            tracker: self.tracker(),
            pursued,
        }
    }

    /// World to clip (wgpu conventions) for a camera at the origin with the
    /// view's orientation: the display's field of view (its edges, so an
    /// asymmetric eye's too) maps to the image, with an infinite far plane
    /// ([`acuity::display::projection_columns`]; separate x and y scales,
    /// so non-square pixels keep the display's field of view).
    pub fn view_proj(&self, view: &FrameView) -> Mat4 {
        let columns = projection_columns(self.scene.display.fov_edges_deg, f64::from(NEAR_PLANE_M));
        let proj = Mat4::from_cols_array_2d(&columns.map(|c| c.map(|x| x as f32)));
        let view_rot = Mat4::from_quat(view.orientation.inverse().as_quat());
        proj * view_rot
    }

    /// Where the rendered eye is for a view: the camera, or for a headset
    /// the left eye beside it.
    pub fn rendered_eye_m(&self, view: &FrameView) -> DVec3 {
        view.eye_m + view.orientation * self.scene.display.rendered_eye_offset_m()
    }

    /// Renders a view with `lods[i]` the LOD of instance `i` (`None`: not
    /// drawn). Waits for the GPU. Instances of one (mesh, LOD) are drawn
    /// with one instanced draw call.
    pub fn render(&self, view: &FrameView, lods: &[Option<usize>]) -> anyhow::Result<RenderOutput> {
        self.render_faded(view, lods, &[])
    }

    /// As [`World::render`], with instance `i` mid cross-fade when
    /// `fades[i]` is set: its LOD `lods[i]` and the one fading out are both
    /// drawn, with complementary dither masks ([`DitherMask`]). `fades` is
    /// empty (no fades) or has one entry per instance.
    pub fn render_faded(
        &self,
        view: &FrameView,
        lods: &[Option<usize>],
        fades: &[Option<FadeOut>],
    ) -> anyhow::Result<RenderOutput> {
        self.render_coloured(view, lods, fades, &[])
    }

    /// As [`World::render_faded`], with every drawn mesh coloured by its
    /// LOD's entry in `palette` (linear RGB replacing the mesh's own
    /// colours, lit as usual: [`RenderRequest::albedo`]; finest LOD first, a
    /// LOD past the end takes the last entry), both halves of a cross-fade
    /// by their own LOD. An empty palette keeps every mesh's colours.
    pub fn render_coloured(
        &self,
        view: &FrameView,
        lods: &[Option<usize>],
        fades: &[Option<FadeOut>],
        palette: &[[f32; 3]],
    ) -> anyhow::Result<RenderOutput> {
        let mut draws: Vec<(MeshId, Mat4)> = Vec::with_capacity(lods.len());
        let mut dither: Vec<DitherMask> = Vec::new();
        let mut albedo: Vec<[f32; 3]> = Vec::new();
        let colour_of = |lod: usize| lod_colour(palette, lod);
        let eye_m = self.rendered_eye_m(view);
        for (i, (inst, lod)) in self.instances.iter().zip(lods).enumerate() {
            let Some(lod) = *lod else { continue };
            let o = &self.objects[inst.object];
            let mesh_of = |lod: usize| {
                o.meshes
                    .get(lod)
                    .copied()
                    .with_context(|| format!("object `{}` has no LOD {lod}", o.name))
            };
            let mesh = mesh_of(lod)?;
            let p = &inst.placement;
            let m = DMat4::from_scale_rotation_translation(
                DVec3::splat(p.scale),
                p.rotation,
                p.position_m - eye_m,
            )
            .as_mat4();
            match fades.get(i).copied().flatten() {
                Some(fade) => {
                    dither.resize(draws.len(), DitherMask::ALL);
                    draws.push((mesh, m));
                    dither.push(DitherMask::fading_in(fade.fraction));
                    albedo.extend(colour_of(lod));
                    draws.push((mesh_of(fade.from_lod)?, m));
                    dither.push(DitherMask::fading_out(fade.fraction));
                    albedo.extend(colour_of(fade.from_lod));
                }
                None => {
                    draws.push((mesh, m));
                    albedo.extend(colour_of(lod));
                }
            }
        }
        if !dither.is_empty() {
            dither.resize(draws.len(), DitherMask::ALL);
        }
        let [width, height] = self.scene.display.resolution_px;
        let out = self.renderer.render(&RenderRequest {
            width,
            height,
            view_proj: self.view_proj(view),
            instances: &draws,
            dither: &dither,
            albedo: &albedo,
            lighting: Lighting::default(),
            background_srgb: BACKGROUND_SRGB,
        })?;
        Ok(out)
    }

    /// Pixels per degree of the rendered frames, for FLIP.
    pub fn pixels_per_degree(&self) -> f32 {
        self.eye_display.pixels_per_degree()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lods_past_the_palette_take_its_last_colour() {
        let palette = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]];
        assert_eq!(lod_colour(&palette, 0), Some([0.0, 1.0, 0.0]));
        assert_eq!(lod_colour(&palette, 1), Some([1.0, 0.0, 0.0]));
        assert_eq!(lod_colour(&palette, 5), Some([1.0, 0.0, 0.0]));
        assert_eq!(lod_colour(&[], 0), None);
    }
}

//! Validation of `[[objects]]`: each object's one mesh source, its LOD
//! triangle targets, its transform or seeded copies, and the scene's
//! triangles at full detail.

use acuity_preprocess::lods;
use glam::DVec3;

use super::context::{Ctx, Res};
use super::raw::RawObject;
use super::{MAX_COPIES, MeshSource, ObjectSpec};
use crate::limits;
use crate::placement::{Copies, PlacementSpec, Transform};

impl Ctx<'_> {
    pub(super) fn object(&self, i: usize, o: RawObject) -> Res<ObjectSpec> {
        let at = |f: &str| format!("objects[{i}].{f}");
        if o.name.trim().is_empty() {
            return Err(self.invalid(at("name"), "must not be empty"));
        }
        let given = [o.lods.is_some(), o.mesh.is_some(), o.procedural.is_some()];
        let source = match (o.lods, o.mesh, o.procedural) {
            _ if given.iter().filter(|&&g| g).count() > 1 => {
                return Err(self.invalid(
                    at("name"),
                    "give exactly one mesh source: lods, mesh + generate_triangles, or procedural",
                ));
            }
            (Some(lods), None, None) => {
                if o.generate_triangles.is_some() {
                    return Err(self.invalid(at("generate_triangles"), "only valid with `mesh`"));
                }
                if let Err(message) = lods::check_lod_count(lods.len()) {
                    return Err(self.invalid(at("lods"), message));
                }
                for (k, l) in lods.iter().enumerate() {
                    if l.trim().is_empty() {
                        return Err(self.invalid(at(&format!("lods[{k}]")), "empty path"));
                    }
                }
                MeshSource::Lods(lods.iter().map(|l| self.resolve(l)).collect())
            }
            (None, Some(mesh), None) => {
                if mesh.trim().is_empty() {
                    return Err(self.invalid(at("mesh"), "empty path"));
                }
                match o.generate_triangles {
                    None => MeshSource::Whole {
                        mesh: self.resolve(&mesh),
                    },
                    Some(triangles) => {
                        self.triangles(&at("generate_triangles"), &triangles)?;
                        MeshSource::Generated {
                            mesh: self.resolve(&mesh),
                            triangles,
                        }
                    }
                }
            }
            (None, None, Some(p)) => {
                if o.generate_triangles.is_some() {
                    return Err(self.invalid(at("generate_triangles"), "only valid with `mesh`"));
                }
                self.triangles(&at("procedural.triangles"), &p.triangles)?;
                if p.triangles[0] > limits::MAX_PROCEDURAL_TRIANGLES {
                    return Err(self.invalid(
                        at("procedural.triangles[0]"),
                        format!(
                            "{} triangles is more than {} (a procedural LOD's limit)",
                            p.triangles[0],
                            limits::MAX_PROCEDURAL_TRIANGLES
                        ),
                    ));
                }
                MeshSource::Procedural {
                    kind: p.kind,
                    triangles: p.triangles,
                }
            }
            _ => {
                return Err(self.invalid(
                    at("name"),
                    "missing mesh source: give lods, mesh + generate_triangles, or procedural",
                ));
            }
        };
        let placement = match (o.transform, o.copies) {
            (Some(_), Some(_)) => {
                return Err(self.invalid(at("copies"), "give either transform or copies, not both"));
            }
            (Some(t), None) => {
                if !(t.scale > 0.0) {
                    return Err(
                        self.invalid(at("transform.scale"), format!("{} must be > 0", t.scale))
                    );
                }
                PlacementSpec::Transform(Transform {
                    position_m: DVec3::from_array(t.position.0),
                    rotation_deg: t.rotation_deg.0,
                    scale: t.scale,
                })
            }
            (None, Some(c)) => {
                if c.count == 0 || c.count > MAX_COPIES {
                    return Err(self.invalid(
                        at("copies.count"),
                        format!("{} is outside 1..={MAX_COPIES}", c.count),
                    ));
                }
                let (volume_min, volume_max) = (c.volume_min.0, c.volume_max.0);
                for k in 0..3 {
                    if volume_min[k] > volume_max[k] {
                        return Err(self.invalid(
                            at(&format!("copies.volume_max[{k}]")),
                            format!(
                                "{} is below volume_min[{k}] = {}",
                                volume_max[k], volume_min[k]
                            ),
                        ));
                    }
                }
                if !(c.scale > 0.0) {
                    return Err(
                        self.invalid(at("copies.scale"), format!("{} must be > 0", c.scale))
                    );
                }
                PlacementSpec::Copies(Copies {
                    count: c.count,
                    seed: c.seed,
                    volume_min_m: DVec3::from_array(volume_min),
                    volume_max_m: DVec3::from_array(volume_max),
                    random_rotation: c.random_rotation,
                    scale: c.scale,
                })
            }
            (None, None) => PlacementSpec::Transform(Transform {
                position_m: DVec3::ZERO,
                rotation_deg: [0.0; 3],
                scale: 1.0,
            }),
        };
        let profile = match o.profile {
            Some(p) if p.trim().is_empty() => return Err(self.invalid(at("profile"), "empty path")),
            Some(p) => Some(self.resolve(&p)),
            None => None,
        };
        let screen_size_bias = o.screen_size_bias.unwrap_or(1.0);
        limits::check_object_bias(screen_size_bias)
            .map_err(|message| self.invalid(at("screen_size_bias"), message))?;
        Ok(ObjectSpec {
            name: o.name,
            source,
            profile,
            placement,
            screen_size_bias,
        })
    }

    /// The full-detail triangles of the procedural objects (the others'
    /// are known once their meshes are loaded) against
    /// [`limits::MAX_SCENE_TRIANGLES`].
    pub(super) fn scene_triangles(&self, objects: &[ObjectSpec]) -> Res<()> {
        let counts = objects.iter().map(|o| {
            let triangles = match &o.source {
                MeshSource::Procedural { triangles, .. } => u64::from(triangles[0]),
                _ => 0,
            };
            (o.name.as_str(), triangles, o.placement.count() as u64)
        });
        limits::check_scene_triangles(counts).map_err(|(i, reason)| {
            let field = match objects[i].placement {
                PlacementSpec::Copies(_) => format!("objects[{i}].copies.count"),
                PlacementSpec::Transform(_) => format!("objects[{i}].procedural.triangles[0]"),
            };
            self.invalid(field, reason)
        })
    }

    fn triangles(&self, field: &str, triangles: &[u32]) -> Res<()> {
        lods::check_targets(triangles).map_err(|e| match e.index {
            Some(k) => self.invalid(format!("{field}[{k}]"), e.message),
            None => self.invalid(field, e.message),
        })
    }
}

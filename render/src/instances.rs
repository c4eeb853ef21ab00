//! A frame's per-instance data: the checks of a request's per-instance
//! slices, and the instances grouped per mesh (in order of first
//! appearance, one instanced draw call each) and packed as the bytes of
//! the instance vertex buffer the shader reads. The packer keeps its
//! buffers from frame to frame, so packing allocates nothing once they
//! have grown to the scene's size.

use std::ops::Range;

use glam::{Mat3, Mat4};

use crate::{DitherMask, Error, MeshId, RenderRequest};

/// Bytes per instance: the model matrix (mat4), the normal matrix as 3 ×
/// vec4, the dither range (vec2) and the albedo (vec4: rgb, and 1 in w
/// when set), all `f32`.
pub(crate) const INSTANCE_STRIDE: u64 = 136;

/// The albedo of an instance without one: weight 0, so the mesh keeps its
/// own colours.
const OWN_COLOURS: [f32; 4] = [0.0; 4];

/// Instances packed for one frame, and the scratch that groups them.
#[derive(Default)]
pub(crate) struct Packer {
    /// The instance buffer's bytes, [`INSTANCE_STRIDE`] per instance.
    pub bytes: Vec<u8>,
    /// Each mesh's instances in `bytes`, as instance indices.
    pub ranges: Vec<(MeshId, Range<u32>)>,
    /// Per mesh id: 1 + its index in `ranges` this frame (0: not drawn);
    /// all 0 between frames.
    group_of_mesh: Vec<u32>,
    /// The request's instance indices, grouped in the order of `ranges`.
    order: Vec<u32>,
}

/// Checks that every instance's mesh is `known` and that `dither` and
/// `albedo` are each empty or one per instance.
pub(crate) fn check(req: &RenderRequest<'_>, known: impl Fn(MeshId) -> bool) -> Result<(), Error> {
    if let Some((bad, _)) = req.instances.iter().find(|(id, _)| !known(*id)) {
        return Err(Error::Settings {
            field: "instances",
            message: format!("unknown mesh id {}", bad.0),
        });
    }
    let n = req.instances.len();
    for (field, len, what) in [
        ("dither", req.dither.len(), "masks"),
        ("albedo", req.albedo.len(), "colours"),
    ] {
        if len != 0 && len != n {
            return Err(Error::Settings {
                field,
                message: format!("{len} {what} for {n} instances (give none or one each)"),
            });
        }
    }
    Ok(())
}

impl Packer {
    /// Groups `req`'s instances per mesh and packs them into
    /// [`bytes`](Self::bytes) and [`ranges`](Self::ranges); returns the
    /// triangles submitted (instances × triangles of their mesh).
    /// `index_count` gives a mesh's index count (0 for a freed one). The
    /// slices must have passed [`check`].
    pub(crate) fn pack(
        &mut self,
        req: &RenderRequest<'_>,
        index_count: impl Fn(MeshId) -> u32,
    ) -> u64 {
        self.ranges.clear();
        // Count each mesh's instances, numbering meshes as they appear.
        for (id, _) in req.instances {
            let m = id.0 as usize;
            if m >= self.group_of_mesh.len() {
                self.group_of_mesh.resize(m + 1, 0);
            }
            if self.group_of_mesh[m] == 0 {
                self.ranges.push((*id, 0..0));
                self.group_of_mesh[m] = self.ranges.len() as u32;
            }
            self.ranges[self.group_of_mesh[m] as usize - 1].1.end += 1;
        }
        // Counts to ranges, then each instance to the next place of its
        // mesh's range (`end` as the cursor, back at the range's end after).
        let mut start = 0;
        for (_, r) in &mut self.ranges {
            let count = r.end;
            *r = start..start;
            start += count;
        }
        self.order.clear();
        self.order.resize(req.instances.len(), 0);
        for (k, (id, _)) in req.instances.iter().enumerate() {
            let r = &mut self.ranges[self.group_of_mesh[id.0 as usize] as usize - 1].1;
            self.order[r.end as usize] = k as u32;
            r.end += 1;
        }
        self.bytes.clear();
        self.bytes
            .reserve(req.instances.len() * INSTANCE_STRIDE as usize);
        let mut triangles = 0u64;
        for (id, r) in &self.ranges {
            for &k in &self.order[r.start as usize..r.end as usize] {
                let k = k as usize;
                let mask = req.dither.get(k).copied().unwrap_or(DitherMask::ALL);
                let albedo = req
                    .albedo
                    .get(k)
                    .map_or(OWN_COLOURS, |&[red, green, blue]| [red, green, blue, 1.0]);
                push_instance(&mut self.bytes, &req.instances[k].1, mask, albedo);
            }
            triangles += u64::from(index_count(*id) / 3) * u64::from(r.end - r.start);
            self.group_of_mesh[id.0 as usize] = 0;
        }
        triangles
    }
}

/// Appends one instance's [`INSTANCE_STRIDE`] bytes.
fn push_instance(bytes: &mut Vec<u8>, m: &Mat4, mask: DitherMask, albedo: [f32; 4]) {
    // The normal matrix; a singular model matrix keeps its own 3x3.
    let n = Mat3::from_mat4(*m).inverse().transpose();
    let n = if n.is_finite() {
        n
    } else {
        Mat3::from_mat4(*m)
    };
    let normal = [n.x_axis, n.y_axis, n.z_axis]
        .into_iter()
        .flat_map(|c| [c.x, c.y, c.z, 0.0]);
    let floats = m
        .to_cols_array()
        .into_iter()
        .chain(normal)
        .chain([mask.keep_from, mask.keep_below])
        .chain(albedo);
    for f in floats {
        bytes.extend_from_slice(&f.to_le_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Lighting;

    fn request<'a>(
        instances: &'a [(MeshId, Mat4)],
        dither: &'a [DitherMask],
        albedo: &'a [[f32; 3]],
    ) -> RenderRequest<'a> {
        RenderRequest {
            width: 1,
            height: 1,
            view_proj: Mat4::IDENTITY,
            instances,
            dither,
            albedo,
            lighting: Lighting::default(),
            background_srgb: [0; 3],
        }
    }

    fn floats(bytes: &[u8]) -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    }

    #[test]
    fn instances_group_per_mesh_in_order_of_first_appearance() {
        let (a, b) = (MeshId(3), MeshId(1));
        let t = |x: f32| Mat4::from_translation(glam::Vec3::new(x, 0.0, 0.0));
        let inst = [(a, t(1.0)), (b, t(2.0)), (a, t(3.0))];
        let albedo = [[0.1, 0.2, 0.3], [1.0; 3], [0.4, 0.5, 0.6]];
        let mut p = Packer::default();
        let triangles = p.pack(
            &request(&inst, &[], &albedo),
            |id| if id == a { 30 } else { 6 },
        );
        assert_eq!(p.ranges, vec![(a, 0..2), (b, 2..3)]);
        assert_eq!(triangles, 10 + 10 + 2);
        assert_eq!(p.bytes.len(), 3 * INSTANCE_STRIDE as usize);
        let f = floats(&p.bytes);
        let per = INSTANCE_STRIDE as usize / 4;
        // The second of mesh `a` is the third instance: x = 3, its albedo.
        let second = &f[per..2 * per];
        assert_eq!(second[12], 3.0);
        assert_eq!(second[28..30], [0.0, 1.0]);
        assert_eq!(second[30..34], [0.4, 0.5, 0.6, 1.0]);
        // The next frame reuses the packer: only its own meshes, in its
        // own order of first appearance.
        let inst = [(b, t(4.0)), (b, t(5.0))];
        assert_eq!(p.pack(&request(&inst, &[], &[]), |_| 6), 4);
        assert_eq!(p.ranges, vec![(b, 0..2)]);
        assert_eq!(p.bytes.len(), 2 * INSTANCE_STRIDE as usize);
        assert_eq!(floats(&p.bytes)[per + 12], 5.0);
        assert!(p.group_of_mesh.iter().all(|&g| g == 0));
    }

    #[test]
    fn a_missing_albedo_keeps_the_mesh_colours_and_a_missing_mask_keeps_all() {
        let inst = [(MeshId(0), Mat4::from_scale(glam::Vec3::splat(2.0)))];
        let mut p = Packer::default();
        p.pack(&request(&inst, &[], &[]), |_| 3);
        let f = floats(&p.bytes);
        assert_eq!(f[28..34], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]);
        // The normal matrix of a uniform scale by 2 is a scale by 1/2.
        assert_eq!([f[16], f[21], f[26]], [0.5; 3]);
    }

    #[test]
    fn slices_are_empty_or_one_per_instance() {
        let inst = [(MeshId(0), Mat4::IDENTITY); 2];
        let known = |id: MeshId| id.0 == 0;
        assert!(check(&request(&inst, &[], &[]), known).is_ok());
        let all = request(&inst, &[DitherMask::ALL; 2], &[[1.0; 3]; 2]);
        assert!(check(&all, known).is_ok());
        let e = check(&request(&inst, &[], &[[1.0; 3]]), known).unwrap_err();
        assert!(e.to_string().contains("albedo"), "{e}");
        let e = check(&request(&inst, &[DitherMask::ALL; 3], &[]), known).unwrap_err();
        assert!(e.to_string().contains("dither"), "{e}");
        let e = check(&request(&[(MeshId(7), Mat4::IDENTITY)], &[], &[]), known).unwrap_err();
        assert!(e.to_string().contains("unknown mesh id 7"), "{e}");
    }
}

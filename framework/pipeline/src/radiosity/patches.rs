//! The patch mesh: a scene's triangles, paired back into the quads they came from, subdivided
//! until no patch edge is longer than a maximum size (light sources with their own size), with
//! the vertices shared between neighbouring patches of one surface so that colours can be
//! averaged at them (nodal averaging, Exercise 6.8).

use std::collections::HashMap;

use glam::Vec3;

use contracts::lab06::Patch;
use raylab_core::accel::TriangleBvh;
use raylab_core::math::Ray;
use raylab_core::scene::Scene;

/// How finely to mesh a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshingOptions {
    /// Longest patch edge on ordinary surfaces, in scene units.
    pub max_size: f32,
    /// Longest patch edge on light sources (emissive surfaces).
    pub max_light_size: f32,
}

/// Where a ray meets the patch mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchHit {
    /// The patch hit.
    pub patch: u32,
    /// Ray parameter of the hit.
    pub t: f32,
    /// The corners (indices into [`PatchMesh::vertices`]) of the triangle of the patch hit.
    pub corners: [u32; 3],
    /// Barycentric weights of the hit point for those corners.
    pub weights: Vec3,
}

/// A scene meshed into patches, with a BVH over the patches' triangles for ray casting.
#[derive(Clone, Debug)]
pub struct PatchMesh {
    /// The patches' corners; a corner shared by patches of one surface is one vertex.
    pub vertices: Vec<Vec3>,
    /// The patches.
    pub patches: Vec<Patch>,
    triangles: Vec<(u32, [u32; 3])>,
    bvh: TriangleBvh,
}

impl PatchMesh {
    /// Meshes `scene`'s triangles (planes and spheres are not meshed): consecutive coplanar
    /// triangles of one material that share a diagonal are a quad again, and each quad or
    /// triangle is cut into a regular grid of patches no longer than `options` allows.
    pub fn from_scene(scene: &Scene, options: MeshingOptions) -> Self {
        let mesh = &scene.mesh;
        let mut builder = Builder::new(scene_extent(scene));
        let mut f = 0;
        while f < mesh.faces.len() {
            let material = scene.material(mesh.face_materials[f]);
            let size = if material.is_emissive() {
                options.max_light_size
            } else {
                options.max_size
            };
            let normal = mesh.face_normal(f);
            let surface = Surface {
                normal,
                reflectance: material.diffuse,
                emission: std::f32::consts::PI * material.emission,
                material: mesh.face_materials[f].0,
            };
            let [a, b, c] = mesh.faces[f];
            let pair = mesh.faces.get(f + 1).filter(|&&[a2, c2, _]| {
                a2 == a
                    && c2 == c
                    && mesh.face_materials[f + 1] == mesh.face_materials[f]
                    && mesh.face_normal(f + 1).dot(normal) > 0.9999
            });
            let p = |i: u32| mesh.positions[i as usize];
            if let Some(&[_, _, d]) = pair {
                builder.quad([p(a), p(b), p(c), p(d)], size, &surface);
                f += 2;
            } else {
                builder.triangle([p(a), p(b), p(c)], size, &surface);
                f += 1;
            }
        }
        builder.finish()
    }

    /// Builds a mesh from patches given directly (their corners index `vertices`).
    pub fn from_patches(vertices: Vec<Vec3>, patches: Vec<Patch>) -> Self {
        let mut triangles = Vec::new();
        for (i, patch) in patches.iter().enumerate() {
            let v = &patch.vertices;
            for k in 1..v.len() - 1 {
                triangles.push((i as u32, [v[0], v[k], v[k + 1]]));
            }
        }
        let bvh = TriangleBvh::build(
            &triangles
                .iter()
                .map(|(_, t)| t.map(|i| vertices[i as usize]))
                .collect::<Vec<_>>(),
        );
        Self {
            vertices,
            patches,
            triangles,
            bvh,
        }
    }

    /// The closest patch along `ray` in `[tmin, tmax]`.
    pub fn closest_patch(&self, ray: &Ray) -> Option<PatchHit> {
        self.bvh.closest_hit_watertight(ray).map(|h| {
            let (patch, corners) = self.triangles[h.face as usize];
            PatchHit {
                patch,
                t: h.t,
                corners,
                weights: Vec3::new(1.0 - h.beta - h.gamma, h.beta, h.gamma),
            }
        })
    }

    /// Emitted radiosity of every patch (the start of progressive refinement).
    pub fn emission(&self) -> Vec<Vec3> {
        self.patches.iter().map(|p| p.emission).collect()
    }

    /// Total power `Σ A_i (B_i.r + B_i.g + B_i.b)` of per-patch radiosities `b`.
    pub fn power(&self, b: &[Vec3]) -> f64 {
        self.patches
            .iter()
            .zip(b)
            .map(|(p, b)| p.area as f64 * (b.x as f64 + b.y as f64 + b.z as f64))
            .sum()
    }

    /// The diagonal of the mesh's bounding box (its scale, for ray offsets).
    pub fn extent(&self) -> f32 {
        let (lo, hi) = self.vertices.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(*v), hi.max(*v)),
        );
        (hi - lo).length().max(f32::MIN_POSITIVE)
    }
}

/// The reflectance, emission and orientation shared by the patches cut from one face.
struct Surface {
    normal: Vec3,
    reflectance: Vec3,
    emission: Vec3,
    material: u32,
}

/// Collects patches, sharing a corner between patches of the same material and orientation.
struct Builder {
    vertices: Vec<Vec3>,
    patches: Vec<Patch>,
    index: HashMap<(i64, i64, i64, u32, [i32; 3]), u32>,
    quantum: f32,
}

impl Builder {
    fn new(extent: f32) -> Self {
        Self {
            vertices: Vec::new(),
            patches: Vec::new(),
            index: HashMap::new(),
            quantum: extent.max(f32::MIN_POSITIVE) * 1e-6,
        }
    }

    fn vertex(&mut self, p: Vec3, s: &Surface) -> u32 {
        let q = |x: f32| (x / self.quantum).round() as i64;
        let n = (s.normal * 1000.0).round().as_ivec3().to_array();
        let key = (q(p.x), q(p.y), q(p.z), s.material, n);
        let next = self.vertices.len() as u32;
        let id = *self.index.entry(key).or_insert(next);
        if id == next {
            self.vertices.push(p);
        }
        id
    }

    fn patch(&mut self, corners: &[Vec3], s: &Surface) {
        let (area, centre) = if corners.len() == 4 {
            let [a, b, c, d] = [corners[0], corners[1], corners[2], corners[3]];
            (0.5 * (c - a).cross(d - b).length(), 0.25 * (a + b + c + d))
        } else {
            let [a, b, c] = [corners[0], corners[1], corners[2]];
            (0.5 * (b - a).cross(c - a).length(), (a + b + c) / 3.0)
        };
        if area <= 0.0 {
            return;
        }
        let vertices = corners.iter().map(|&p| self.vertex(p, s)).collect();
        self.patches.push(Patch {
            vertices,
            centre,
            normal: s.normal,
            area,
            reflectance: s.reflectance,
            emission: s.emission,
        });
    }

    /// A quad `p0 p1 p2 p3` as an `n × m` grid of bilinearly placed sub-quads.
    fn quad(&mut self, p: [Vec3; 4], size: f32, s: &Surface) {
        let cuts = |a: f32, b: f32| ((a.max(b) / size).ceil() as usize).max(1);
        let n = cuts((p[1] - p[0]).length(), (p[2] - p[3]).length());
        let m = cuts((p[3] - p[0]).length(), (p[2] - p[1]).length());
        let at = |i: usize, j: usize| {
            let (u, v) = (i as f32 / n as f32, j as f32 / m as f32);
            (1.0 - u) * (1.0 - v) * p[0]
                + u * (1.0 - v) * p[1]
                + u * v * p[2]
                + (1.0 - u) * v * p[3]
        };
        for j in 0..m {
            for i in 0..n {
                self.patch(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)], s);
            }
        }
    }

    /// A triangle as `n²` similar triangles.
    fn triangle(&mut self, [a, b, c]: [Vec3; 3], size: f32, s: &Surface) {
        let longest = (b - a).length().max((c - b).length()).max((a - c).length());
        let n = ((longest / size).ceil() as usize).max(1);
        let at = |i: usize, j: usize| {
            a + (b - a) * (i as f32 / n as f32) + (c - a) * (j as f32 / n as f32)
        };
        for j in 0..n {
            for i in 0..n - j {
                self.patch(&[at(i, j), at(i + 1, j), at(i, j + 1)], s);
                if i + j + 1 < n {
                    self.patch(&[at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)], s);
                }
            }
        }
    }

    fn finish(self) -> PatchMesh {
        PatchMesh::from_patches(self.vertices, self.patches)
    }
}

/// The diagonal of the bounding box of a scene's triangles.
fn scene_extent(scene: &Scene) -> f32 {
    let (lo, hi) = scene.mesh.positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(*v), hi.max(*v)),
    );
    (hi - lo).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab_core::scene::builtin_scene;

    #[test]
    fn cornell_box_is_meshed_into_patches_that_cover_it() {
        let scene = builtin_scene("cornell").unwrap();
        let options = MeshingOptions {
            max_size: 0.1,
            max_light_size: 0.05,
        };
        let mesh = PatchMesh::from_scene(&scene, options);
        let total: f32 = (0..scene.mesh.faces.len())
            .map(|f| {
                let [a, b, c] = scene.mesh.triangle(f);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let patched: f32 = mesh.patches.iter().map(|p| p.area).sum();
        assert!((patched / total - 1.0).abs() < 1e-3, "{patched} vs {total}");
        for p in &mesh.patches {
            for w in p.vertices.windows(2) {
                let edge = mesh.vertices[w[1] as usize] - mesh.vertices[w[0] as usize];
                let limit = if p.emission.max_element() > 0.0 {
                    0.05
                } else {
                    0.1
                };
                assert!(
                    edge.length() <= limit * 1.001,
                    "edge {} > {limit}",
                    edge.length()
                );
            }
        }
        assert!(mesh.patches.iter().any(|p| p.emission.max_element() > 0.0));
        // The floor's interior vertices are shared by four patches.
        let mut uses = vec![0u32; mesh.vertices.len()];
        for p in &mesh.patches {
            for &v in &p.vertices {
                uses[v as usize] += 1;
            }
        }
        assert!(uses.contains(&4));
        assert!(mesh.patches.iter().any(|p| p.vertices.len() == 4));
    }
}

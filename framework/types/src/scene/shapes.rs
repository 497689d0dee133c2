use glam::{Vec2, Vec3};

use super::MaterialId;
use crate::math::Aabb;

/// An infinite plane `p·n + d = 0`, with a tangent frame for texture coordinates (lab 09).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Plane {
    /// Unit normal `n`.
    pub normal: Vec3,
    /// Offset `d`: the plane holds every `p` with `p·n + d = 0`.
    pub d: f32,
    /// First tangent (texture `u` direction) in the plane.
    pub tangent: Vec3,
    /// Second tangent (texture `v` direction), `normal × tangent`.
    pub bitangent: Vec3,
    /// World units per texture repeat.
    pub tex_scale: f32,
    /// Material of the plane.
    pub material: MaterialId,
}

impl Plane {
    /// The plane through `point` with normal `normal` (normalized here).
    pub fn new(point: Vec3, normal: Vec3, material: MaterialId) -> Self {
        let normal = normal.normalize();
        let onb = crate::math::Onb::from_w(normal);
        Self {
            normal,
            d: -point.dot(normal),
            tangent: onb.u,
            bitangent: onb.v,
            tex_scale: 1.0,
            material,
        }
    }
}

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sphere {
    /// Centre `c`.
    pub center: Vec3,
    /// Radius `r > 0`.
    pub radius: f32,
    /// Material of the sphere.
    pub material: MaterialId,
}

impl Sphere {
    /// Bounding box.
    pub fn bounds(&self) -> Aabb {
        Aabb::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }
}

/// A triangle mesh with per-vertex attributes indexed like the positions (tobj's single index).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals: empty, or one per position.
    pub normals: Vec<Vec3>,
    /// Vertex texture coordinates: empty, or one per position.
    pub texcoords: Vec<Vec2>,
    /// Triangles as three vertex indices each.
    pub faces: Vec<[u32; 3]>,
    /// Material of each triangle.
    pub face_materials: Vec<MaterialId>,
}

impl Mesh {
    /// The three corners of face `f`.
    #[inline]
    pub fn triangle(&self, f: usize) -> [Vec3; 3] {
        let [a, b, c] = self.faces[f];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// The unit geometric normal of face `f` (see [`triangle_normal`]).
    #[inline(always)]
    pub fn face_normal(&self, f: usize) -> Vec3 {
        triangle_normal(self.triangle(f))
    }

    /// Appends `other`, renumbering its vertices.
    pub fn append(&mut self, other: &Mesh) {
        let base = self.positions.len() as u32;
        let had_normals = !self.normals.is_empty() || self.positions.is_empty();
        let had_uv = !self.texcoords.is_empty() || self.positions.is_empty();
        // Attributes stay aligned with positions: fill in what either side lacks.
        if !other.normals.is_empty() && !had_normals {
            self.normals = vec![Vec3::ZERO; self.positions.len()];
        }
        if !other.texcoords.is_empty() && !had_uv {
            self.texcoords = vec![Vec2::ZERO; self.positions.len()];
        }
        self.positions.extend_from_slice(&other.positions);
        if !self.normals.is_empty() || !other.normals.is_empty() {
            if other.normals.is_empty() {
                self.normals
                    .extend(std::iter::repeat_n(Vec3::ZERO, other.positions.len()));
            } else {
                self.normals.extend_from_slice(&other.normals);
            }
        }
        if !self.texcoords.is_empty() || !other.texcoords.is_empty() {
            if other.texcoords.is_empty() {
                self.texcoords
                    .extend(std::iter::repeat_n(Vec2::ZERO, other.positions.len()));
            } else {
                self.texcoords.extend_from_slice(&other.texcoords);
            }
        }
        self.faces
            .extend(other.faces.iter().map(|f| f.map(|i| i + base)));
        self.face_materials.extend_from_slice(&other.face_materials);
    }
}

/// The unit normal `(v1 − v0) × (v2 − v0)`, normalized, of the triangle `[v0, v1, v2]`: counter-
/// clockwise vertices seen from the side it points to.
#[inline(always)]
pub fn triangle_normal([v0, v1, v2]: [Vec3; 3]) -> Vec3 {
    (v1 - v0).cross(v2 - v0).normalize()
}

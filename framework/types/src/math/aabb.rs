use glam::Vec3;

/// An axis-aligned bounding box; the empty box has `min = +∞`, `max = −∞`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The box containing nothing; the identity of [`Aabb::union`].
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box spanned by two corners.
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The smallest box containing all `points`.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow(p))
    }

    /// This box grown to contain `p`.
    #[inline]
    pub fn grow(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    /// The smallest box containing both.
    #[inline]
    pub fn union(self, other: Aabb) -> Self {
        Self::new(self.min.min(other.min), self.max.max(other.max))
    }

    /// Whether the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// Extent along each axis.
    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }

    /// Centre point.
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area (0 for an empty box); the cost measure of the surface area heuristic.
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.diagonal();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// Index of the longest axis (0 = x, 1 = y, 2 = z).
    pub fn longest_axis(&self) -> usize {
        let d = self.diagonal();
        if d.x >= d.y && d.x >= d.z {
            0
        } else if d.y >= d.z {
            1
        } else {
            2
        }
    }

    /// Whether `p` lies inside or on the box.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Slab test: the parameter interval `[t0, t1]` over which the ray
    /// `origin + t·dir` (given as `1/dir`) is inside the box, clipped to `[tmin, tmax]`.
    #[inline]
    pub fn intersect(
        &self,
        origin: Vec3,
        inv_dir: Vec3,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, f32)> {
        let t0 = (self.min - origin) * inv_dir;
        let t1 = (self.max - origin) * inv_dir;
        let near = t0.min(t1).max_element().max(tmin);
        let far = t0.max(t1).min_element().min(tmax);
        (near <= far).then_some((near, far))
    }
}

use glam::Vec3;

/// A ray `r(t) = origin + t·direction`, valid for `tmin ≤ t ≤ tmax`.
///
/// `direction` is unit length for every ray the framework creates; intersection routines may
/// rely on it (their `t` is then the Euclidean distance along the ray).
///
/// Laid out like Embree's rays, with the origin and `tmin` in the first 16 bytes and the
/// direction (here with `tmax`) in the next, so that a copy made in two 16-byte moves (a caller's
/// `let mut r = *ray;`) holds each vector within one store, and a query that reads the direction
/// right after the copy is served from that store instead of stalling until it reaches the
/// cache (docs/performance.md).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C, align(16))]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Smallest accepted ray parameter (distance).
    pub tmin: f32,
    /// Unit direction of travel.
    pub direction: Vec3,
    /// Largest accepted ray parameter; closest-hit queries shrink it as they find hits.
    pub tmax: f32,
}

impl Ray {
    /// A ray over `[tmin, tmax]`.
    pub fn new(origin: Vec3, direction: Vec3, tmin: f32, tmax: f32) -> Self {
        Self {
            origin,
            direction,
            tmin,
            tmax,
        }
    }

    /// A ray over `[tmin, ∞)`.
    pub fn unbounded(origin: Vec3, direction: Vec3, tmin: f32) -> Self {
        Self::new(origin, direction, tmin, f32::INFINITY)
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }

    /// Whether the ray can be traced: finite origin and direction, and an interval that is not
    /// NaN. A NaN direction (a student's `normalize` of a zero vector, say) passes every slab
    /// test of a BVH, so a traversal would visit the whole tree and report nonsense; the
    /// scene's queries find nothing along such a ray.
    #[inline]
    pub fn is_traceable(&self) -> bool {
        self.origin.is_finite() && self.direction.is_finite() && self.tmin <= self.tmax
    }

    /// Whether `t` lies in the ray's valid interval.
    #[inline]
    pub fn accepts(&self, t: f32) -> bool {
        t >= self.tmin && t <= self.tmax
    }
}

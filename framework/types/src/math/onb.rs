use glam::Vec3;

/// An orthonormal basis `(u, v, w)` with `w` along a given direction, used to turn local
/// (hemisphere) directions into world directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Onb {
    /// First tangent.
    pub u: Vec3,
    /// Second tangent, `w × u`.
    pub v: Vec3,
    /// The axis the basis was built around.
    pub w: Vec3,
}

impl Onb {
    /// A basis around the unit vector `w`, by the branchless method of Duff et al. (2017),
    /// "Building an Orthonormal Basis, Revisited".
    pub fn from_w(w: Vec3) -> Self {
        let sign = 1.0f32.copysign(w.z);
        let a = -1.0 / (sign + w.z);
        let b = w.x * w.y * a;
        let u = Vec3::new(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x);
        let v = Vec3::new(b, sign + w.y * w.y * a, -w.y);
        Self { u, v, w }
    }

    /// World direction of the local coordinates `(x, y, z)` = `x·u + y·v + z·w`.
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        local.x * self.u + local.y * self.v + local.z * self.w
    }

    /// Local coordinates of a world direction.
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        Vec3::new(world.dot(self.u), world.dot(self.v), world.dot(self.w))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_and_right_handed() {
        for w in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.5, 0.8).normalize(),
        ] {
            let b = Onb::from_w(w);
            assert!((b.u.length() - 1.0).abs() < 1e-5);
            assert!((b.v.length() - 1.0).abs() < 1e-5);
            assert!(b.u.dot(b.v).abs() < 1e-5 && b.u.dot(b.w).abs() < 1e-5);
            assert!((b.u.cross(b.v) - b.w).length() < 1e-5);
            let d = Vec3::new(0.2, 0.4, -0.1);
            assert!((b.to_local(b.to_world(d)) - d).length() < 1e-5);
        }
    }
}

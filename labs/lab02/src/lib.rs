//! # Lab 02 — intersections and Lambertian shading
//!
//! The framework shoots the camera rays (lab 01), keeps the scene in a BVH and asks your code
//! which primitive a ray hits; the closest hit wins because every test shrinks the ray's
//! `tmax` (DTU `RayTracer::trace_to_closest`). Then your shader computes the light reflected
//! towards the eye from point and directional lights — no shadows yet (that is lab 03).
//!
//! Read `docs/lab02.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab02                # all exercises
//! cargo test -p lab02 exercise_2_2   # one exercise
//! raylab render --lab 2 --pipeline student
//! ```
//!
//! Every intersection test must accept only hits with `ray.tmin ≤ t ≤ ray.tmax`
//! (`ray.accepts(t)` does exactly that). Ray directions are unit length.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Your intersection tests and shader. The framework calls them through the `Intersection`
/// and `Shading` traits.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    /// **Exercise 2.1** — ray–plane intersection (docs/lab02.md, §2.1).
    ///
    /// The plane holds the points `p` with `p·n + d = 0` (`plane.normal`, `plane.d`).
    /// Insert the ray `r(t) = o + t·ω` and solve for `t`:
    ///
    /// ```text
    /// t = −(o·n + d) / (ω·n)
    /// ```
    ///
    /// No hit when the ray is parallel to the plane (`ω·n = 0`) or `t` is outside
    /// `[tmin, tmax]`. The normal of the hit is `plane.normal`.
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        todo!("Exercise 2.1: intersect_plane (docs/lab02.md, Exercise 2.1)")
    }

    /// **Exercise 2.2** — ray–triangle intersection with barycentric coordinates
    /// (docs/lab02.md, §2.2).
    ///
    /// Points of the triangle's plane are `v0 + β·e1 + γ·e2` with `e1 = v1 − v0`,
    /// `e2 = v2 − v0`; the point is inside the triangle when `β ≥ 0`, `γ ≥ 0` and
    /// `β + γ ≤ 1`. Setting it equal to `o + t·ω` gives a 3×3 linear system in `(t, β, γ)`;
    /// solve it (Cramer's rule gives Möller–Trumbore, or use the plane and the normal) and
    /// accept the hit only if the point is inside and `t` is in `[tmin, tmax]`.
    ///
    /// Return `t`, `β`, `γ`, and the unit normal `normalize(e1 × e2)`.
    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        todo!("Exercise 2.2: intersect_triangle (docs/lab02.md, Exercise 2.2)")
    }

    /// **Exercise 2.3** — ray–sphere intersection (docs/lab02.md, §2.3).
    ///
    /// Insert the ray into `(p − c)·(p − c) = r²`: with `b/2 = (o − c)·ω` and
    /// `c' = (o − c)·(o − c) − r²` (for a unit `ω`) the roots are
    /// `t = −b/2 ± √((b/2)² − c')`. No hit when the discriminant is negative. Return the
    /// **nearest root inside `[tmin, tmax]`**: the near one, or the far one when the near one
    /// is outside the interval (a ray that starts inside the sphere hits its far side). The
    /// normal is the unit vector from the centre to the hit point.
    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        todo!("Exercise 2.3: intersect_sphere (docs/lab02.md, Exercise 2.3)")
    }
}

impl Shading for Student {
    /// **Exercise 2.4** — light arriving at `position` from a point light (docs/lab02.md,
    /// §2.4; DTU `PointLight::sample`). With `r = |light.position − position|`:
    ///
    /// ```text
    /// direction = (light.position − position) / r      towards the light
    /// distance  = r
    /// radiance  = light.intensity / r²                 the inverse-square law
    /// ```
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample {
        todo!("Exercise 2.4: sample_point_light (docs/lab02.md, Exercise 2.4)")
    }

    /// **Exercise 2.5** — light from a directional light (docs/lab02.md, §2.5; DTU
    /// `Directional::sample`). `light.direction` is the direction the light *travels*; the
    /// direction towards the light is its opposite. The light is infinitely far away
    /// (`distance = f32::INFINITY`) and delivers `radiance = light.emission` from that one
    /// direction.
    fn sample_directional_light(&self, light: &DirectionalLight, position: Vec3) -> LightSample {
        todo!("Exercise 2.5: sample_directional_light (docs/lab02.md, Exercise 2.5)")
    }

    /// **Exercise 2.6** — radiance reflected by a Lambertian surface (docs/lab02.md, §2.6;
    /// DTU `Lambertian::shade`). The BRDF of a perfectly diffuse surface is `ρ_d/π`, so
    ///
    /// ```text
    /// L_r = Σ_lights (ρ_d / π) · L_i · max(0, n · ω_i)
    /// ```
    ///
    /// Light from below the surface (`n·ω_i < 0`) contributes nothing.
    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {
        todo!("Exercise 2.6: shade_lambertian (docs/lab02.md, Exercise 2.6)")
    }
}

//! Lab 02 — ray–surface intersection and Lambertian shading (docs/lab02.md).

use glam::Vec3;

use crate::math::Ray;
use crate::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// A ray–plane or ray–sphere intersection.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SurfaceHit {
    /// Ray parameter `t` of the hit (its distance, for a unit direction).
    pub distance: f32,
    /// Unit geometric normal at the hit (the plane's normal; outward for a sphere).
    pub normal: Vec3,
}

/// A ray–triangle intersection with the barycentric coordinates of the hit point
/// `(1 − β − γ)·v0 + β·v1 + γ·v2`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TriangleHit {
    /// Ray parameter `t` of the hit.
    pub distance: f32,
    /// Barycentric weight `β` of `v1`.
    pub beta: f32,
    /// Barycentric weight `γ` of `v2`.
    pub gamma: f32,
    /// Unit normal `normalize((v1 − v0) × (v2 − v0))` (not flipped towards the ray).
    pub normal: Vec3,
}

/// Light arriving at a surface point from one light source.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LightSample {
    /// Unit direction from the surface point towards the light, `ω_i`.
    pub direction: Vec3,
    /// Distance to the light (`f32::INFINITY` for a directional light).
    pub distance: f32,
    /// Incident radiance `L_i` (for point and directional lights: the value that, times
    /// `cos θ_i`, gives the irradiance).
    pub radiance: Vec3,
}

/// Lab 02's contract, part one: the three ray–primitive intersection tests.
///
/// Every test accepts only hits with `ray.tmin ≤ t ≤ ray.tmax`; the framework's
/// `trace_to_closest` relies on that to find the closest hit.
#[crate::contract]
pub trait Intersection: Send + Sync {
    /// Exercise 2.1 — ray–plane intersection, `t = −(o·n + d)/(ω·n)`.
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit>;

    /// Exercise 2.2 — ray–triangle intersection with barycentric coordinates.
    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit>;

    /// Exercise 2.3 — ray–sphere intersection: the nearest root in `[tmin, tmax]`.
    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit>;
}

/// Lab 02's contract, part two: lights and the Lambertian shader.
#[crate::contract]
pub trait Shading: Send + Sync {
    /// Exercise 2.4 — light from a point light: direction, distance and the inverse-square
    /// law `L_i = I / r²`.
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample;

    /// Exercise 2.5 — light from a directional light: `ω_i = −direction`, `L_i = E`.
    fn sample_directional_light(&self, light: &DirectionalLight, position: Vec3) -> LightSample;

    /// Exercise 2.6 — reflected radiance of a Lambertian surface,
    /// `L_r = Σ_i (ρ_d/π) · L_i · max(0, n·ω_i)`.
    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3;
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab02`.
pub type Contract = dyn Lab02;

/// Both halves of lab 02, as one object (what a lab02 crate's `Student` is).
pub trait Lab02: Intersection + Shading {}

impl<T: Intersection + Shading + ?Sized> Lab02 for T {}

impl crate::Mix for dyn Lab02 {
    fn mix(
        student: &std::sync::Arc<Self>,
        key: &std::sync::Arc<Self>,
        key_for: Vec<&'static str>,
        calls: &std::sync::Arc<crate::CallLog>,
    ) -> std::sync::Arc<Self> {
        crate::PartSlot::mixed(student, key, key_for, calls)
    }

    fn only(
        function: &'static str,
        student: &std::sync::Arc<Self>,
        base: &std::sync::Arc<Self>,
    ) -> std::sync::Arc<Self> {
        crate::PartSlot::shared(function, student, base)
    }
}

/// Lab 02's code goes under both halves as well: the integrator calls them one by one.
impl crate::Part for dyn Lab02 {
    fn register(code: std::sync::Arc<Self>, parts: &mut crate::Parts) {
        parts.put::<dyn Intersection>(code.clone());
        parts.put::<dyn Shading>(code.clone());
        parts.put::<Self>(code);
    }
}

/// The waiting slot of lab 02 as a whole.
impl Intersection for crate::Waiting<dyn Lab02> {
    fn intersect_plane(&self, _: &Ray, _: &Plane) -> Option<SurfaceHit> {
        self.unavailable("intersect_plane")
    }
    fn intersect_triangle(&self, _: &Ray, _: Vec3, _: Vec3, _: Vec3) -> Option<TriangleHit> {
        self.unavailable("intersect_triangle")
    }
    fn intersect_sphere(&self, _: &Ray, _: &Sphere) -> Option<SurfaceHit> {
        self.unavailable("intersect_sphere")
    }
}

impl Shading for crate::Waiting<dyn Lab02> {
    fn sample_point_light(&self, _: &PointLight, _: Vec3) -> LightSample {
        self.unavailable("sample_point_light")
    }
    fn sample_directional_light(&self, _: &DirectionalLight, _: Vec3) -> LightSample {
        self.unavailable("sample_directional_light")
    }
    fn shade_lambertian(&self, _: Vec3, _: Vec3, _: &[LightSample]) -> Vec3 {
        self.unavailable("shade_lambertian")
    }
}

impl crate::Trace for dyn Lab02 {
    fn trace(code: &std::sync::Arc<Self>) -> std::sync::Arc<Self> {
        std::sync::Arc::new(crate::Traced::new(code.clone()))
    }
}

impl crate::wire::Serve for dyn Lab02 {
    fn serve(&self, method: &str, args: &[u8], host: &dyn crate::wire::Host) -> Vec<u8> {
        use crate::wire::Serves;
        Serves::<dyn Intersection>::serve_part(self, method, args, host)
            .or_else(|| Serves::<dyn Shading>::serve_part(self, method, args, host))
            .unwrap_or_else(|| crate::wire::unknown_method(method))
    }
}

//! Lab 06 — radiosity with the hemicube (docs/lab06.md).
//!
//! The framework meshes a scene into patches ([`PatchMesh`](crate::radiosity::PatchMesh)),
//! renders the hemicube's five faces of a patch as an item buffer of patch ids
//! ([`ItemBuffer`]), runs the progressive-refinement loop and draws the solution
//! ([`crate::radiosity::solver`]); the student computes the form factors, shoots the energy
//! and turns radiosity into colours. Radiosities `B`, unshot radiosities `ΔB` and emissions
//! `E` are in W/m² per colour channel.

use glam::Vec3;

use crate::radiosity::{DeltaFormFactors, ItemBuffer, Patch};

/// Lab 06's contract (the DTU radiosity framework's `calcAnalyticalFF`, `Hemicube`,
/// `calcFF`, `maxenergy_patch`, `distributeEnergy` and `colorReconstruction`).
pub trait Radiosity: Send + Sync {
    /// Exercise 6.1 — `point_form_factor`: the form factor from a differential area at `x`
    /// with unit normal `n_x` to a small patch of area `area_y` at `y` with unit normal `n_y`,
    /// `F = A_y cos φ_x cos φ_y / (π r²)`, with each cosine clamped at zero (no occlusion).
    fn point_form_factor(&self, x: Vec3, n_x: Vec3, y: Vec3, n_y: Vec3, area_y: f32) -> f32;

    /// Exercise 6.2 — `delta_form_factor_top`: the delta form factor of the pixel of area
    /// `pixel_area` centred at `(x, y)` on the top face (`z = 1`) of the unit hemicube,
    /// `ΔF = ΔA / (π (x² + y² + 1)²)`.
    fn delta_form_factor_top(&self, x: f32, y: f32, pixel_area: f32) -> f32;

    /// Exercise 6.3 — `delta_form_factor_side`: the delta form factor of the pixel of area
    /// `pixel_area` centred at `(u, z)` on a side face of the unit hemicube (`u ∈ [−1, 1]`
    /// along the face, `z ∈ [0, 1]` the height above the patch), `ΔF = z ΔA / (π (u² + z² + 1)²)`.
    fn delta_form_factor_side(&self, u: f32, z: f32, pixel_area: f32) -> f32;

    /// Exercise 6.4 — `accumulate_form_factors`: the form factors `F_ij` from the shooter to
    /// each of `patch_count` patches: the sum of the delta form factors of the hemicube pixels
    /// in which patch `j` is seen (`items` and `delta` have the same layout, face by face).
    fn accumulate_form_factors(
        &self,
        items: &ItemBuffer,
        delta: &DeltaFormFactors,
        patch_count: usize,
    ) -> Vec<f32>;

    /// Exercise 6.5 — `select_shooter`: the patch with the most unshot power
    /// `A_i · (ΔB_i.r + ΔB_i.g + ΔB_i.b)`, or `None` when no patch has any.
    fn select_shooter(&self, patches: &[Patch], unshot: &[Vec3]) -> Option<usize>;

    /// Exercise 6.6 — `shoot`: one step of progressive refinement from patch `i`: every other
    /// patch `j` receives `ρ_j ΔB_i F_ij A_i / A_j`, added to its radiosity and its unshot
    /// radiosity; then `ΔB_i = 0`.
    fn shoot(
        &self,
        patches: &[Patch],
        form_factors: &[f32],
        shooter: usize,
        radiosity: &mut [Vec3],
        unshot: &mut [Vec3],
    );

    /// Exercise 6.7 — `patch_colours`: the radiance of each (Lambertian) patch, `L = B / π`.
    fn patch_colours(&self, radiosity: &[Vec3]) -> Vec<Vec3>;

    /// Exercise 6.8 — `vertex_colours`: nodal averaging: the colour of each of
    /// `vertex_count` vertices is the mean of the colours of the patches that have it as a
    /// corner (black for a vertex of no patch).
    fn vertex_colours(
        &self,
        patches: &[Patch],
        vertex_count: usize,
        patch_colours: &[Vec3],
    ) -> Vec<Vec3>;
}

//! # Lab 06 — radiosity with the hemicube
//!
//! Radiosity solves for the light of a scene of diffuse surfaces once, independently of the
//! viewpoint: the scene is cut into small patches of constant radiosity `B` (W/m²), and the
//! light that leaves one patch and arrives at another is its *form factor* `F_ij`. The
//! framework meshes the scene into patches, casts the rays of each hemicube into an *item
//! buffer* of patch ids, runs the progressive-refinement loop and draws the solution; you
//! write every formula in them (the DTU radiosity framework's `calcAnalyticalFF`,
//! `Hemicube::getDeltaFormFactor`, `calcFF`, `maxenergy_patch`, `distributeEnergy` and
//! `colorReconstruction`).
//!
//! Read `docs/lab06.md` first: it states each formula and derives it. Then fill in the
//! functions below and run
//!
//! ```text
//! cargo test -p lab06                # every exercise
//! cargo test -p lab06 exercise_6_2   # one exercise
//! raylab report --lab 6 --pipeline student   # the Cornell box solved by your code
//! ```
//!
//! A [`Patch`] has its `area`, unit `normal`, `centre`, `reflectance` ρ and emitted
//! radiosity `emission` `E`; colours are `Vec3`s, one number per channel (r, g, b).

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab06::Radiosity;
use contracts::lab06::{DeltaFormFactors, ItemBuffer, Patch};

/// Your radiosity. The framework calls it through the `Radiosity` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Radiosity for Student {
    /// **Exercise 6.1** — the analytic point-to-patch form factor (docs/lab06.md, §6.1; DTU
    /// `calcAnalyticalFF`).
    ///
    /// The fraction of the light leaving a differential area at `x` (unit normal `n_x`) that
    /// arrives at a small patch of area `area_y` at `y` (unit normal `n_y`), with nothing in
    /// between. `φ_x` is the angle between `n_x` and the direction from `x` to `y`, `φ_y` the
    /// angle between `n_y` and the direction back from `y` to `x`; a patch facing away has
    /// form factor 0, so clamp each cosine at 0.
    ///
    /// Hint: with `d = y − x`, `r² = d·d` and `ω = d / r`, `cos φ_x = n_x·ω` and
    /// `cos φ_y = −n_y·ω`.
    fn point_form_factor(&self, x: Vec3, n_x: Vec3, y: Vec3, n_y: Vec3, area_y: f32) -> f32 {
        todo!("Exercise 6.1: point_form_factor (docs/lab06.md, Exercise 6.1)")
    }

    /// **Exercise 6.2** — the delta form factor of a top-face pixel (docs/lab06.md, §6.2; DTU
    /// `Hemicube::getDeltaFormFactor`).
    ///
    /// The hemicube sits on the patch with its `z` axis along the normal; its top face is the
    /// square `z = 1`, `x, y ∈ [−1, 1]`. Return the form factor from the patch's centre to the
    /// pixel of area `pixel_area` centred at `(x, y, 1)`.
    ///
    /// Hint: the distance to the pixel is `r = √(x² + y² + 1)` and both cosines are `1/r`.
    fn delta_form_factor_top(&self, x: f32, y: f32, pixel_area: f32) -> f32 {
        todo!("Exercise 6.2: delta_form_factor_top (docs/lab06.md, Exercise 6.2)")
    }

    /// **Exercise 6.3** — the delta form factor of a side-face pixel (docs/lab06.md, §6.3).
    ///
    /// A side face stands at distance 1 from the centre; the pixel of area `pixel_area` is
    /// centred at `u ∈ [−1, 1]` along the face and height `z ∈ [0, 1]` above the patch's plane.
    ///
    /// Hint: as in 6.2 the distance is `r = √(u² + z² + 1)`, but now the patch's normal makes
    /// `cos φ = z/r` with the direction, and the pixel's own normal `cos φ' = 1/r`.
    fn delta_form_factor_side(&self, u: f32, z: f32, pixel_area: f32) -> f32 {
        todo!("Exercise 6.3: delta_form_factor_side (docs/lab06.md, Exercise 6.3)")
    }

    /// **Exercise 6.4** — form factors from an item buffer (docs/lab06.md, §6.4; DTU
    /// `calcFF`).
    ///
    /// `items.face(face)` lists the patch seen through each pixel of one of the five faces
    /// (`HemicubeFace::ALL`), `None` where nothing is seen; `delta.face(face)` lists the delta
    /// form factors of the same pixels in the same order. Return `F`, `patch_count` long:
    /// `F[j]` is the sum of the delta form factors of the pixels that see patch `j`.
    ///
    /// Hint: start from `vec![0.0; patch_count]` and walk each face's two lists together
    /// (`zip`).
    fn accumulate_form_factors(
        &self,
        items: &ItemBuffer,
        delta: &DeltaFormFactors,
        patch_count: usize,
    ) -> Vec<f32> {
        todo!("Exercise 6.4: accumulate_form_factors (docs/lab06.md, Exercise 6.4)")
    }

    /// **Exercise 6.5** — the next shooter (docs/lab06.md, §6.5; DTU `maxenergy_patch`).
    ///
    /// Return the index of the patch with the most unshot *power*: unshot radiosity times
    /// area, summed over the three channels. Return `None` when no patch has unshot power
    /// above 0 (everything has been shot).
    ///
    /// Hint: radiosity is power per area — a small bright patch may carry less than a large
    /// dim one.
    fn select_shooter(&self, patches: &[Patch], unshot: &[Vec3]) -> Option<usize> {
        todo!("Exercise 6.5: select_shooter (docs/lab06.md, Exercise 6.5)")
    }

    /// **Exercise 6.6** — one shot of progressive refinement (docs/lab06.md, §6.6; DTU
    /// `distributeEnergy`).
    ///
    /// `form_factors[j]` is `F_ij` from the shooter `i = shooter` to patch `j`. Every other
    /// patch `j` receives the radiosity of docs/lab06.md's formula (6.6), which you add both
    /// to `radiosity[j]` and to `unshot[j]` (it has not been passed on yet). Then the shooter
    /// has nothing left to shoot: set `unshot[shooter]` to zero.
    ///
    /// Hint: the formula is per channel — multiply the `Vec3`s component-wise.
    fn shoot(
        &self,
        patches: &[Patch],
        form_factors: &[f32],
        shooter: usize,
        radiosity: &mut [Vec3],
        unshot: &mut [Vec3],
    ) {
        todo!("Exercise 6.6: shoot (docs/lab06.md, Exercise 6.6)")
    }

    /// **Exercise 6.7** — colour reconstruction (docs/lab06.md, §6.7; DTU
    /// `colorReconstruction`).
    ///
    /// The colour to display is the radiance a patch sends towards the eye. Return it for
    /// every patch, given its radiosity.
    ///
    /// Hint: a Lambertian surface's radiance is the same in every direction, and integrating
    /// `L cos θ` over the hemisphere gives `B`.
    fn patch_colours(&self, radiosity: &[Vec3]) -> Vec<Vec3> {
        todo!("Exercise 6.7: patch_colours (docs/lab06.md, Exercise 6.7)")
    }

    /// **Exercise 6.8** — nodal averaging (docs/lab06.md, §6.8).
    ///
    /// Each patch lists its corner vertices (`patch.vertices`, indices below `vertex_count`).
    /// A vertex's colour is the mean of the colours of the patches it is a corner of, each patch
    /// counting once whatever its area; a vertex of no patch is black. The framework then interpolates the vertex colours across each
    /// patch (Gouraud shading).
    ///
    /// Hint: one pass over the patches adds each patch's colour to its corners and counts
    /// them; a second pass divides.
    fn vertex_colours(
        &self,
        patches: &[Patch],
        vertex_count: usize,
        patch_colours: &[Vec3],
    ) -> Vec<Vec3> {
        todo!("Exercise 6.8: vertex_colours (docs/lab06.md, Exercise 6.8)")
    }
}

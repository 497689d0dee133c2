//! Lab 06 — radiosity with the hemicube (docs/lab06.md).
//!
//! The framework meshes a scene into [`Patch`]es, renders the hemicube's five faces of a patch
//! as an item buffer of patch ids ([`ItemBuffer`]), runs the progressive-refinement loop and
//! draws the solution (the `pipeline` crate's `radiosity`); the student computes the form
//! factors, shoots the energy and turns radiosity into colours. Radiosities `B`, unshot radiosities `ΔB` and emissions
//! `E` are in W/m² per colour channel.

use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab06`.
pub type Contract = dyn Radiosity;

/// Lab 06's contract (the DTU radiosity framework's `calcAnalyticalFF`, `Hemicube`,
/// `calcFF`, `maxenergy_patch`, `distributeEnergy` and `colorReconstruction`).
#[crate::contract]
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

/// One patch: a planar triangle or quad with constant reflectance and emission.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Patch {
    /// Its corners, 3 or 4 indices into the patch mesh's vertices, counter-clockwise seen from
    /// the side its normal points to.
    pub vertices: Vec<u32>,
    /// Its centre (the mean of its corners).
    pub centre: Vec3,
    /// Its unit normal.
    pub normal: Vec3,
    /// Its area.
    pub area: f32,
    /// Diffuse reflectance `ρ` per channel (the material's `Kd`).
    pub reflectance: Vec3,
    /// Emitted radiosity `E = π L_e` in W/m² (the material's `Ke` is the radiance `L_e`).
    pub emission: Vec3,
}

/// One face of the hemicube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum HemicubeFace {
    /// The top face, `z = 1`: `resolution × resolution` pixels.
    Top,
    /// The side face `x = 1` (`u` along `y`): `resolution × resolution/2` pixels.
    PlusU,
    /// The side face `x = −1` (`u` along `−y`).
    MinusU,
    /// The side face `y = 1` (`u` along `−x`).
    PlusV,
    /// The side face `y = −1` (`u` along `x`).
    MinusV,
}

impl HemicubeFace {
    /// The five faces, the top first.
    pub const ALL: [HemicubeFace; 5] = [
        HemicubeFace::Top,
        HemicubeFace::PlusU,
        HemicubeFace::MinusU,
        HemicubeFace::PlusV,
        HemicubeFace::MinusV,
    ];

    /// Pixels across and up the face at hemicube `resolution` (even).
    pub fn size(self, resolution: u32) -> (u32, u32) {
        match self {
            HemicubeFace::Top => (resolution, resolution),
            _ => (resolution, resolution / 2),
        }
    }

    /// The direction, in the patch's frame (`z` along its normal), through the point `c` of
    /// the face: `(x, y)` on the top face, `(u, z)` on a side face.
    pub fn direction(self, c: Vec2) -> Vec3 {
        match self {
            HemicubeFace::Top => Vec3::new(c.x, c.y, 1.0),
            HemicubeFace::PlusU => Vec3::new(1.0, c.x, c.y),
            HemicubeFace::MinusU => Vec3::new(-1.0, -c.x, c.y),
            HemicubeFace::PlusV => Vec3::new(-c.x, 1.0, c.y),
            HemicubeFace::MinusV => Vec3::new(c.x, -1.0, c.y),
        }
    }
}

/// The centre of pixel `(i, j)` (`j` up the face) of a face at `resolution`: `(x, y)` on the
/// top face, `(u, z)` on a side face.
pub fn pixel_centre(face: HemicubeFace, resolution: u32, i: u32, j: u32) -> Vec2 {
    let step = 2.0 / resolution as f32;
    let a = -1.0 + (i as f32 + 0.5) * step;
    match face {
        HemicubeFace::Top => Vec2::new(a, -1.0 + (j as f32 + 0.5) * step),
        _ => Vec2::new(a, (j as f32 + 0.5) * step),
    }
}

/// The area of one pixel of a hemicube at `resolution`, `(2/resolution)²`.
pub fn pixel_area(resolution: u32) -> f32 {
    let step = 2.0 / resolution as f32;
    step * step
}

/// The patch seen through each pixel of the five faces, `None` where no patch is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ItemBuffer {
    /// Pixels across the top face (even).
    pub resolution: u32,
    /// The faces in the order of [`HemicubeFace::ALL`], each row by row (`i` fastest).
    pub faces: [Vec<Option<u32>>; 5],
}

impl ItemBuffer {
    /// The ids seen on `face`.
    pub fn face(&self, face: HemicubeFace) -> &[Option<u32>] {
        &self.faces[face as usize]
    }
}

/// The delta form factor of every pixel of a hemicube, tabulated once per resolution by the
/// lab's `delta_form_factor_top` and `delta_form_factor_side` (the four side faces share one
/// table: the formula sees only `(u, z)`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DeltaFormFactors {
    /// Pixels across the top face.
    pub resolution: u32,
    /// The top face's pixels, row by row (the layout of [`ItemBuffer::faces`]`[0]`).
    pub top: Vec<f32>,
    /// A side face's pixels, row by row from the patch's plane up.
    pub side: Vec<f32>,
}

impl DeltaFormFactors {
    /// The table at `resolution` (made even) from `radiosity`'s delta form factors.
    pub fn tabulate(radiosity: &dyn Radiosity, resolution: u32) -> Self {
        let resolution = resolution.max(2).next_multiple_of(2);
        let area = pixel_area(resolution);
        let table = |face: HemicubeFace| {
            let (w, h) = face.size(resolution);
            (0..w * h)
                .map(|k| {
                    let c = pixel_centre(face, resolution, k % w, k / w);
                    match face {
                        HemicubeFace::Top => radiosity.delta_form_factor_top(c.x, c.y, area),
                        _ => radiosity.delta_form_factor_side(c.x, c.y, area),
                    }
                })
                .collect()
        };
        Self {
            resolution,
            top: table(HemicubeFace::Top),
            side: table(HemicubeFace::PlusU),
        }
    }

    /// The delta form factors of `face`'s pixels, in the layout of [`ItemBuffer::face`].
    pub fn face(&self, face: HemicubeFace) -> &[f32] {
        match face {
            HemicubeFace::Top => &self.top,
            _ => &self.side,
        }
    }

    /// The sum over the whole hemicube (1 up to the discretisation).
    pub fn total(&self) -> f64 {
        self.top.iter().map(|&d| d as f64).sum::<f64>()
            + 4.0 * self.side.iter().map(|&d| d as f64).sum::<f64>()
    }
}

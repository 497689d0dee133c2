//! Exercise 6.6: one shot of progressive radiosity, and energy conservation in a closed box.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab06::Radiosity;
use grading::{GoldenFile, LabContext, for_all};
use pipeline::radiosity::Patch;
use pipeline::radiosity::solver::{FormFactors, SolveSettings, solve};

use super::hemicube::sum_bound;
use super::scenes::{check_image, closed_box};
use super::shooter::{bare_patch, radiosity};
use super::{GOLDEN_SHOOT, Part, SNAPSHOT_FLAT, close, load, part_slot, vec3_close};

/// Input of `shoot`: patches, form factors from the shooter (summing to at most 1), the
/// shooter, radiosities and unshot radiosities.
pub type ShootInput = (Vec<Patch>, Vec<f32>, usize, Vec<Vec3>, Vec<Vec3>);

/// Patches with areas from 10⁻⁶ to 10⁴ and reflectances in `[0, 1]`, form factors summing to at
/// most 1 (none to the shooter itself), a shooter with unshot radiosity, radiosities at least
/// the unshot ones.
pub fn shoot_input() -> impl Strategy<Value = ShootInput> {
    (2usize..12).prop_flat_map(|n| {
        let patch = ((-6.0f32..4.0), (0.0f32..=1.0, 0.0f32..=1.0, 0.0f32..=1.0))
            .prop_map(|(e, (r, g, b))| bare_patch(10f32.powf(e), Vec3::new(r, g, b)));
        (
            prop::collection::vec(patch, n),
            prop::collection::vec(0.0f32..1.0, n),
            0..n,
            prop::collection::vec(radiosity(), n),
            prop::collection::vec(radiosity(), n),
            radiosity().prop_map(|u| u + Vec3::splat(1e-3)),
        )
            .prop_map(|(patches, raw, i, extra, mut unshot, shooter_unshot)| {
                let mut f = raw;
                f[i] = 0.0;
                let sum: f32 = f.iter().sum();
                if sum > 1.0 {
                    f.iter_mut().for_each(|x| *x /= sum);
                }
                unshot[i] = shooter_unshot;
                let b = unshot.iter().zip(&extra).map(|(u, e)| *u + *e).collect();
                (patches, f, i, b, unshot)
            })
    })
}

fn check_shoot(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    input: &ShootInput,
) -> Result<(), String> {
    let (patches, f, i, b0, u0) = input;
    let i = *i;
    let (mut b, mut u) = (b0.clone(), u0.clone());
    r.shoot(patches, f, i, &mut b, &mut u);
    let call = format!("shoot(… {} patches, shooter = {i}, …)", patches.len());
    if u[i] != Vec3::ZERO {
        return Err(format!(
            "{call}: afterwards the shooter's unshot radiosity is {}; it has shot everything it had, so it must be 0",
            u[i]
        ));
    }
    if !vec3_close(b[i], b0[i], 0.0, 1e-6) {
        return Err(format!(
            "{call}: the shooter's radiosity went from {} to {}; shooting passes on its unshot radiosity but keeps its radiosity (it still sends that light out)",
            b0[i], b[i]
        ));
    }
    for j in 0..patches.len() {
        if j == i {
            continue;
        }
        let (db, du) = (b[j] - b0[j], u[j] - u0[j]);
        if !vec3_close(db, du, 1e-30, 1e-3) && !vec3_close(b[j], b0[j] + du, 1e-30, 1e-5) {
            return Err(format!(
                "{call}: patch {j}'s radiosity grew by {db} but its unshot radiosity by {du}: what a patch receives is added to both"
            ));
        }
        if (du.cmplt(Vec3::ZERO)).any() || !du.is_finite() {
            return Err(format!(
                "{call}: patch {j} received {du}: received radiosity is finite and at least 0"
            ));
        }
        if f[j] == 0.0 && du != Vec3::ZERO {
            return Err(format!(
                "{call}: patch {j} has form factor 0 from the shooter but received {du}"
            ));
        }
        for c in 0..3 {
            if patches[j].reflectance[c] == 0.0 && du[c] != 0.0 {
                return Err(format!(
                    "{call}: patch {j} has reflectance {} but received {du}: a patch reflects what it receives times its reflectance ρ_j, so a channel with ρ = 0 receives nothing",
                    patches[j].reflectance
                ));
            }
        }
    }
    diagnose_shoot(r, &call, input)?;
    // Energy: the power arriving at the others is the shooter's power times Σ F_ij, per channel
    // (on the channels of patches with ρ > 0).
    let shot_power = u0[i].as_dvec3() * patches[i].area as f64;
    let mut arriving = glam::DVec3::ZERO;
    let mut expected = glam::DVec3::ZERO;
    // The f32 rounding of ΔB_j added to the unshot radiosity it already had.
    let mut rounding = glam::DVec3::ZERO;
    for j in 0..patches.len() {
        if j == i {
            continue;
        }
        let rho = patches[j].reflectance.as_dvec3();
        let du = (u[j] - u0[j]).as_dvec3();
        for c in 0..3 {
            if rho[c] > 1e-3 {
                arriving[c] += du[c] * patches[j].area as f64 / rho[c];
                expected[c] += shot_power[c] * f[j] as f64;
                rounding[c] += 2e-7 * u[j][c].abs() as f64 * patches[j].area as f64 / rho[c];
            }
        }
    }
    for c in 0..3 {
        if !close(
            arriving[c],
            expected[c],
            rounding[c] + 1e-12 * shot_power[c],
            1e-3,
        ) {
            return Err(format!(
                "{call}: in channel {c} the shooter sends power A_i ΔB_i = {:e}, of which Σ_j F_ij = {:.4} should arrive at the other patches (power {:e}); your radiosities make A_j ΔB_j / ρ_j add up to {:e}. Radiosity is power per area: what patch j receives is ρ_j ΔB_i F_ij A_i / A_j",
                shot_power[c],
                expected[c] / shot_power[c].max(1e-300),
                expected[c],
                arriving[c]
            ));
        }
    }
    if let Some(key) = key {
        let (mut kb, mut ku) = (b0.clone(), u0.clone());
        key.shoot(patches, f, i, &mut kb, &mut ku);
        for j in 0..patches.len() {
            if !vec3_close(b[j], kb[j], 1e-30, 1e-4) || !vec3_close(u[j], ku[j], 1e-30, 1e-4) {
                return Err(format!(
                    "{call}: patch {j} has radiosity {} and unshot {} afterwards, expected {} and {}",
                    b[j], u[j], kb[j], ku[j]
                ));
            }
        }
    }
    Ok(())
}

/// What each patch's radiosity receives from one shot of `input`'s shooter through `r`, every
/// other patch starting from nothing (so that nothing is lost to rounding against what it had).
fn received(r: &dyn Radiosity, (patches, f, i, b0, u0): &ShootInput) -> Vec<Vec3> {
    let mut b = vec![Vec3::ZERO; patches.len()];
    let mut u = b.clone();
    b[*i] = b0[*i];
    u[*i] = u0[*i];
    r.shoot(patches, f, *i, &mut b, &mut u);
    b.iter()
        .enumerate()
        .map(|(j, x)| if j == *i { Vec3::ZERO } else { *x })
        .collect()
}

/// The first patch and channel whose received radiosity in `changed` is not `factor` times
/// that in `before` (channels that received a normal, finite amount only): `(j, before_j,
/// changed_j)`.
fn not_scaled(before: &[Vec3], changed: &[Vec3], factor: f32) -> Option<(usize, Vec3, Vec3)> {
    before
        .iter()
        .zip(changed)
        .enumerate()
        .find_map(|(j, (a, b))| {
            let differs = (0..3).any(|c| {
                a[c].is_normal()
                    && a[c].is_finite()
                    && (a[c] * 1e-20).is_normal()
                    && (b[c] - factor * a[c]).abs() > 1e-3 * factor * a[c].abs()
            });
            differs.then_some((j, *a, *b))
        })
}

/// The relations of one shot that tell its mistakes apart: what patch `j` receives halves
/// when the receivers' areas double (the power arriving spreads over `A_j`), doubles when the
/// shooter's area doubles (the power shot is `A_i ΔB_i`), and does not change with the
/// shooter's radiosity `B_i` (only the unshot `ΔB_i` is shot) or its reflectance (the receiver
/// reflects, with its own `ρ_j`).
fn diagnose_shoot(r: &dyn Radiosity, call: &str, input: &ShootInput) -> Result<(), String> {
    let (patches, f, i, b0, u0) = input;
    let i = *i;
    let before = received(r, input);
    if before.iter().all(|x| *x == Vec3::ZERO) {
        // A patch that receives a normal amount (ρ_j ΔB_i F_ij A_i / A_j, in f64).
        let lit = (0..patches.len()).find(|&j| {
            let ratio = f[j] as f64 * patches[i].area as f64 / patches[j].area as f64;
            j != i && (patches[j].reflectance * u0[i]).as_dvec3().max_element() * ratio > 1e-30
        });
        return match lit {
            Some(j) => Err(format!(
                "{call}: no patch receives anything, though patch {j} has form factor F_ij = {} from the shooter, reflectance {} and the shooter has unshot radiosity ΔB_i = {}: read ΔB_i (into a local) before setting the shooter's unshot radiosity to 0, which comes last",
                f[j], patches[j].reflectance, u0[i]
            )),
            None => Ok(()),
        };
    }
    let with = |change: &dyn Fn(usize, &mut Patch)| {
        let mut p = patches.clone();
        for (j, patch) in p.iter_mut().enumerate() {
            change(j, patch);
        }
        received(r, &(p, f.clone(), i, b0.clone(), u0.clone()))
    };
    let receivers_doubled = with(&|j, p| {
        if j != i {
            p.area *= 2.0;
        }
    });
    let shooter_doubled = with(&|j, p| {
        if j == i {
            p.area *= 2.0;
        }
    });
    if not_scaled(&before, &receivers_doubled, 0.5).is_some() {
        if not_scaled(&before, &receivers_doubled, 2.0).is_none() {
            let (j, a, b) = not_scaled(&before, &receivers_doubled, 0.5).unwrap_or_default();
            return Err(format!(
                "{call}: patch {j} receives {a}, and {b} with every receiver's area doubled: twice as much, where a patch twice as large receives half the radiosity (the same power over twice the area). The shooter's power A_i ΔB_i F_ij spreads over the receiver's area: the ratio is A_i / A_j, the shooter's area over the receiver's, not A_j / A_i"
            ));
        }
        if not_scaled(&before, &receivers_doubled, 1.0).is_none()
            && not_scaled(&before, &shooter_doubled, 1.0).is_none()
        {
            let j = before.iter().position(|x| *x != Vec3::ZERO).unwrap_or(0);
            return Err(format!(
                "{call}: patch {j} receives {} whatever the patches' areas (the same with every receiver's area doubled, and with the shooter's): ΔB_i F_ij is power per unit of the shooter's area; the power A_i ΔB_i F_ij that arrives spreads over the receiver's area A_j, so patch j receives ρ_j ΔB_i F_ij A_i / A_j — the ratio of areas is missing",
                before[j]
            ));
        }
        let (j, a, b) = not_scaled(&before, &receivers_doubled, 0.5).unwrap_or_default();
        return Err(format!(
            "{call}: patch {j} receives {a}, and {b} with every receiver's area doubled, expected half of it: radiosity is power per area, so the same power arriving at a patch twice as large is half the radiosity (ρ_j ΔB_i F_ij A_i / A_j)"
        ));
    }
    if let Some((j, a, b)) = not_scaled(&before, &shooter_doubled, 2.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, and {b} with the shooter's area doubled, expected twice as much: a shooter twice as large shoots twice the power A_i ΔB_i (ρ_j ΔB_i F_ij A_i / A_j)"
        ));
    }
    let mut b_changed = b0.clone();
    b_changed[i] = b0[i] * 3.0 + Vec3::new(1.0, 2.0, 3.0);
    let radiosity_changed = received(r, &(patches.clone(), f.clone(), i, b_changed, u0.clone()));
    if let Some((j, a, b)) = not_scaled(&before, &radiosity_changed, 1.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, but {b} when only the shooter's radiosity B_i changes (its unshot radiosity ΔB_i the same): a shot sends the unshot radiosity ΔB_i, the light the shooter has received since it last shot; B_i also holds the light it has already shot, which would be sent again"
        ));
    }
    let reflectance_changed = with(&|j, p| {
        if j == i {
            p.reflectance = Vec3::select(
                p.reflectance.cmpgt(Vec3::splat(0.5)),
                Vec3::splat(0.2),
                Vec3::splat(0.8),
            );
        }
    });
    if let Some((j, a, b)) = not_scaled(&before, &reflectance_changed, 1.0) {
        return Err(format!(
            "{call}: patch {j} receives {a}, but {b} when only the shooter's reflectance changes: the receiving patch reflects what arrives, so the factor is its own reflectance ρ_j (patches[j].reflectance), not the shooter's"
        ));
    }
    Ok(())
}

/// A shot in which every factor of `ρ_j ΔB_i F_ij A_i / A_j` differs from patch to patch and
/// from channel to channel, and the shooter's radiosity from its unshot radiosity: the input
/// on which `diagnose_shoot` first tells the mistakes apart.
pub fn diagnosis_input() -> ShootInput {
    let patches = vec![
        bare_patch(0.5, Vec3::new(0.3, 0.6, 0.9)),
        bare_patch(2.0, Vec3::new(0.8, 0.5, 0.2)),
        bare_patch(0.1, Vec3::new(0.4, 0.7, 0.6)),
        bare_patch(1.0, Vec3::new(0.5, 0.25, 0.75)),
    ];
    let f = vec![0.0, 0.3, 0.05, 0.2];
    let u = vec![
        Vec3::new(1.0, 2.0, 1.5),
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::ZERO,
        Vec3::new(0.5, 0.0, 0.25),
    ];
    let b = vec![
        Vec3::new(5.0, 4.0, 3.0),
        Vec3::new(0.4, 0.5, 0.6),
        Vec3::new(0.2, 0.1, 0.3),
        Vec3::new(0.5, 0.7, 0.25),
    ];
    (patches, f, 0, b, u)
}

/// In a closed box with `ρ < 1` (6 faces of 3 × 3 patches, one emitting), the solution's total
/// power stays below the geometric series `P_E (1 + ρ + ρ² + …) = P_E / (1 − ρ)` and reaches
/// it, at scales from 10⁻³ to 10³.
fn check_closed_box_energy(r: &dyn Radiosity) -> Result<(), String> {
    let (rho, n) = (0.6f32, 16);
    for size in [1e-3f32, 1.0, 1e3] {
        let mesh = closed_box(size, 3, rho);
        let settings = SolveSettings {
            form_factors: FormFactors::Hemicube(n),
            threshold: 1e-4,
            max_shots: 5000,
        };
        let solution = solve(r, &mesh, &settings);
        let emitted = mesh.power(&mesh.emission());
        let total = mesh.power(&solution.radiosity) / emitted;
        let bound = 1.0 / (1.0 - rho as f64);
        let slack = 1e-3 + 2.0 * sum_bound(n);
        let unshot = mesh.power(&solution.unshot) / emitted;
        if !total.is_finite()
            || total > bound * (1.0 + slack)
            || total < bound * (1.0 - slack) - unshot / (1.0 - rho as f64)
        {
            return Err(format!(
                "in a closed box of side {size:e} with reflectance ρ = {rho} everywhere and one emitting patch, the converged solution ({} shots, hemicube {n}) has total power Σ A_j B_j = {total:.5} times the emitted power; every bounce keeps the fraction ρ of the light, so it must reach the geometric series 1/(1 − ρ) = {bound:.5} without exceeding it (within {slack:.1e})",
                solution.shots()
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_6_6(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    let input = diagnosis_input();
    let call = format!(
        "shoot(patches with areas {:?} and reflectances {}, form factors {:?}, shooter = 0 with radiosity B_0 = {} and unshot ΔB_0 = {}, …)",
        input.0.iter().map(|p| p.area).collect::<Vec<_>>(),
        input
            .0
            .iter()
            .map(|p| p.reflectance.to_string())
            .collect::<Vec<_>>()
            .join(", "),
        input.1,
        input.3[0],
        input.4[0]
    );
    diagnose_shoot(p.as_ref(), &call, &input)?;
    for_all(300, shoot_input(), |input| {
        check_shoot(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<ShootInput, (Vec<Vec3>, Vec<Vec3>)> = load(ctx, GOLDEN_SHOOT)?;
    for case in &golden.cases {
        let (patches, f, i, b0, u0) = &case.input;
        let (mut b, mut u) = (b0.clone(), u0.clone());
        p.shoot(patches, f, *i, &mut b, &mut u);
        let (eb, eu) = &case.expected;
        for j in 0..patches.len() {
            if !vec3_close(b[j], eb[j], 1e-30, 1e-4) || !vec3_close(u[j], eu[j], 1e-30, 1e-4) {
                return Err(format!(
                    "shoot on a recorded case ({} patches, shooter {i}): patch {j} has radiosity {} and unshot {} afterwards, expected {} and {}",
                    patches.len(),
                    b[j],
                    u[j],
                    eb[j],
                    eu[j]
                ));
            }
        }
    }
    let r = part_slot(Part::Shoot, p, &ctx.base);
    check_closed_box_energy(r.as_ref())?;
    check_image(r.as_ref(), ctx, false, SNAPSHOT_FLAT)
}

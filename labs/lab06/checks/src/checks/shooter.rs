//! Exercise 6.5: selecting the patch with the most unshot power.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab06::Radiosity;
use grading::{GoldenFile, LabContext, for_all};
use pipeline::radiosity::Patch;

use super::{GOLDEN_SHOOTER, load};

/// A patch with only what shooting needs: area and reflectance (one vertex, at no position).
pub(super) fn bare_patch(area: f32, reflectance: Vec3) -> Patch {
    Patch {
        vertices: vec![0, 0, 0],
        centre: Vec3::ZERO,
        normal: Vec3::Z,
        area,
        reflectance,
        emission: Vec3::ZERO,
    }
}

/// A colour with channels from 10⁻³ to 10³, some of them 0.
pub(super) fn radiosity() -> impl Strategy<Value = Vec3> {
    let channel = prop_oneof![1 => Just(0.0f32), 3 => (-3.0f32..3.0).prop_map(|e| 10f32.powf(e))];
    (channel.clone(), channel.clone(), channel).prop_map(|(r, g, b)| Vec3::new(r, g, b))
}

/// Input of `select_shooter`: patch areas from 10⁻⁸ to 10⁶ and unshot radiosities (a tenth of
/// the cases with nothing left to shoot).
pub type ShooterInput = (Vec<Patch>, Vec<Vec3>);

/// Patches and unshot radiosities for `select_shooter`.
pub fn shooter_input() -> impl Strategy<Value = ShooterInput> {
    (1usize..30, prop::bool::weighted(0.1)).prop_flat_map(|(n, empty)| {
        (
            prop::collection::vec(
                (-8.0f32..6.0).prop_map(|e| bare_patch(10f32.powf(e), Vec3::splat(0.5))),
                n,
            ),
            prop::collection::vec(
                radiosity().prop_map(move |u| if empty { Vec3::ZERO } else { u }),
                n,
            ),
        )
    })
}

fn power(p: &Patch, u: Vec3) -> f64 {
    p.area as f64 * (u.x as f64 + u.y as f64 + u.z as f64)
}

fn check_shooter(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (patches, unshot): &ShooterInput,
) -> Result<(), String> {
    let got = r.select_shooter(patches, unshot);
    let powers: Vec<f64> = patches
        .iter()
        .zip(unshot)
        .map(|(p, u)| power(p, *u))
        .collect();
    let most = powers.iter().cloned().fold(0.0, f64::max);
    let call = format!(
        "select_shooter(patches with areas {:?}, unshot {:?})",
        patches.iter().map(|p| p.area).collect::<Vec<_>>(),
        unshot
    );
    match got {
        None if most > 0.0 => Err(format!(
            "{call} = None, but patches still have unshot power (most: {most:e})"
        )),
        None => Ok(()),
        Some(i) if i >= patches.len() => Err(format!(
            "{call} = Some({i}): there are only {} patches",
            patches.len()
        )),
        Some(_) if most == 0.0 => Err(format!(
            "{call} = {got:?}, but no patch has unshot power left: return None, so that refinement stops"
        )),
        Some(i) if powers[i] < most * (1.0 - 1e-5) => {
            let j = powers.iter().position(|&p| p == most).unwrap_or(0);
            Err(format!(
                "{call} = Some({i}), whose unshot power A·(ΔB.r + ΔB.g + ΔB.b) is {:e}; patch {j} has {most:e}: pick the most unshot power (radiosity times area), not the most unshot radiosity",
                powers[i]
            ))
        }
        Some(i) => match key.and_then(|k| k.select_shooter(patches, unshot)) {
            Some(k) if (powers[k] - powers[i]).abs() > 1e-5 * most => {
                Err(format!("{call} = Some({i}), expected Some({k})"))
            }
            _ => Ok(()),
        },
    }
}

pub(super) fn exercise_6_5(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(300, shooter_input(), |input| {
        check_shooter(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<ShooterInput, Option<usize>> = load(ctx, GOLDEN_SHOOTER)?;
    for case in &golden.cases {
        let (patches, unshot) = &case.input;
        let got = p.select_shooter(patches, unshot);
        let same = match (got, case.expected) {
            (Some(a), Some(b)) => {
                a < patches.len()
                    && (power(&patches[a], unshot[a]) - power(&patches[b], unshot[b])).abs()
                        <= 1e-5 * power(&patches[b], unshot[b])
            }
            (a, b) => a == b,
        };
        if !same {
            return Err(format!(
                "select_shooter on a recorded case of {} patches = {got:?}, expected {:?}",
                patches.len(),
                case.expected
            ));
        }
    }
    Ok(())
}

//! Exercise 9.4: texture addressing modes (wrap, clamp, mirror).

use std::sync::Arc;

use proptest::prelude::*;

use contracts::lab09::{Addressing, Texturing};
use grading::{GoldenFile, LabContext, for_all};

use super::scene::{addressing, check_render};
use super::{GOLDEN_ADDRESS, Part};

/// An addressing case: a point `x ∈ [0, 1)`, a whole number `k` of periods from −10³ to 10³,
/// and the mode.
pub type AddressInput = (f32, i32, Addressing);

/// Points in `[0, 1)` (some next to 0 and 1), periods from −10³ to 10³, every mode.
pub fn address_input() -> impl Strategy<Value = AddressInput> {
    (
        prop_oneof![
            4 => 0.0f32..1.0,
            1 => 0.0f32..1e-3,
            1 => (1.0f32 - 1e-3)..1.0,
            1 => Just(0.0f32),
            1 => Just(0.5f32),
        ],
        prop_oneof![3 => -3i32..=3, 1 => -1000i32..=1000],
        addressing(),
    )
}

fn check_address(p: &dyn Texturing, (x, k, mode): AddressInput) -> Result<(), String> {
    let call = |t: f32| format!("address(t = {t}, {mode:?})");
    // The identity on [0, 1).
    let got = p.address(x, mode);
    if (got - x).abs() > 1e-7 {
        return Err(format!(
            "{} is {got}: a coordinate already in [0, 1) is left as it is",
            call(x)
        ));
    }
    let tol = 2e-6;
    let on_circle = |a: f64, b: f64| {
        let d = (a - b).abs();
        d.min(1.0 - d)
    };
    let odd = k.rem_euclid(2) == 1;
    // t = k + x' just above the whole number k, or t = k − x' just below it, with x' in
    // [0, 1) exactly (cases whose rounding leaves [0, 1) are skipped).
    for below in [false, true] {
        let t = if below { k as f32 - x } else { k as f32 + x };
        let x = if below {
            k as f64 - t as f64
        } else {
            t as f64 - k as f64
        };
        if !(0.0..1.0).contains(&x) {
            continue;
        }
        let got = p.address(t, mode);
        if !got.is_finite() || !(0.0..=1.0).contains(&got) {
            return Err(format!(
                "{} is {got}: the corresponder maps every coordinate into [0, 1]{}",
                call(t),
                if t < 0.0 {
                    " — for a negative t too (Rust's % and f32::fract keep the sign of t)"
                } else {
                    ""
                }
            ));
        }
        let (expected, what) = match mode {
            Addressing::Repeat => (
                if below { 1.0 - x } else { x },
                "repeat is periodic with period 1: t and t + k for any whole k address the same point (negative t too)",
            ),
            Addressing::Mirror => (
                if odd { 1.0 - x } else { x },
                "mirror is the identity on [0, 1], symmetric about every integer and periodic with period 2: 2 − t on [1, 2], −t on [−1, 0] (negative t too)",
            ),
            Addressing::Clamp => (
                (t as f64).clamp(0.0, 1.0),
                "clamp leaves [0, 1] as it is and sends t < 0 to 0, t > 1 to 1",
            ),
        };
        let off = if mode == Addressing::Repeat {
            on_circle(got as f64, expected)
        } else {
            (got as f64 - expected).abs()
        };
        if off > tol * (1.0 + t.abs() as f64 * 1e-3) {
            return Err(format!(
                "{} is {got}, expected {expected:.7}: {what}",
                call(t)
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_9_4(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    for_all(1500, address_input(), |input| {
        check_address(p.as_ref(), input)
    })?;
    // Whole numbers: repeat gives 0 or 1 (the same place), mirror 0 at even and 1 at odd
    // ones, clamp 0 below and 1 above.
    for k in -5i32..=5 {
        let t = k as f32;
        let call = |mode: Addressing| format!("address(t = {t}, {mode:?})");
        let r = p.address(t, Addressing::Repeat);
        if r != 0.0 && r != 1.0 {
            return Err(format!(
                "{} is {r}: a whole number repeats to the texture's edge, 0 (or 1, the same place)",
                call(Addressing::Repeat)
            ));
        }
        let m = p.address(t, Addressing::Mirror);
        let even = k.rem_euclid(2) == 0;
        if (m - if even { 0.0 } else { 1.0 }).abs() > 1e-6 {
            return Err(format!(
                "{} is {m}: mirror gives 0 at even and 1 at odd whole numbers",
                call(Addressing::Mirror)
            ));
        }
        let c = p.address(t, Addressing::Clamp);
        if c != t.clamp(0.0, 1.0) {
            return Err(format!(
                "{} is {c}: clamp sends t ≤ 0 to 0 and t ≥ 1 to 1",
                call(Addressing::Clamp)
            ));
        }
    }
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(500, (-1e3f32..1e3, addressing()), |(t, mode)| {
            let (got, expected) = (p.address(t, mode), key.address(t, mode));
            let off = (got - expected).abs();
            let off = if mode == Addressing::Repeat {
                off.min(1.0 - off)
            } else {
                off
            };
            if off <= 1e-6 * (1.0 + t.abs() * 1e-3) {
                Ok(())
            } else {
                Err(format!(
                    "address(t = {t}, {mode:?}) is {got}, expected {expected}"
                ))
            }
        })?;
    }
    let golden: GoldenFile<(f32, Addressing), f32> = ctx.golden(GOLDEN_ADDRESS)?;
    for case in &golden.cases {
        let (t, mode) = case.input;
        let got = p.address(t, mode);
        let off = (got - case.expected).abs();
        let off = if mode == Addressing::Repeat {
            off.min(1.0 - off)
        } else {
            off
        };
        if off > 1e-6 * (1.0 + t.abs() * 1e-3) {
            return Err(format!(
                "address(t = {t}, {mode:?}) is {got}, expected {}",
                case.expected
            ));
        }
    }
    check_render(p, Part::Address, ctx)
}

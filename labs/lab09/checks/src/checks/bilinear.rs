//! Exercise 9.6: bilinear filtering: centres, affinity, continuity and addressing modes.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab09::{Addressing, Texturing};
use grading::{GoldenFile, LabContext, compare_vec3, for_all};
use raylab_core::scene::Texture;

use super::scene::{
    TextureCase, addressing, check_render, random_texture, texcoords, texel_centre, texel_name,
    texture_case,
};
use super::{GOLDEN_BILINEAR, Part};

/// Step, in texels, over which Exercise 9.6's continuity check bounds the change.
pub const CONTINUITY_STEP_TEXELS: f32 = 1e-3;

fn bilinear_call(case: TextureCase, uv: Vec2, mode: Addressing) -> String {
    format!(
        "sample_bilinear(a {}×{} texture, uv = {uv}, {mode:?})",
        case.0, case.1
    )
}

/// What a failing bilinear lookup does, found by running it on a probe: a 5×4 texture whose
/// texels hold their own centres in texel-centre coordinates (`x = u·w − ½`, `y = v·h − ½`,
/// rows counted from the bottom), read with clamp at a point inside, `(x, y) = (1.3, 2.8)`.
/// A lookup that blends texels around some point returns that point, which is compared with
/// the point each usual slip blends around. `None` when the lookup is right on the probe or
/// matches no slip.
fn bilinear_slip(p: &dyn Texturing) -> Option<&'static str> {
    let (w, h) = (5u32, 4u32);
    let probe = Texture::from_fn("<texel centres>", w, h, |i, j| {
        Vec3::new(i as f32, (h - 1 - j) as f32, 0.0)
    });
    let (x, y) = (1.3f32, 2.8f32);
    let uv = Vec2::new((x + 0.5) / w as f32, (y + 0.5) / h as f32);
    let got = p.sample_bilinear(&probe, uv, &|t: f32| t.clamp(0.0, 1.0));
    if !got.is_finite() {
        return None;
    }
    // Points in texel-centre coordinates, clamped to the centres as the probe is.
    let on_probe =
        |x: f32, y: f32| Vec2::new(x.clamp(0.0, (w - 1) as f32), y.clamp(0.0, (h - 1) as f32));
    let (x0, y0) = (x.floor(), y.floor());
    let (s, t) = (x - x0, y - y0);
    let matches = |q: Vec2| (Vec2::new(got.x, got.y) - q).abs().max_element() < 1e-3;
    if matches(on_probe(x, y)) {
        return None;
    }
    let slips = [
        (
            on_probe(x0 + t, y0 + s),
            "the weights s and t are swapped: s, the fractional part along u, blends the columns, and t, along v, the rows",
        ),
        (
            on_probe(x + 0.5, y + 0.5),
            "the half texel is not subtracted: texel k's centre is k + ½ texels from the edge, so subtract ½ from u·w and v·h before taking the integer part",
        ),
        (
            on_probe(x0 + 1.0 - s, y0 + 1.0 - t),
            "the weights are reversed: the neighbour at the larger column gets s and the lower one 1 − s (likewise t for the rows)",
        ),
        (
            on_probe(x, (h - 1) as f32 - y),
            "v is upside down: the rows are blended as if counted from the bottom, but `texel` counts them from the top",
        ),
        (
            on_probe((x + 0.5).floor(), (y + 0.5).floor()),
            "that is the nearest texel, not a blend of the four around the point",
        ),
        (
            on_probe(x, (y + 0.5).floor()),
            "the columns are blended but not the rows: blend the two rows around the point as well, by t",
        ),
        (
            on_probe((x + 0.5).floor(), y),
            "the rows are blended but not the columns: blend the two columns around the point as well, by s",
        ),
    ];
    slips
        .into_iter()
        .find(|&(q, _)| matches(q))
        .map(|(_, hint)| hint)
}

/// `e` with the slip [`bilinear_slip`] finds, or with `otherwise` when it finds none.
fn with_slip(e: String, p: &dyn Texturing, otherwise: &str) -> String {
    match bilinear_slip(p) {
        Some(hint) => format!("{e}: {hint}"),
        None if otherwise.is_empty() => e,
        None => format!("{e}: {otherwise}"),
    }
}

/// At a texel's centre the bilinear lookup is that texel.
fn check_centres(p: &dyn Texturing, base: &dyn Texturing, case: TextureCase) -> Result<(), String> {
    let texture = random_texture(case);
    for mode in Addressing::ALL {
        let address = |t: f32| base.address(t, mode);
        for j in 0..texture.height {
            for i in 0..texture.width {
                let uv = texel_centre(&texture, i, j);
                compare_vec3(
                    &bilinear_call(case, uv, mode),
                    p.sample_bilinear(&texture, uv, &address),
                    texture.texel(i, j),
                    1e-5,
                    1e-4,
                )
                .map_err(|e| {
                    with_slip(
                        format!("{e}, texel {}", texel_name(i, j)),
                        p,
                        "at a texel's centre the lookup is that texel (texel k's centre is k + ½ texels from the edge)",
                    )
                })?;
            }
        }
    }
    Ok(())
}

/// An affine function of `(u, v)` sampled at the texel centres comes back exactly between
/// them.
fn check_affine(
    p: &dyn Texturing,
    base: &dyn Texturing,
    (w, h): (u32, u32),
    (c0, cu, cv): (Vec3, Vec3, Vec3),
    s: Vec2,
) -> Result<(), String> {
    let f = |uv: Vec2| c0 + cu * uv.x + cv * uv.y;
    let mut texture = Texture::from_fn("<affine>", w, h, |_, _| Vec3::ZERO);
    for j in 0..h {
        for i in 0..w {
            let c = texel_centre(&texture, i, j);
            texture.texels[(j * w + i) as usize] = f(c);
        }
    }
    // A point between the first and last texel centres.
    let lo = Vec2::new(0.5 / w as f32, 0.5 / h as f32);
    let uv = lo + s * (Vec2::ONE - 2.0 * lo);
    let address = |t: f32| base.address(t, Addressing::Clamp);
    let got = p.sample_bilinear(&texture, uv, &address);
    compare_vec3(
        &format!("sample_bilinear(a {w}×{h} texture whose texel at centre c holds {c0} + {cu}·c.u + {cv}·c.v, uv = {uv}, Clamp)"),
        got,
        f(uv),
        2e-5,
        1e-4,
    )
    .map_err(|e| {
        with_slip(
            e,
            p,
            "between texel centres, bilinear interpolation reproduces a linear gradient exactly; the weights are the point's fractional position between the centres around it",
        )
    })
}

/// Points next to texel edges, texel centres and the repeat seam, and a step along u or v.
pub type ContinuityInput = (TextureCase, u32, u32, f32, bool, Addressing);

/// Continuity cases: a texture, a column or row boundary, an offset and the axis.
pub fn continuity_input() -> impl Strategy<Value = ContinuityInput> {
    (
        texture_case(),
        0u32..=32,
        0u32..2,
        -2.0f32..2.0,
        any::<bool>(),
        addressing(),
    )
}

/// Across a texel edge (or centre, or the seam at a whole number) the lookup changes by at
/// most the texels' range times the step.
fn check_continuity(
    p: &dyn Texturing,
    base: &dyn Texturing,
    (case, k, centre, other, along_u, mode): ContinuityInput,
) -> Result<(), String> {
    let texture = random_texture(case);
    let n = if along_u { case.0 } else { case.1 } as f32;
    // A texel edge k/n or centre (k + ½)/n, shifted by a whole period or two, so the seam at
    // 0 and 1 (and beyond) is crossed too.
    let period = (other.round() as i32) as f32;
    let at = (k as f32 + 0.5 * centre as f32) / n + period;
    let step = CONTINUITY_STEP_TEXELS / n;
    let other = other.rem_euclid(1.0);
    let point = |t: f32| {
        if along_u {
            Vec2::new(t, other)
        } else {
            Vec2::new(other, t)
        }
    };
    let address = |t: f32| base.address(t, mode);
    let (a, b) = (point(at - step), point(at + step));
    let (ca, cb) = (
        p.sample_bilinear(&texture, a, &address),
        p.sample_bilinear(&texture, b, &address),
    );
    // Texels lie in [0, 1): the change over 2·10⁻³ texels is at most 2·10⁻³, plus rounding.
    let bound = 2.0 * CONTINUITY_STEP_TEXELS + 2e-4 * (1.0 + at.abs() * n);
    let jump = (ca - cb).abs().max_element();
    if jump.is_nan() || jump > bound {
        let place = if (at - at.round()).abs() < 1e-6 && centre == 0 {
            "the texture's edge (the seam of the repeated texture)"
        } else if centre == 0 {
            "a texel edge"
        } else {
            "a texel centre"
        };
        return Err(format!(
            "{} is {ca} but {} is {cb}: across {place} at {} = {at}, {} texels apart, the colour jumps by {jump:.4}; a bilinear lookup is continuous (texels in [0, 1) change it by at most {bound:.4} over that step). Find each of the four neighbours through `address` so that the texels on both sides of the edge or seam are blended",
            bilinear_call(case, a, mode),
            bilinear_call(case, b, mode),
            if along_u { "u" } else { "v" },
            2.0 * CONTINUITY_STEP_TEXELS
        ));
    }
    Ok(())
}

/// The lookup is periodic, mirrored or clamped as its corresponder, and within the texels'
/// range.
fn check_modes(
    p: &dyn Texturing,
    base: &dyn Texturing,
    case: TextureCase,
    s: Vec2,
    k: (i32, i32),
) -> Result<(), String> {
    let texture = random_texture(case);
    let (lo, hi) = texture.texels.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), t| (lo.min(*t), hi.max(*t)),
    );
    let look = |uv: Vec2, mode: Addressing| {
        let address = |t: f32| base.address(t, mode);
        p.sample_bilinear(&texture, uv, &address)
    };
    let shift = Vec2::new(k.0 as f32, k.1 as f32);
    let tol = 1e-4 * (1.0 + shift.abs().max_element() * case.0.max(case.1) as f32);
    for mode in Addressing::ALL {
        let c = look(s, mode);
        if !c.is_finite() || c.cmplt(lo - 1e-5).any() || c.cmpgt(hi + 1e-5).any() {
            return Err(format!(
                "{} is {c}, outside the range [{lo}, {hi}] of the texels: a bilinear lookup is a weighted average of texels, with weights in [0, 1] that sum to 1",
                bilinear_call(case, s, mode)
            ));
        }
    }
    let (repeat, mirror, clamp) = (Addressing::Repeat, Addressing::Mirror, Addressing::Clamp);
    let relations: [(Vec2, Addressing, Vec2, &str); 5] = [
        (
            s + shift,
            repeat,
            s,
            "repeated, the texture is periodic with period 1 in u and v",
        ),
        (
            -s,
            mirror,
            s,
            "mirrored, the texture is symmetric about u = 0 and v = 0",
        ),
        (
            Vec2::splat(2.0) - s + 2.0 * shift,
            mirror,
            s,
            "mirrored, the texture is symmetric about u = 1 and v = 1 and periodic with period 2",
        ),
        (
            Vec2::new(-1.0 - s.x * 3.0, s.y),
            clamp,
            Vec2::new(0.0, s.y),
            "clamped, the texture left of u = 0 is its value at u = 0",
        ),
        (
            Vec2::new(s.x, 1.0 + s.y * 50.0),
            clamp,
            Vec2::new(s.x, 1.0),
            "clamped, the texture above v = 1 is its value at v = 1",
        ),
    ];
    for (uv, mode, same_as, what) in relations {
        let (got, expected) = (look(uv, mode), look(same_as, mode));
        compare_vec3(&bilinear_call(case, uv, mode), got, expected, tol, 0.0)
            .map_err(|e| format!("{e} = {}: {what}", bilinear_call(case, same_as, mode)))?;
    }
    Ok(())
}

pub(super) fn exercise_9_6(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    let base = ctx.base.code::<dyn contracts::lab09::Texturing>();
    for_all(60, texture_case(), |case| {
        check_centres(p.as_ref(), base.as_ref(), case)
    })?;
    let colour =
        (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(r, g, b)| Vec3::new(r, g, b));
    for_all(
        300,
        (
            (2u32..=16, 2u32..=12),
            (colour.clone(), colour.clone(), colour),
            (0.0f32..=1.0, 0.0f32..=1.0).prop_map(|(a, b)| Vec2::new(a, b)),
        ),
        |(size, f, s)| check_affine(p.as_ref(), base.as_ref(), size, f, s),
    )?;
    for_all(600, continuity_input(), |input| {
        check_continuity(p.as_ref(), base.as_ref(), input)
    })?;
    for_all(
        300,
        (
            texture_case(),
            (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| Vec2::new(a, b)),
            (-1000i32..=1000, -3i32..=3),
        ),
        |(case, s, k)| check_modes(p.as_ref(), base.as_ref(), case, s, k),
    )?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(
            300,
            (texture_case(), texcoords(), addressing()),
            |(case, uv, mode)| {
                let texture = random_texture(case);
                let address = |t: f32| base.address(t, mode);
                let n = case.0.max(case.1) as f32;
                compare_vec3(
                    &bilinear_call(case, uv, mode),
                    p.sample_bilinear(&texture, uv, &address),
                    key.sample_bilinear(&texture, uv, &address),
                    1e-5 + 1e-6 * uv.abs().max_element() * n,
                    1e-4,
                )
                .map_err(|e| with_slip(e, p.as_ref(), ""))
            },
        )?;
    }
    let golden: GoldenFile<(TextureCase, Vec2, Addressing), Vec3> = ctx.golden(GOLDEN_BILINEAR)?;
    for case in &golden.cases {
        let (tex, uv, mode) = case.input;
        let address = |t: f32| base.address(t, mode);
        let n = tex.0.max(tex.1) as f32;
        compare_vec3(
            &bilinear_call(tex, uv, mode),
            p.sample_bilinear(&random_texture(tex), uv, &address),
            case.expected,
            1e-5 + 1e-6 * uv.abs().max_element() * n,
            1e-4,
        )
        .map_err(|e| with_slip(e, p.as_ref(), ""))?;
    }
    check_render(p, Part::Bilinear, ctx)
}

//! Exercise 9.5: nearest-texel lookup, at texel centres and on texel edges.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use contracts::lab09::{Addressing, Texturing};
use grading::{GoldenFile, LabContext, compare_vec3, for_all};
use raylab_core::scene::Texture;

use super::scene::{
    TextureCase, addressing, check_render, find_texel, random_texture, texcoords, texel_centre,
    texel_name, texture_case,
};
use super::{GOLDEN_NEAREST, Part};

/// The index, among `n` texels along an axis whose centres lie at `centre(k)`, of the centre
/// closest to `t` (found by trying them all), unless two are about as close (`None`).
fn closest_centre(n: u32, t: f32, centre: impl Fn(u32) -> f32) -> Option<u32> {
    let mut d: Vec<(f32, u32)> = (0..n).map(|k| ((centre(k) - t).abs(), k)).collect();
    d.sort_by(|a, b| a.0.total_cmp(&b.0));
    let margin = 1e-3 / n as f32;
    match d.as_slice() {
        [only] => Some(only.1),
        [first, second, ..] if second.0 - first.0 > margin => Some(first.1),
        _ => None,
    }
}

/// The texel whose centre is closest to the texture-space point `a` (None at a near tie).
pub fn closest_texel(texture: &Texture, a: Vec2) -> Option<(u32, u32)> {
    let i = closest_centre(texture.width, a.x, |i| texel_centre(texture, i, 0).x)?;
    let j = closest_centre(texture.height, a.y, |j| texel_centre(texture, 0, j).y)?;
    Some((i, j))
}

fn nearest_call(case: TextureCase, uv: Vec2, mode: &str) -> String {
    format!(
        "sample_nearest(a {}×{} texture, uv = {uv}, {mode})",
        case.0, case.1
    )
}

/// `sample_nearest` at `uv` through `address` gives the texel closest to the addressed point.
fn check_nearest_at(
    p: &dyn Texturing,
    case: TextureCase,
    uv: Vec2,
    address: &dyn Fn(f32) -> f32,
    mode: &str,
) -> Result<(), String> {
    let texture = random_texture(case);
    let a = Vec2::new(address(uv.x), address(uv.y));
    let Some((i, j)) = closest_texel(&texture, a) else {
        return Ok(());
    };
    let got = p.sample_nearest(&texture, uv, address);
    let expected = texture.texel(i, j);
    if got == expected {
        return Ok(());
    }
    let call = nearest_call(case, uv, mode);
    // What the usual slips would read: a coordinate not passed through `address` (used as it
    // is, the index clamped into the texture).
    let raw = |t: f32| t.clamp(0.0, 1.0);
    let slip = |b: Vec2| closest_texel(&texture, b).filter(|&t| t != (i, j));
    let found = match find_texel(&texture, got) {
        Some((gi, gj)) => {
            let hint = if slip(Vec2::new(raw(uv.x), raw(uv.y))) == Some((gi, gj))
                && slip(Vec2::new(a.x, raw(uv.y))) != Some((gi, gj))
                && slip(Vec2::new(raw(uv.x), a.y)) != Some((gi, gj))
            {
                " — neither u nor v went through `address`: the texel is the one at the unaddressed point, clamped into the texture"
            } else if slip(Vec2::new(a.x, raw(uv.y))) == Some((gi, gj)) {
                " — v did not go through `address`: call it on v as well as on u"
            } else if slip(Vec2::new(raw(uv.x), a.y)) == Some((gi, gj)) {
                " — u did not go through `address`: call it on u as well as on v"
            } else if gi == i && gj == texture.height - 1 - j {
                " — the row is upside down: rows count from the top, v goes up"
            } else if gi != i && gj == j {
                " — the column is wrong: texel i covers [i/w, (i+1)/w), so it holds the point when its centre is the closest"
            } else if gj != j && gi == i {
                " — the row is wrong: texel row j covers v in [1 − (j+1)/h, 1 − j/h]"
            } else {
                ""
            };
            format!("the texel {}{hint}", texel_name(gi, gj))
        }
        None => format!("{got}, which is not a texel of the texture"),
    };
    Err(format!(
        "{call} is {found}; the addressed point is {a}, whose closest texel centre is that of texel {} = {expected}",
        texel_name(i, j)
    ))
}

/// A corresponder that is none of the three modes (any map into `[0, 1]` will do): the lookup
/// must use the one it is given.
fn odd_corresponder(t: f32) -> f32 {
    0.5 + 0.5 * (1.7 * t + 0.3).sin()
}

/// The edges of the texture, before any other lookup, so that an index one past the last
/// column or row is named before it can read outside the texture: `address` giving exactly 1
/// or 0 for u (with v inside, so that an unclamped column still reads a texel of the next row)
/// and then for v, on textures of several rows first and a single row last. The other
/// coordinate lies a quarter of a texel into its texel, so that only the edge is in question;
/// a lookup wrong along the other axis gets the diagnosis of [`check_nearest_at`].
fn check_nearest_edges(p: &dyn Texturing) -> Result<(), String> {
    let inside = |t: f32| t.clamp(0.0, 1.0);
    let mode = "address = clamp into [0, 1]";
    for case in [(4, 3, 2), (16, 9, 3), (5, 1, 4), (1, 1, 1)] {
        let texture = random_texture(case);
        let (w, h) = (case.0, case.1);
        // A row above the bottom one (so that column w of an unclamped index is still in the
        // texels), and a column in the middle.
        let (row, column) = (h.saturating_sub(2), w / 2);
        let v = 1.0 - (row as f32 + 0.25) / h as f32;
        let u = (column as f32 + 0.25) / w as f32;
        // Each edge: the point, the texel, whether the edge is along u, and what to say.
        let edges = [
            (
                Vec2::new(1.0, v),
                (w - 1, row),
                true,
                "u = 1 is the right edge, in the last column: ⌊u·w⌋ = w is one past it, so clamp the column to w − 1",
            ),
            (
                Vec2::new(0.0, v),
                (0, row),
                true,
                "u = 0 is the left edge, in column 0",
            ),
            (
                Vec2::new(u, 1.0),
                (column, 0),
                false,
                "v = 1 is the top edge, in row 0: rows count from the top while v grows upwards, so the row comes from 1 − v",
            ),
            (
                Vec2::new(u, 0.0),
                (column, h - 1),
                false,
                "v = 0 is the bottom edge, in the last row: (1 − v)·h = h is one past it, so clamp the row to h − 1",
            ),
        ];
        for (uv, (i, j), along_u, what) in edges {
            let asked = std::cell::RefCell::new(Vec::new());
            let recorded = |t: f32| {
                asked.borrow_mut().push(t);
                inside(t)
            };
            let got = p.sample_nearest(&texture, uv, &recorded);
            let expected = texture.texel(i, j);
            if got == expected {
                continue;
            }
            let asked = asked.into_inner();
            for (t, axis) in [(uv.x, "u"), (uv.y, "v")] {
                if !asked.contains(&t) {
                    return Err(format!(
                        "{} is {got}, expected the texel {} = {expected}; it never called `address` on {axis} = {t}: look the texture up where `address` sends u and v, whatever the mode",
                        nearest_call(case, uv, mode),
                        texel_name(i, j),
                    ));
                }
            }
            let found = find_texel(&texture, got);
            // Column w of row j, read through the flat index, is column 0 of row j + 1.
            let past_the_end = along_u && i == w - 1 && j + 1 < h && got == texture.texel(0, j + 1);
            let edge_only = match found {
                Some((gi, gj)) if along_u => gj == j && gi != i,
                Some((gi, gj)) => gi == i && gj != j,
                None => false,
            };
            if !(past_the_end || edge_only) {
                check_nearest_at(p, case, uv, &inside, mode)?;
            }
            let found = match found {
                Some(_) if past_the_end => format!(
                    "the texel {}, which is where column {w} of row {j} would be, one past the last column",
                    texel_name(0, j + 1)
                ),
                Some((gi, gj)) => format!("the texel {}", texel_name(gi, gj)),
                None => format!("{got}, which is not a texel of the texture"),
            };
            return Err(format!(
                "{} is {found}, expected the texel {} = {expected}: {what}",
                nearest_call(case, uv, mode),
                texel_name(i, j),
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_9_5(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    let base = ctx.base.code::<dyn contracts::lab09::Texturing>();
    check_nearest_edges(p.as_ref())?;
    for_all(
        600,
        (texture_case(), texcoords(), addressing()),
        |(case, uv, mode)| {
            let address = |t: f32| base.address(t, mode);
            check_nearest_at(p.as_ref(), case, uv, &address, &format!("{mode:?}"))
        },
    )?;
    for_all(200, (texture_case(), texcoords()), |(case, uv)| {
        check_nearest_at(
            p.as_ref(),
            case,
            uv,
            &odd_corresponder,
            "address = 0.5 + 0.5·sin(1.7t + 0.3)",
        )
        .map_err(|e| format!("{e}: look the texture up where `address` sends u and v"))
    })?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(
            300,
            (texture_case(), texcoords(), addressing()),
            |(case, uv, mode)| {
                let texture = random_texture(case);
                let address = |t: f32| base.address(t, mode);
                let a = Vec2::new(address(uv.x), address(uv.y));
                if closest_texel(&texture, a).is_none() {
                    return Ok(());
                }
                compare_vec3(
                    &nearest_call(case, uv, &format!("{mode:?}")),
                    p.sample_nearest(&texture, uv, &address),
                    key.sample_nearest(&texture, uv, &address),
                    0.0,
                    0.0,
                )
            },
        )?;
    }
    let golden: GoldenFile<(TextureCase, Vec2, Addressing), Vec3> = ctx.golden(GOLDEN_NEAREST)?;
    for case in &golden.cases {
        let (tex, uv, mode) = case.input;
        let address = |t: f32| base.address(t, mode);
        compare_vec3(
            &nearest_call(tex, uv, &format!("{mode:?}")),
            p.sample_nearest(&random_texture(tex), uv, &address),
            case.expected,
            0.0,
            0.0,
        )?;
    }
    check_render(p, Part::Nearest, ctx)
}

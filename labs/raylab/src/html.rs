//! The pages the instructor's commands write: the shared style, the page with the grader's
//! stamp at its foot, titled lists and the script that sorts tables.

use maud::{DOCTYPE, Markup, PreEscaped, html};

const STYLE: &str = "body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 1em}\
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:.3em .6em;text-align:left}\
.passed{color:#060}.failed{color:#a00}pre{background:#f4f4f4;padding:.6em;white-space:pre-wrap}\
pre.program{border-left:4px solid #c90}\
.images{display:flex;gap:1em;flex-wrap:wrap}figure{margin:0}img{image-rendering:pixelated;\
width:320px;border:1px solid #ccc}footer{margin-top:2em;color:#666}\
pre.answer{background:#f4f8ff;border-left:4px solid #36c}";

/// A page with `title`, the shared style, `body` and the grader's stamp at its foot.
pub(crate) fn page(title: &str, body: Markup, script: Option<&str>) -> String {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                title { (title) }
                style { (PreEscaped(STYLE)) }
            }
            body {
                (body)
                footer { p { (stamp()) } }
                @if let Some(script) = script {
                    script { (PreEscaped(script)) }
                }
            }
        }
    }
    .into_string()
}

/// A titled list, or nothing when `lines` is empty.
pub(crate) fn section_list(title: Markup, lines: &[String]) -> Markup {
    html! {
        @if !lines.is_empty() {
            h2 { (title) }
            ul { @for line in lines { li { (line) } } }
        }
    }
}

/// Sorts a table by the column whose header is clicked (numbers as numbers), each click
/// reversing the order.
pub(crate) const SORT_SCRIPT: &str = "document.querySelectorAll('table.sortable th').forEach((th,i)=>{th.style.cursor='pointer';th.title='sort';th.onclick=()=>{const t=th.closest('table'),b=t.tBodies[0],rows=[...b.rows],up=th.dataset.up!=='1';th.dataset.up=up?'1':'0';const key=r=>{const s=r.cells[i].dataset.v??r.cells[i].textContent;const n=parseFloat(s);return isNaN(n)?s:n};rows.sort((x,y)=>{const a=key(x),c=key(y);return (a<c?-1:a>c?1:0)*(up?1:-1)});rows.forEach(r=>b.appendChild(r))}});";

/// The grader's version and the time of writing, for the foot of every report.
pub(crate) fn stamp() -> String {
    format!(
        "raylab {} (grader), {}",
        env!("CARGO_PKG_VERSION"),
        utc_time(crate::utc::now())
    )
}

/// `seconds` since the Unix epoch as `YYYY-MM-DD HH:MM UTC`.
fn utc_time(seconds: u64) -> String {
    let [year, month, day, hour, minute, _] = crate::utc::date_time(seconds);
    format!("{year:04}-{month:02}-{day:02} {hour:02}:{minute:02} UTC")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_time_of_known_instants() {
        assert_eq!(utc_time(0), "1970-01-01 00:00 UTC");
        // 2000-02-29 12:34 UTC, a leap day in a year divisible by 400.
        assert_eq!(utc_time(951_827_640), "2000-02-29 12:34 UTC");
        assert_eq!(utc_time(1_798_761_599), "2026-12-31 23:59 UTC");
    }
}

//! The registry's format: `labs/course.toml`, a `[labs]` table of one line per lab,
//! `labNN = "Title"`, in the order of the course. Comments and blank lines aside, nothing else
//! is accepted, so that the build script (which lists the labs before anything is compiled)
//! and the crate read it with this one parser.

/// One line of the registry.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// The lab's number, 1–99 (`labNN`).
    pub number: u8,
    /// Its title.
    pub title: String,
    /// The line it is on, counted from 1.
    pub line: usize,
}

/// The labs of `text`, in order; `Err("LINE: what is wrong")` for the first line that is not
/// of the format.
pub fn parse(text: &str) -> Result<Vec<Entry>, String> {
    let mut entries: Vec<Entry> = Vec::new();
    let mut in_labs = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        if content == "[labs]" {
            if in_labs {
                return Err(format!("{line}: a second [labs] table"));
            }
            in_labs = true;
            continue;
        }
        if !in_labs {
            return Err(format!("{line}: expected the table header [labs] first"));
        }
        let Some((key, value)) = content.split_once('=') else {
            return Err(format!(
                "{line}: expected `labNN = \"Title\"`, found `{content}`"
            ));
        };
        let (key, value) = (key.trim(), value.trim());
        let number = key
            .strip_prefix("lab")
            .filter(|n| n.len() == 2 && n.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|n| n.parse::<u8>().ok())
            .filter(|&n| n > 0)
            .ok_or_else(|| format!("{line}: expected a lab name lab01 … lab99, found `{key}`"))?;
        let title = value
            .strip_prefix('"')
            .and_then(|v| v.strip_suffix('"'))
            .filter(|t| !t.trim().is_empty() && !t.contains(['"', '\\']))
            .ok_or_else(|| {
                format!(
                    "{line}: expected the title of {key} in double quotes, without quotes or backslashes inside, found `{value}`"
                )
            })?;
        if let Some(last) = entries.last() {
            if number <= last.number {
                return Err(format!(
                    "{line}: {key} comes after lab{:02}: the labs are listed once each, in increasing order",
                    last.number
                ));
            }
        }
        entries.push(Entry {
            number,
            title: title.to_string(),
            line,
        });
    }
    if entries.is_empty() {
        return Err("1: the registry lists no lab".into());
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_labs_in_order_and_names_the_line_of_a_mistake() {
        let ok = "# the course\n[labs]\nlab01 = \"Camera rays\"\n\nlab03 = \"Shadows\"  \n";
        let labs = parse(ok).unwrap();
        assert_eq!(labs.len(), 2);
        assert_eq!(
            (labs[1].number, labs[1].title.as_str(), labs[1].line),
            (3, "Shadows", 5)
        );
        for (text, line) in [
            ("lab01 = \"A\"", "1:"),
            ("[labs]\nlab1 = \"A\"", "2:"),
            ("[labs]\nlab01 = A", "2:"),
            ("[labs]\nlab01 = \"\"", "2:"),
            ("[labs]\nlab02 = \"A\"\nlab01 = \"B\"", "3:"),
            ("[labs]\nlab02 = \"A\"\nlab02 = \"B\"", "3:"),
            ("[labs]\nlab00 = \"A\"", "2:"),
            ("[labs]\n", "1:"),
        ] {
            let error = parse(text).unwrap_err();
            assert!(error.starts_with(line), "{text:?}: {error}");
        }
    }
}

//! Text set into the Markdown reports as it is: code spans, table cells and fenced blocks.

/// `text` as a Markdown code span: shown as it is, never read as Markdown or HTML (a file
/// name in a submission is the student's to choose: `docs/<img src=x onerror=…>.md`). The
/// fence is one backtick longer than the longest run in `text`; control characters become
/// U+FFFD.
pub(super) fn code_span(text: &str) -> String {
    let text: String = text
        .chars()
        .map(|c| if c.is_control() { '\u{fffd}' } else { c })
        .collect();
    let mut longest = 0;
    let mut run = 0;
    for c in text.chars() {
        run = if c == '`' { run + 1 } else { 0 };
        longest = longest.max(run);
    }
    let fence = "`".repeat(longest + 1);
    format!("{fence} {text} {fence}")
}

/// `text` in a Markdown table cell: as text (no HTML, no Markdown), on one line, with its
/// pipes escaped.
pub(super) fn table_cell(text: &str) -> String {
    if text.is_empty() {
        return String::new();
    }
    code_span(text).replace('|', "\\|")
}

/// `text` as a Markdown code block whose fence no line of `text` can close.
pub(super) fn fenced(text: &str) -> String {
    let longest = text.split(|c| c != '`').map(str::len).max().unwrap_or(0);
    let fence = "`".repeat(longest.max(2) + 1);
    format!("{fence}text\n{text}\n{fence}\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_in_markdown_are_code() {
        assert_eq!(
            code_span("modified: docs/<img src=x onerror=alert(1)>.md"),
            "` modified: docs/<img src=x onerror=alert(1)>.md `"
        );
        assert_eq!(code_span("a``b`\nc"), "``` a``b`\u{fffd}c ```");
    }
}

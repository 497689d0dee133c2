//! Parsers of the command line's counts. A value they refuse is named by clap with its option
//! ("invalid value '-5' for '--width <WIDTH>': …"), and they say what was wrong with it and
//! what is accepted. Their options take a value that starts with `-` as the value
//! (`allow_negative_numbers`), so that `--width -5` is refused for being negative rather than
//! for being an unknown option.

/// A number of pixels, an image's width or height: a whole number, 1 or more.
pub fn pixels(text: &str) -> Result<u32, String> {
    positive(
        text,
        "a positive number of pixels (a whole number, 1 or more)",
    )
}

/// A count of samples, subdivisions or photons: a whole number, 1 or more.
pub fn count(text: &str) -> Result<u32, String> {
    positive(text, "a positive whole number (1 or more)")
}

/// `text` as a whole number from 1 to `u32::MAX`, or what is wrong with it and `expected`.
fn positive(text: &str, expected: &str) -> Result<u32, String> {
    let text = text.trim();
    let wrong = match text.parse::<i128>() {
        Ok(n) if n < 0 => format!("{text} is negative"),
        Ok(0) => "0 is not positive".to_string(),
        Ok(n) => match u32::try_from(n) {
            Ok(n) => return Ok(n),
            Err(_) => format!("{text} is more than {}", u32::MAX),
        },
        Err(_) if text.parse::<f64>().is_ok() => format!("{text} is not a whole number"),
        Err(_) => format!("'{}' is not a number", text.escape_debug()),
    };
    Err(format!("{wrong}; expected {expected}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_is_a_positive_whole_number_and_anything_else_says_why_not() {
        assert_eq!(pixels("512"), Ok(512));
        assert_eq!(count(" 4 "), Ok(4));
        assert_eq!(pixels("4294967295"), Ok(u32::MAX));
        let expected = "expected a positive number of pixels (a whole number, 1 or more)";
        for (text, wrong) in [
            ("-5", "-5 is negative"),
            ("0", "0 is not positive"),
            ("-0", "0 is not positive"),
            ("2.5", "2.5 is not a whole number"),
            ("4294967296", "4294967296 is more than 4294967295"),
            ("wide", "'wide' is not a number"),
            ("", "'' is not a number"),
        ] {
            assert_eq!(pixels(text), Err(format!("{wrong}; {expected}")), "{text}");
        }
        assert_eq!(
            count("-1"),
            Err("-1 is negative; expected a positive whole number (1 or more)".to_string())
        );
    }
}

//! The identifier of a lab: its number, and the names the tree gives it.

use std::fmt;
use std::str::FromStr;

/// A lab of the course by number (1–99): `lab01` is its crate and folder, `docs/lab01.md` its
/// docs page. Whether the course has it is the registry's to say ([`crate::lab`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LabId(u8);

impl LabId {
    /// Lab `number`; `None` outside 1–99.
    pub const fn new(number: u32) -> Option<Self> {
        if number >= 1 && number <= 99 {
            Some(Self(number as u8))
        } else {
            None
        }
    }

    /// Lab `number`, which must be in 1–99 (for constants; a panic otherwise).
    pub const fn of(number: u32) -> Self {
        match Self::new(number) {
            Some(id) => id,
            None => panic!("a lab number is in 1–99"),
        }
    }

    /// Its number.
    pub const fn number(self) -> u32 {
        self.0 as u32
    }

    /// Its folder, relative to the repository root: `labs/lab01`.
    pub fn folder(self) -> String {
        format!("labs/{self}")
    }

    /// The student's source file: `labs/lab01/src/lib.rs`.
    pub fn source(self) -> String {
        format!("labs/{self}/src/lib.rs")
    }

    /// The student's written answers: `labs/lab01/answers.md`.
    pub fn answers(self) -> String {
        format!("labs/{self}/answers.md")
    }

    /// Its docs page: `docs/lab01.md`.
    pub fn docs(self) -> String {
        format!("docs/{self}.md")
    }
}

/// The lab's crate and folder name, `lab01`.
impl fmt::Display for LabId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "lab{:02}", self.0)
    }
}

/// A lab as people write it: `lab01`, `lab1`, `01` or `1`.
impl FromStr for LabId {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let digits = s.strip_prefix("lab").unwrap_or(s);
        digits
            .parse::<u32>()
            .ok()
            .filter(|_| !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()))
            .and_then(Self::new)
            .ok_or_else(|| format!("expected a lab such as 3, 03 or lab03, found '{s}'"))
    }
}

impl serde::Serialize for LabId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u32(self.number())
    }
}

impl<'de> serde::Deserialize<'de> for LabId {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let number = u32::deserialize(d)?;
        Self::new(number).ok_or_else(|| serde::de::Error::custom("a lab number is in 1–99"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_parses() {
        let lab = LabId::of(7);
        assert_eq!(lab.to_string(), "lab07");
        assert_eq!(lab.docs(), "docs/lab07.md");
        assert_eq!(lab.source(), "labs/lab07/src/lib.rs");
        for text in ["7", "07", "lab07", "lab7"] {
            assert_eq!(text.parse::<LabId>(), Ok(lab), "{text}");
        }
        for text in ["", "lab", "0", "100", "-1", "lab 7", "7.1", "+7"] {
            assert!(text.parse::<LabId>().is_err(), "{text}");
        }
    }
}

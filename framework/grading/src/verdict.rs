//! The verdict record: how a check proves to `raylab grade` that it ran to its end, through a
//! channel the student's code cannot forge.
//!
//! A test process's exit code and its output are the student's to choose: `exit(0)` in a
//! student function, or a printed "test result: ok", says nothing about the check. So in
//! grading, a verdict counts only when it is a *record* carrying a secret that is fresh for
//! each exercise's run:
//!
//! 1. the grader draws the secret ([`new_secret`]), sets [`CHANNEL_VAR`] and writes the secret
//!    to the process's standard input, which it then closes;
//! 2. the harness ([`crate::harness`]) takes it ([`VerdictChannel::take`])
//!    before any student code has run, so that code later reads only an empty stdin;
//! 3. when the check has finished, the harness prints one line
//!    `RAYLAB-VERDICT <secret> <json>` to standard output and ends the process;
//! 4. the grader scans everything the process printed for that line with that secret
//!    ([`RecordScanner`]). No line, a line for another exercise, or one that does not parse:
//!    the exercise did not complete.
//!
//! The student's code may print anything, including look-alike lines; without the secret they
//! match nothing. What the secret cannot stop is code that reads the harness's memory; in
//! `raylab grade` student crates are compiled with `unsafe_code` forbidden and run without
//! `/proc` (docs/instructors.md, "Threat model", says what remains).

use std::io::{Read, Write};
use std::sync::atomic::{AtomicBool, Ordering};

use memchr::memmem;
use serde::{Deserialize, Serialize};

#[cfg(test)]
use crate::Failure;
use crate::{FailureKind, Judgement};

/// Set (to `stdin`) by the grader when the secret waits on standard input.
pub const CHANNEL_VAR: &str = "RAYLAB_VERDICT_CHANNEL";

/// The start of a record line, before the secret.
pub const RECORD_TAG: &str = "RAYLAB-VERDICT ";

/// A secret is this many bytes, written as twice as many hexadecimal digits.
const SECRET_BYTES: usize = 32;

/// The check's message is cut to this many bytes in the record.
const MESSAGE_LIMIT: usize = 16 * 1024;

/// The check's reason (the heart of the message, which holds it too) is cut to this many bytes.
const REASON_LIMIT: usize = 1024;

/// The record line is cut at this many bytes when read.
const RECORD_LIMIT: usize = MESSAGE_LIMIT + REASON_LIMIT + 4096;

static TAKEN: AtomicBool = AtomicBool::new(false);

/// What a check reports about one exercise.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Record {
    /// The exercise, e.g. `"2.2"`.
    pub exercise: String,
    /// Whether the check accepted the student's code.
    pub passed: bool,
    /// What became of the check, when it did not accept it.
    pub kind: Option<FailureKind>,
    /// Why not (the check's message), or empty.
    pub message: String,
    /// What the check (or the panic) said, the heart of the message; or empty.
    #[serde(default)]
    pub reason: String,
    /// The exercises whose functions were the answer key's in the run that decided the verdict
    /// (`"1.1"`), passed or failed: empty when the student's code alone was judged
    /// ([`crate::Judgement::key_for`]). The message then says so in a sentence.
    #[serde(default)]
    pub key_for: Vec<String>,
}

impl Record {
    /// The record of `exercise`'s judgement, its message cut to a bounded length: a failure's
    /// message, or for a pass the judgement's note (empty when the student's code alone
    /// passed).
    pub fn of(exercise: &str, judgement: &Judgement) -> Self {
        let failure = judgement.outcome.as_ref().err();
        Self {
            exercise: exercise.to_string(),
            passed: judgement.outcome.is_ok(),
            kind: failure.map(|f| f.kind.clone()),
            message: cut(
                failure.map_or(judgement.note.as_str(), |f| f.message.as_str()),
                MESSAGE_LIMIT,
            ),
            reason: cut(failure.map_or("", |f| f.reason.as_str()), REASON_LIMIT),
            key_for: judgement.key_for.clone(),
        }
    }
}

/// The harness's end of the channel: the secret, taken once per process.
pub struct VerdictChannel {
    secret: String,
}

impl VerdictChannel {
    /// The channel the grader opened, or `None` outside grading. Only the first call in a
    /// process can get it: the secret is read from standard input, which is then at its end.
    pub fn take() -> Option<Self> {
        if TAKEN.swap(true, Ordering::SeqCst) {
            return None;
        }
        std::env::var_os(CHANNEL_VAR)?;
        let mut secret = String::new();
        std::io::stdin()
            .lock()
            .take(2 * SECRET_BYTES as u64 + 2)
            .read_to_string(&mut secret)
            .ok()?;
        let secret = secret.trim().to_string();
        forbid_tracing();
        let valid =
            secret.len() == 2 * SECRET_BYTES && secret.bytes().all(|b| b.is_ascii_hexdigit());
        // An invalid secret still takes the channel: the record it writes matches nothing.
        Some(Self {
            secret: if valid { secret } else { String::new() },
        })
    }

    /// Prints the record of `exercise` with its judgement and ends the process: nothing the
    /// student's code does afterwards can change it.
    pub fn report(self, exercise: &str, judgement: &Judgement) -> ! {
        let record = Record::of(exercise, judgement);
        let json = serde_json::to_string(&record).unwrap_or_default();
        let mut out = std::io::stdout().lock();
        let _ = write!(out, "\n{RECORD_TAG}{} {json}\n", self.secret);
        let _ = out.flush();
        std::process::exit(0);
    }
}

/// Makes this process non-dumpable, so that no other process of the sandbox — a debugger the
/// student's code starts, say — may `ptrace` it or read its memory (`process_vm_readv`) to find
/// the secret: for a non-dumpable process that takes `CAP_SYS_PTRACE`, which the sandbox drops.
fn forbid_tracing() {
    #[cfg(target_os = "linux")]
    // SAFETY: PR_SET_DUMPABLE takes one integer argument and touches no memory of ours.
    unsafe {
        libc::prctl(libc::PR_SET_DUMPABLE, 0, 0, 0, 0);
    }
}

/// `text` cut to at most `limit` bytes at a character boundary, with a note when cut.
fn cut(text: &str, limit: usize) -> String {
    if text.len() <= limit {
        return text.to_string();
    }
    let mut end = limit;
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}\n[… cut: {} bytes in all]", &text[..end], text.len())
}

/// A fresh secret from the operating system's random source, as hexadecimal digits.
pub fn new_secret() -> std::io::Result<String> {
    let mut bytes = [0u8; SECRET_BYTES];
    std::fs::File::open("/dev/urandom")?.read_exact(&mut bytes)?;
    Ok(bytes.iter().map(|b| format!("{b:02x}")).collect())
}

/// The grader's end: finds the record with the secret in a process's output as it streams
/// past, in time linear in its length whatever the output holds.
pub struct RecordScanner {
    needle: Vec<u8>,
    carry: Vec<u8>,
    line: Option<Vec<u8>>,
    complete: bool,
}

impl RecordScanner {
    /// A scanner for the record line carrying `secret`.
    pub fn new(secret: &str) -> Self {
        Self {
            needle: format!("{RECORD_TAG}{secret} ").into_bytes(),
            carry: Vec::new(),
            line: None,
            complete: false,
        }
    }

    /// Scans the next piece of the output.
    pub fn feed(&mut self, chunk: &[u8]) {
        if self.complete {
            return;
        }
        if let Some(line) = &mut self.line {
            let end = chunk.iter().position(|&b| b == b'\n');
            let take = end.unwrap_or(chunk.len());
            let room = RECORD_LIMIT.saturating_sub(line.len());
            line.extend_from_slice(&chunk[..take.min(room)]);
            self.complete = end.is_some() || line.len() >= RECORD_LIMIT;
            return;
        }
        let mut window = std::mem::take(&mut self.carry);
        window.extend_from_slice(chunk);
        match memmem::find(&window, &self.needle) {
            Some(at) => {
                self.line = Some(Vec::new());
                let rest = window[at + self.needle.len()..].to_vec();
                self.feed(&rest);
            }
            None => {
                let keep = self.needle.len().saturating_sub(1).min(window.len());
                self.carry = window[window.len() - keep..].to_vec();
            }
        }
    }

    /// The record of `exercise`, if the output held a well-formed one for it.
    pub fn record(&self, exercise: &str) -> Option<Record> {
        let line = self.line.as_ref()?;
        let record: Record = serde_json::from_slice(line).ok()?;
        (record.exercise == exercise).then_some(record)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record_line(secret: &str, exercise: &str, passed: bool) -> String {
        let json = serde_json::to_string(&Record {
            exercise: exercise.into(),
            passed,
            kind: (!passed).then_some(FailureKind::Wrong),
            message: String::new(),
            reason: String::new(),
            key_for: Vec::new(),
        })
        .unwrap();
        format!("\n{RECORD_TAG}{secret} {json}\n")
    }

    #[test]
    fn only_the_secret_makes_a_record() {
        let secret = new_secret().unwrap();
        assert_eq!(secret.len(), 64);
        let forged = record_line(&"0".repeat(64), "2.1", true);
        let genuine = record_line(&secret, "2.1", false);
        let output = format!("test result: ok. 1 passed{forged}noise{genuine}after");
        // Fed in every chunking, the genuine record is found and the forged one is not.
        for size in [1, 3, 7, 64, 4096] {
            let mut scanner = RecordScanner::new(&secret);
            for chunk in output.as_bytes().chunks(size) {
                scanner.feed(chunk);
            }
            let record = scanner.record("2.1").expect("the genuine record");
            assert!(!record.passed, "chunks of {size}");
            assert_eq!(scanner.record("2.2"), None, "another exercise's record");
        }
        let mut scanner = RecordScanner::new(&secret);
        scanner.feed(forged.as_bytes());
        assert_eq!(scanner.record("2.1"), None);
    }

    #[test]
    fn a_truncated_or_garbled_record_is_none() {
        let secret = new_secret().unwrap();
        let line = record_line(&secret, "1.1", true);
        let mut scanner = RecordScanner::new(&secret);
        scanner.feed(&line.as_bytes()[..line.len() - 5]);
        assert_eq!(scanner.record("1.1"), None);
        let mut scanner = RecordScanner::new(&secret);
        scanner.feed(
            format!("{RECORD_TAG}{secret} {{\"exercise\":\"1.1\",\"passed\":tru\n").as_bytes(),
        );
        assert_eq!(scanner.record("1.1"), None);
    }

    #[test]
    fn a_record_of_the_longest_message_and_reason_is_read_whole() {
        let secret = new_secret().unwrap();
        let long = "x".repeat(4 * MESSAGE_LIMIT);
        let failure = Failure {
            exercise: "3.2".into(),
            kind: FailureKind::Wrong,
            reason: long.clone(),
            message: long,
        };
        let record = Record::of(
            "3.2",
            &Judgement {
                outcome: Err(failure),
                key_for: vec!["3.1".into()],
                note: String::new(),
            },
        );
        let json = serde_json::to_string(&record).unwrap();
        let mut scanner = RecordScanner::new(&secret);
        scanner.feed(format!("\n{RECORD_TAG}{secret} {json}\n").as_bytes());
        assert_eq!(scanner.record("3.2"), Some(record));
    }

    #[test]
    fn a_record_says_whose_code_decided_it_and_old_records_still_parse() {
        let keyed = Judgement {
            outcome: Ok(()),
            key_for: vec!["1.1".into(), "1.2".into()],
            note: "This check was judged with the answer key's `a` and `b` in place of yours."
                .into(),
        };
        let record = Record::of("1.6", &keyed);
        assert!(record.passed);
        assert_eq!(record.key_for, ["1.1", "1.2"]);
        assert_eq!(record.message, keyed.note);
        let json = serde_json::to_string(&record).unwrap();
        assert!(json.contains(r#""key_for":["1.1","1.2"]"#), "{json}");
        // A record of a grader from before the field.
        let old: Record = serde_json::from_str(
            r#"{"exercise":"1.1","passed":true,"kind":null,"message":"","reason":""}"#,
        )
        .unwrap();
        assert!(old.key_for.is_empty());
    }

    #[test]
    fn long_messages_are_cut() {
        let text = "é".repeat(MESSAGE_LIMIT);
        let cut = cut(&text, MESSAGE_LIMIT);
        assert!(cut.len() < MESSAGE_LIMIT + 64);
        assert!(cut.ends_with(&format!("{} bytes in all]", text.len())));
    }
}

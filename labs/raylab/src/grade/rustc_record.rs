//! How cargo compiles a lab for WebAssembly, written down: while the grader builds the
//! handout's stubs (before any submission), `raylab` is cargo's `RUSTC_WORKSPACE_WRAPPER` and
//! records each compiler command line — its arguments and the `CARGO_*` variables cargo set —
//! before it runs the compiler. A submission's lab is then compiled with the same command
//! lines in the build jail ([`super::jail`]), where cargo, the grading tree and the target
//! directory are out of sight.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use raylab_core::Error;

use crate::handout::io;

/// The variable that turns `raylab` into the recording wrapper: the directory the records go
/// to, one `<crate name>.json` per compiled crate.
pub const RECORD_VAR: &str = "RAYLAB_RECORD_RUSTC";

/// One compiler run as cargo made it.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq, Eq)]
pub struct RustcCall {
    /// The arguments after the compiler's path.
    pub args: Vec<String>,
    /// The `CARGO_*` variables cargo set for it (the crate's name, version, manifest
    /// directory, …), which `env!` reads.
    pub env: Vec<(String, String)>,
}

impl RustcCall {
    /// The record of the crate `crate_name` in `dir`.
    pub fn load(dir: &Path, crate_name: &str) -> Result<Self, Error> {
        let path = dir.join(format!("{crate_name}.json"));
        let text = std::fs::read_to_string(&path).map_err(io(&path))?;
        serde_json::from_str(&text).map_err(|e| Error::Failed {
            what: path.display().to_string(),
            reason: format!("not a compiler record: {e}"),
        })
    }

    /// The value of the option `--name VALUE` or `--name=VALUE`, if given.
    pub fn option(&self, name: &str) -> Option<&str> {
        let joined = format!("{name}=");
        self.args.iter().enumerate().find_map(|(i, a)| {
            if a == name {
                self.args.get(i + 1).map(String::as_str)
            } else {
                a.strip_prefix(&joined)
            }
        })
    }
}

/// When `raylab` runs as the recording wrapper (`RECORD_VAR` set, the compiler's path first
/// among its arguments), records the call and becomes the compiler; otherwise returns.
pub fn wrap_if_asked() {
    let Some(dir) = std::env::var_os(RECORD_VAR) else {
        return;
    };
    let mut args = std::env::args_os().skip(1);
    let Some(rustc) = args.next() else {
        return;
    };
    let args: Vec<OsString> = args.collect();
    if let Err(e) = record(Path::new(&dir), &args) {
        eprintln!("error: recording the compiler's command line: {e}");
        std::process::exit(1);
    }
    let error =
        std::os::unix::process::CommandExt::exec(std::process::Command::new(&rustc).args(&args));
    eprintln!(
        "error: cannot run {}: {error}",
        PathBuf::from(rustc).display()
    );
    std::process::exit(1);
}

/// Writes the record of a compiler run with `args` into `dir`, when it compiles a crate
/// (cargo also asks the compiler what it can do, with `--crate-name ___`).
fn record(dir: &Path, args: &[OsString]) -> Result<(), Error> {
    let args: Vec<String> = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let call = RustcCall {
        env: std::env::vars()
            .filter(|(name, _)| name.starts_with("CARGO_"))
            .collect(),
        args,
    };
    let Some(name) = call.option("--crate-name").filter(|n| *n != "___") else {
        return Ok(());
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let path = dir.join(format!("{name}.json"));
    let text = serde_json::to_string_pretty(&call).expect("a record serialises");
    std::fs::write(&path, text).map_err(io(&path))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_read_in_both_spellings() {
        let call = RustcCall {
            args: ["--crate-name", "lab02", "--edition=2024", "--out-dir", "/x"]
                .map(String::from)
                .to_vec(),
            env: Vec::new(),
        };
        assert_eq!(call.option("--crate-name"), Some("lab02"));
        assert_eq!(call.option("--edition"), Some("2024"));
        assert_eq!(call.option("--out-dir"), Some("/x"));
        assert_eq!(call.option("--target"), None);
    }
}

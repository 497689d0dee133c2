//! The crates `raylab grade` writes into its tree for each graded lab, so that a submission's
//! code runs in WebAssembly apart from the checks (docs/architecture.md, "Graded code runs in
//! WebAssembly"):
//!
//! - `labs/labNN/guest`: the lab crate compiled to a `wasm32` module, one line of code
//!   (`raylab_guest::serve!`);
//! - `labs/labNN/graded`: the lab's graded program, [`graded_program!`]: the lab's checks, with
//!   every exercise (hidden ones too) and the answer keys, calling the student's code only
//!   through the module [`MODULE_VAR`] names. It does not depend on the lab crate, so
//!   it is built once per grading and no student code is ever compiled into it.

use std::io;
use std::path::Path;

/// The environment variable that names, for a graded program, the student's module (a
/// `.wasm` file, or a `.cwasm` file the program precompiled).
pub const MODULE_VAR: &str = "RAYLAB_STUDENT_MODULE";

/// The environment variable that names, for a graded program, its lab's directory (golden data,
/// snapshots): the grader gives it relative to the exercise's directory, so that no message
/// names a place of its machine. Without it, the directory the program was built from.
pub const LAB_DIR_VAR: &str = "RAYLAB_LAB_DIR";

/// The lab directory of a graded program built from `built`: [`LAB_DIR_VAR`]'s, when set.
pub fn lab_dir(built: &'static str) -> &'static str {
    match std::env::var(LAB_DIR_VAR) {
        Ok(dir) => Box::leak(dir.into_boxed_str()),
        Err(_) => built,
    }
}

/// The environment variable that asks a graded program to compile the module of
/// [`MODULE_VAR`] to the `.cwasm` file it names, and end.
pub const PRECOMPILE_VAR: &str = "RAYLAB_PRECOMPILE";

/// The whole of a graded program, `labs/labNN/graded/main.rs`:
/// `grading::graded_program!(lab03, lab03_checks, reference, wasm_host);`: the lab, its checks,
/// the answer key and the runtime of the student's module, each a crate of the program's own
/// manifest.
#[macro_export]
macro_rules! graded_program {
    ($lab:ident, $checks:ident, $key:ident, $host:ident) => {
        fn main() {
            if let Some(out) = ::std::env::var_os($crate::graded::PRECOMPILE_VAR) {
                let wasm = ::std::env::var_os($crate::graded::MODULE_VAR).unwrap_or_default();
                let compiled = $host::StudentModule::precompile(
                    ::std::path::Path::new(&wasm),
                    ::std::path::Path::new(&out),
                );
                if let Err(e) = compiled {
                    eprintln!("error: {e}");
                    ::std::process::exit(1);
                }
                ::std::process::exit(0);
            }
            let lab = $checks::checks::LAB;
            let subject: ::std::sync::Arc<::contracts::$lab::Contract> = ::std::sync::Arc::new(
                ::contracts::wire::Remote::<::contracts::$lab::Contract>::new(
                    ::std::sync::Arc::new($host::ModuleFromEnv::new($crate::graded::MODULE_VAR)),
                ),
            );
            $crate::harness::run($crate::harness::LabChecks {
                lab,
                lab_dir: $crate::graded::lab_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/..")),
                exercises: $checks::checks::exercises(),
                subject,
                base: $key::pipeline(lab.number()),
                key_labs: $key::KEYS,
                hidden: true,
                report: None,
                generate_golden: $checks::generate_golden,
            })
        }
    };
}

fn manifest(package: &str, lib_or_bin: &str, dependencies: &[(&str, &Path)]) -> String {
    let mut text = format!(
        "[package]\nname = \"{package}\"\nversion.workspace = true\nedition.workspace = true\n\
         publish = false\n\n{lib_or_bin}\n[dependencies]\n"
    );
    for (name, path) in dependencies {
        text.push_str(&format!(
            "{name} = {{ path = \"{}\" }}\n",
            path.display().to_string().replace('\\', "/")
        ));
    }
    text
}

/// The file name of lab `lab`'s module built by a guest crate of [`write_guest_crate`] with
/// `tag` (in `wasm32-unknown-unknown/<profile>/` of the target directory).
pub fn module_file(lab: &str, tag: &str) -> String {
    format!("{lab}_guest_{tag}.wasm")
}

/// The name of lab `lab`'s graded program written by [`write_graded_crate`] with `tag`.
pub fn program_name(lab: &str, tag: &str) -> String {
    format!("{lab}-graded-{tag}")
}

/// Writes the guest crate of lab `lab` (e.g. "lab03") into `dir`: a `cdylib` package
/// `{lab}-guest` that depends on the lab crate at `lab_dir` and on `contracts` and
/// `raylab-guest` in `framework`. Built for `wasm32-unknown-unknown`, it is
/// [`module_file`]`(lab, tag)`: cargo puts the builds of every tree that shares a target
/// directory at one place, so each grading names its own by a `tag` of its own. With
/// `standalone`, the crate is a workspace of its own, with the package fields written out.
pub fn write_guest_crate(
    dir: &Path,
    lab: &str,
    tag: &str,
    lab_dir: &Path,
    framework: &Path,
    standalone: bool,
) -> io::Result<()> {
    let module = module_file(lab, tag);
    let library = module.trim_end_matches(".wasm");
    let mut text = manifest(
        &format!("{lab}-guest"),
        &format!("[lib]\nname = \"{library}\"\ncrate-type = [\"cdylib\"]\npath = \"lib.rs\"\n"),
        &[
            (lab, lab_dir),
            ("contracts", &framework.join("contracts")),
            ("raylab-guest", &framework.join("guest")),
        ],
    );
    if standalone {
        text = text
            .replace("version.workspace = true", "version = \"0.1.0\"")
            .replace("edition.workspace = true", "edition = \"2024\"");
        text.push_str("\n[workspace]\n");
    }
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("Cargo.toml"), text)?;
    std::fs::write(
        dir.join("lib.rs"),
        format!(
            "//! {lab} compiled to WebAssembly for grading (written by `raylab grade`).\n\
             raylab_guest::serve!({lab}::Student as contracts::{lab}::Contract);\n"
        ),
    )
}

/// Writes the graded program of lab `lab` into `dir` (`labs/labNN/graded` of a tree whose
/// framework is `framework` and whose answer key is `reference`): a package `{lab}-graded`
/// whose binary [`program_name`]`(lab, tag)` is one line, [`graded_program!`].
pub fn write_graded_crate(
    dir: &Path,
    lab: &str,
    tag: &str,
    checks_dir: &Path,
    framework: &Path,
    reference: &Path,
) -> io::Result<()> {
    let text = manifest(
        &format!("{lab}-graded"),
        &format!(
            "[[bin]]\nname = \"{}\"\npath = \"main.rs\"\n",
            program_name(lab, tag)
        ),
        &[
            (&format!("{lab}-checks"), checks_dir),
            ("contracts", &framework.join("contracts")),
            ("grading", &framework.join("grading")),
            ("wasm-host", &framework.join("wasm-host")),
            ("reference", reference),
        ],
    );
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join("Cargo.toml"), text)?;
    std::fs::write(
        dir.join("main.rs"),
        format!(
            "//! The graded program of {lab} (written by `raylab grade`).\n\
             grading::graded_program!({lab}, {lab}_checks, reference, wasm_host);\n"
        ),
    )
}

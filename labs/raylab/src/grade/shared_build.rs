//! What every submission of a grading shares, built before the first submission's clock
//! starts: each graded lab's graded program (its checks with the answer key, calling the
//! student's code in its module), and the crates a lab compiles against for WebAssembly, built
//! from the handout's stubs while the compiler's command lines are recorded
//! ([`super::rustc_record`]); then the build jail ([`super::jail`]) that holds those crates.
//! All of it is the course's own code: no student code is in the tree while cargo runs, and
//! a failure here is the grader's, reported before any submission is graded.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

use course::LabId;
use raylab_core::Error;

use super::jail::{self, Jail};
use super::lab_build::LabCalls;
use super::runner::{compiler_errors, run_captured};
use super::rustc_record::{self, RustcCall};
use super::sandbox::Sandbox;
use crate::handout::io;

/// Where cargo runs: the grading tree and the target directory shared by every submission (so
/// the framework is compiled once per class, not once per student).
pub struct Workspace {
    /// The grading tree (`raylab handout` with the hidden tests and the whole answer key); its
    /// labs keep the handout's stubs.
    pub tree: PathBuf,
    /// `CARGO_TARGET_DIR` of the builds.
    pub target: PathBuf,
    /// Where each exercise runs, in an empty directory of its own.
    pub runs: PathBuf,
    /// The build jail's directory.
    pub jail: PathBuf,
    /// What the grading's builds are named by (`grading::graded`): unique to its directory, so
    /// that gradings sharing a target directory never take each other's programs or modules.
    pub tag: String,
    /// The sandbox builds and exercises run in.
    pub sandbox: Sandbox,
    /// How long one compiler run of a submission's build may take.
    pub build_timeout: Duration,
}

/// What the submissions of a grading share.
pub struct Shared {
    /// Each graded lab's graded program.
    pub programs: BTreeMap<LabId, PathBuf>,
    /// How each graded lab and its module are compiled.
    pub calls: BTreeMap<LabId, LabCalls>,
    /// The jail that compiles them.
    pub jail: Jail,
}

/// How long the shared build may take: the framework and wasmtime, from a cold target
/// directory on a slow machine.
const SHARED_BUILD_LIMIT: Duration = Duration::from_secs(4 * 3600);

impl Workspace {
    /// Writes the guest and graded crates into the tree and fetches its dependencies, before
    /// any student code is anywhere near it.
    pub fn prepare(&self) -> Result<(), Error> {
        let this = std::env::current_exe().map_err(io(Path::new("raylab")))?;
        let recorder = self.recorder();
        let _ = fs::remove_file(&recorder);
        if fs::hard_link(&this, &recorder).is_err() {
            fs::copy(&this, &recorder).map_err(io(&this))?;
        }
        self.write_graded_crates()?;
        let output = self
            .cargo(&["fetch", "--quiet"])
            .output()
            .map_err(io(&self.tree))?;
        if !output.status.success() {
            return Err(Error::Failed {
                what: format!("cargo fetch in {}", self.tree.display()),
                reason: String::from_utf8_lossy(&output.stderr).trim().to_string(),
            });
        }
        // Under `--run-as`, the exercises' user cannot read the answer key's source.
        for secret in ["reference", "tests"] {
            let dir = self.tree.join(secret);
            if dir.exists() {
                self.sandbox.hide_from_exercises(&dir)?;
            }
        }
        fs::create_dir_all(&self.target).map_err(io(&self.target))
    }

    /// The copy of this program that records the compiler's command lines, made when the
    /// grading starts (the program itself may be built again while it grades).
    fn recorder(&self) -> PathBuf {
        self.jail.with_file_name("rustc-recorder")
    }

    /// Builds what the submissions share for `labs` ([`Shared`]).
    pub fn build_shared(&self, labs: &[LabId]) -> Result<Shared, Error> {
        let programs = self.build_graded_programs(labs)?;
        let (calls, deps) = self.build_stubs_for_wasm(labs)?;
        let guests = labs
            .iter()
            .map(|&lab| {
                let path = self.tree.join(format!("labs/{lab}/guest/lib.rs"));
                fs::read_to_string(&path)
                    .map(|text| (lab, text))
                    .map_err(io(&path))
            })
            .collect::<Result<Vec<_>, Error>>()?;
        let sysroot = self.sandbox.sysroot();
        let host = jail::host_triple(sysroot)?;
        let jail = Jail::prepare(&self.jail, sysroot, &host, &deps, &guests)?;
        self.check_jail(&jail)?;
        Ok(Shared {
            programs,
            calls,
            jail,
        })
    }

    /// `cargo ARGS` in the tree, as the grader: the environment of this machine's builds and
    /// nothing of the caller's (`RUSTFLAGS`, a compiler wrapper), so that every grading shares
    /// one target directory's units.
    fn cargo(&self, args: &[&str]) -> Command {
        let sysroot = self.sandbox.sysroot();
        let mut command = Command::new(sysroot.join("bin/cargo"));
        command
            .args(args)
            .current_dir(&self.tree)
            .env_clear()
            .env(
                "PATH",
                format!("{}:/usr/bin:/bin", sysroot.join("bin").display()),
            )
            .env("CARGO_HOME", self.sandbox.cargo_home())
            .env("CARGO_TARGET_DIR", &self.target)
            .env(
                "HOME",
                std::env::var_os("HOME").unwrap_or_else(|| "/tmp".into()),
            )
            .env("CARGO_TERM_COLOR", "never")
            .stdin(Stdio::null());
        command
    }

    /// `cargo build --bins` of the graded programs of `labs` (`grading::graded`): the
    /// executable of each.
    fn build_graded_programs(&self, labs: &[LabId]) -> Result<BTreeMap<LabId, PathBuf>, Error> {
        let mut args = vec![
            "build",
            "--bins",
            "--offline",
            "--locked",
            "--message-format=json-render-diagnostics",
        ];
        let packages: Vec<String> = labs.iter().map(|l| format!("{l}-graded")).collect();
        for package in &packages {
            args.extend(["-p", package]);
        }
        let artifacts = self.build("the graded programs", self.cargo(&args))?;
        let mut programs = BTreeMap::new();
        for artifact in &artifacts {
            let program = |l: &LabId| grading::graded::program_name(&format!("{l}"), &self.tag);
            if let (Some(executable), Some(&lab)) = (
                &artifact.executable,
                labs.iter().find(|l| artifact.target == program(l)),
            ) {
                programs.insert(lab, executable.clone());
            }
        }
        match labs.iter().find(|l| !programs.contains_key(l)) {
            Some(lab) => Err(Error::Failed {
                what: format!("the graded program of {lab}"),
                reason: "cargo built it but named no executable".into(),
            }),
            None => Ok(programs),
        }
    }

    /// Builds `labs`' stubs and their guest crates for WebAssembly with the compiler's command
    /// lines recorded: each lab's [`LabCalls`], and the files of the crates they compile
    /// against (every crate of the build but the labs and their guests).
    fn build_stubs_for_wasm(
        &self,
        labs: &[LabId],
    ) -> Result<(BTreeMap<LabId, LabCalls>, Vec<PathBuf>), Error> {
        // The stubs' sources newer than their last build: cargo compiles them again, and so
        // runs the compiler whose command line is recorded.
        for &lab in labs {
            touch_tree(&self.tree.join(format!("labs/{lab}/src")))?;
        }
        let records = self.jail.with_extension("records");
        if records.exists() {
            fs::remove_dir_all(&records).map_err(io(&records))?;
        }
        let mut args = vec![
            "build",
            "--lib",
            "--offline",
            "--locked",
            "--target",
            jail::WASM,
            "--message-format=json-render-diagnostics",
        ];
        let packages: Vec<String> = labs.iter().map(|l| format!("{l}-guest")).collect();
        for package in &packages {
            args.extend(["-p", package]);
        }
        // Registry crates' paths as `/cargo/…` in what is compiled into a module (a panic's
        // location), not this machine's.
        let remap = format!(
            "target.{}.rustflags=[{}]",
            jail::WASM,
            serde_json::to_string(&format!(
                "--remap-path-prefix={}=/cargo",
                self.sandbox.cargo_home().display()
            ))
            .expect("a string serialises")
        );
        args.extend(["--config", &remap]);
        let mut command = self.cargo(&args);
        command
            .env("RUSTC_WORKSPACE_WRAPPER", self.recorder())
            .env(rustc_record::RECORD_VAR, &records);
        let artifacts = self.build("the labs' stubs for WebAssembly", command)?;
        let mut calls = BTreeMap::new();
        let mut crates = Vec::new();
        for &lab in labs {
            let guest = grading::graded::module_file(&format!("{lab}"), &self.tag);
            let guest = guest.trim_end_matches(".wasm").to_string();
            calls.insert(
                lab,
                LabCalls {
                    lab: RustcCall::load(&records, &format!("{lab}"))?,
                    guest: RustcCall::load(&records, &guest)?,
                },
            );
            crates.push(format!("{lab}"));
            crates.push(guest);
        }
        let wasm_dir = self.target.join(jail::WASM);
        let deps = artifacts
            .into_iter()
            .filter(|a| !crates.contains(&a.target))
            .filter(|a| a.proc_macro || a.files.iter().any(|f| f.starts_with(&wasm_dir)))
            .flat_map(|a| a.files)
            .collect();
        Ok((calls, deps))
    }

    /// Runs `command` (a `cargo build` with JSON messages), the shared build named `what`: its
    /// artifacts, or an error with the compiler's messages.
    fn build(&self, what: &str, command: Command) -> Result<Vec<Artifact>, Error> {
        let run = run_captured(command, None, SHARED_BUILD_LIMIT, usize::MAX)?;
        let text = String::from_utf8_lossy(&run.output);
        let artifacts: Vec<Artifact> = text.lines().filter_map(Artifact::parse).collect();
        match run.status {
            Some(status) if status.success() => Ok(artifacts),
            _ => Err(Error::Failed {
                what: format!("building {what} (in {})", self.tree.display()),
                reason: format!(
                    "the grader's own build failed, before any submission was graded:\n{}",
                    compiler_errors(
                        &text
                            .lines()
                            .filter(|l| !l.starts_with('{'))
                            .collect::<Vec<_>>()
                            .join("\n")
                    )
                ),
            }),
        }
    }

    /// Runs the jail's compiler once (`rustc -vV`) as a submission's build would run it: a
    /// machine that cannot isolate a build says so before any submission is graded.
    fn check_jail(&self, jail: &Jail) -> Result<(), Error> {
        jail.clear()?;
        fs::create_dir_all(jail.out()).map_err(io(&jail.out()))?;
        let output = self
            .sandbox
            .jailed(jail.root(), &["-vV".to_string()], &[])
            .output();
        let _ = jail.clear();
        let why = match output {
            Ok(o) if o.status.success() => return Ok(()),
            Ok(o) => String::from_utf8_lossy(&o.stderr).trim().to_string(),
            Err(e) => e.to_string(),
        };
        Err(Error::Failed {
            what: "isolating the builds".into(),
            reason: format!(
                "a submission's build cannot be isolated on this machine, so nothing is graded: the compiler did not start in the jail ({why}); bubblewrap needs user namespaces, and --run-as needs root with the right to chroot"
            ),
        })
    }
}

/// One `compiler-artifact` message of cargo.
struct Artifact {
    /// The target's name (`lab02`, `contracts`, …).
    target: String,
    /// Whether the target is a procedural macro (a library of the host).
    proc_macro: bool,
    /// The files cargo wrote for it.
    files: Vec<PathBuf>,
    /// The executable, for a binary.
    executable: Option<PathBuf>,
}

impl Artifact {
    fn parse(line: &str) -> Option<Self> {
        let message: serde_json::Value = serde_json::from_str(line).ok()?;
        if message["reason"] != "compiler-artifact" {
            return None;
        }
        let kinds = message["target"]["kind"].as_array()?;
        if kinds.iter().any(|k| k == "custom-build") {
            return None;
        }
        Some(Self {
            target: message["target"]["name"].as_str()?.to_string(),
            proc_macro: kinds.iter().any(|k| k == "proc-macro"),
            files: message["filenames"]
                .as_array()?
                .iter()
                .filter_map(|f| f.as_str().map(PathBuf::from))
                .collect(),
            executable: message["executable"].as_str().map(PathBuf::from),
        })
    }
}

/// Sets the modification time of every file under `dir` to now.
fn touch_tree(dir: &Path) -> Result<(), Error> {
    let now = std::time::SystemTime::now();
    for entry in fs::read_dir(dir).map_err(io(dir))? {
        let path = entry.map_err(io(dir))?.path();
        if path.is_dir() {
            touch_tree(&path)?;
        } else {
            fs::File::options()
                .write(true)
                .open(&path)
                .and_then(|f| f.set_modified(now))
                .map_err(io(&path))?;
        }
    }
    Ok(())
}

impl Workspace {
    /// Writes, for each lab crate of the tree, its guest crate (the lab compiled to a
    /// WebAssembly module) and its graded program (`grading::graded`).
    fn write_graded_crates(&self) -> Result<(), Error> {
        let framework = self.tree.join("framework");
        let mut members = String::new();
        for lab in course::labs() {
            let name = format!("{lab}");
            let lab_dir = self.tree.join("labs").join(&name);
            if !lab_dir.join("Cargo.toml").is_file() {
                continue;
            }
            let guest = lab_dir.join("guest");
            grading::graded::write_guest_crate(
                &guest, &name, &self.tag, &lab_dir, &framework, false,
            )
            .map_err(io(&guest))?;
            let graded = lab_dir.join("graded");
            grading::graded::write_graded_crate(
                &graded,
                &name,
                &self.tag,
                &lab_dir.join("checks"),
                &framework,
                &self.tree.join("reference"),
            )
            .map_err(io(&graded))?;
            members.push_str(&format!(
                "    \"labs/{name}/guest\",\n    \"labs/{name}/graded\",\n"
            ));
        }
        if members.is_empty() {
            return Ok(());
        }
        let manifest = self.tree.join("Cargo.toml");
        let text = fs::read_to_string(&manifest).map_err(io(&manifest))?;
        let Some(at) = text.find("    \"labs/*/checks\",\n") else {
            return Err(Error::Failed {
                what: manifest.display().to_string(),
                reason: "its workspace members have no line `\"labs/*/checks\",`".into(),
            });
        };
        let mut text = text;
        text.insert_str(at, &members);
        fs::write(&manifest, text).map_err(io(&manifest))
    }
}

//! One submission's lab compiled to its WebAssembly module in the build jail ([`super::jail`]):
//! the lab crate, then the guest crate that links it, each with the command line cargo used
//! for the handout's stubs ([`super::rustc_record`]) with its paths moved into the jail. The
//! compiler sees the submission's sources, the prebuilt crates and the toolchain, nothing
//! else; it writes only the build's own output directory.

use std::path::{Path, PathBuf};
use std::time::Duration;

use course::LabId;
use raylab_core::Error;

use super::jail::{self, Jail};
use super::runner::{compiler_errors, run_captured};
use super::rustc_record::RustcCall;
use super::sandbox::Sandbox;

/// How cargo compiled a lab for WebAssembly: its crate and the guest crate around it.
#[derive(Clone, Debug)]
pub struct LabCalls {
    /// The lab crate (`labs/labNN/src/lib.rs`).
    pub lab: RustcCall,
    /// The guest crate (`labs/labNN/guest/lib.rs`), a `cdylib`: the module.
    pub guest: RustcCall,
}

/// What a build of a submission's lab came to.
#[derive(Debug)]
pub enum Built {
    /// The module, copied out of the jail to where it was asked for.
    Module,
    /// The compiler rejected the code: its messages.
    DoesNotCompile(String),
    /// The grader could not finish the build (its time limit, a resource limit, a crash of
    /// the compiler): why, with the figures. Not the student's compile error.
    NotGraded(String),
}

/// Where one lab's build runs and what bounds it.
pub struct LabBuild<'a> {
    /// The sandbox that runs the compiler.
    pub sandbox: &'a Sandbox,
    /// The jail it runs in.
    pub jail: &'a Jail,
    /// The host paths the recorded command lines name: the grading tree, the target directory.
    pub host: HostPaths<'a>,
    /// The time limit of one compiler run (doubled for its one retry).
    pub timeout: Duration,
    /// The address space of a compiler run, for the message when it is reached.
    pub memory: u64,
}

/// The places on this machine that recorded command lines name and a jailed build must not.
#[derive(Clone, Copy)]
pub struct HostPaths<'a> {
    /// The grading tree, cargo's workspace: the build's working directory becomes `/build`.
    pub tree: &'a Path,
    /// Cargo's target directory: its `deps/` directories become `/deps`.
    pub target: &'a Path,
    /// Anything else no argument may keep (cargo's home, the grading directory, `HOME`).
    pub private: &'a [PathBuf],
}

impl LabBuild<'_> {
    /// Compiles the directory `src` (the submission's `labs/labNN/src/` as intake took it) as
    /// lab `lab` with `calls`, and copies the module to `to`.
    pub fn build(
        &self,
        lab: LabId,
        calls: &LabCalls,
        src: &Path,
        to: &Path,
    ) -> Result<Built, Error> {
        let outcome = self.build_in_jail(lab, calls, src, to);
        self.jail.clear()?;
        outcome
    }

    fn build_in_jail(
        &self,
        lab: LabId,
        calls: &LabCalls,
        src: &Path,
        to: &Path,
    ) -> Result<Built, Error> {
        // A run stopped at the time limit may be the machine's load: once more, with twice the
        // time; stopped again, the grader's limit, not the code's mistake.
        for attempt in 1..=2 {
            let timeout = self.timeout * attempt;
            match self.attempt(lab, calls, src, timeout)? {
                Step::Built => {
                    let module = self.jail.out().join(module_file(&calls.guest)?);
                    crate::handout::copy_file(&module, to)?;
                    return Ok(Built::Module);
                }
                Step::Failed(built) => return Ok(built),
                Step::Stopped(_) if attempt == 1 => {}
                Step::Stopped(what) => {
                    return Ok(Built::NotGraded(format!(
                        "the build of {what} did not finish within {} s and was stopped, after a first attempt stopped at {} s: the grader's time limit, not a compile error (grade again with a longer --build-timeout)",
                        timeout.as_secs(),
                        self.timeout.as_secs()
                    )));
                }
            }
        }
        unreachable!("the second attempt returns")
    }

    /// Stages the sources and runs the lab's and the guest's compiler runs, each within
    /// `timeout`.
    fn attempt(
        &self,
        lab: LabId,
        calls: &LabCalls,
        src: &Path,
        timeout: Duration,
    ) -> Result<Step, Error> {
        let root = self.sandbox.jail_root(self.jail.root());
        let lab_name = calls
            .lab
            .option("--crate-name")
            .unwrap_or_default()
            .to_string();
        self.jail.stage(lab, src, self.sandbox.build_owner())?;
        for (what, call) in [
            ("the lab's crate", &calls.lab),
            ("the module around it", &calls.guest),
        ] {
            let (args, env) = in_jail(call, &self.host, &root, &lab_name, lab)?;
            let command = self.sandbox.jailed(self.jail.root(), &args, &env);
            let run = run_captured(command, None, timeout, COMPILER_OUTPUT_LIMIT);
            self.sandbox.end_exercise();
            let run = run?;
            match run.status {
                Some(status) if status.success() => {}
                Some(status) => {
                    let text = String::from_utf8_lossy(&run.output);
                    return Ok(Step::Failed(self.failed(what, status, &text, timeout)));
                }
                None => return Ok(Step::Stopped(what)),
            }
        }
        Ok(Step::Built)
    }

    /// What a compiler run that ended with `status` and printed `text` means: the code's
    /// errors, or the grader's limits.
    fn failed(
        &self,
        what: &str,
        status: std::process::ExitStatus,
        text: &str,
        timeout: Duration,
    ) -> Built {
        use std::os::unix::process::ExitStatusExt;
        // bubblewrap passes a signal on as the exit status 128 + N.
        let signal = status.signal().or_else(|| {
            status
                .code()
                .filter(|c| (129..=128 + 64).contains(c))
                .map(|c| c - 128)
        });
        let memory = self.memory >> 20;
        if text.contains("memory allocation of") || text.contains("failed to allocate") {
            return Built::NotGraded(format!(
                "the compiler ran out of memory building {what} (the limit is {memory} MiB of address space): a resource limit of the grader, not a compile error"
            ));
        }
        match (signal, status.code()) {
            (Some(libc::SIGXCPU), _) => Built::NotGraded(format!(
                "the compiler used up its CPU time building {what} (about {} s): a resource limit of the grader, not a compile error",
                timeout.as_secs()
            )),
            (Some(signal), _) => Built::NotGraded(format!(
                "the compiler was stopped by signal {signal} building {what} (the limits: {memory} MiB of address space, {} s): not a compile error",
                timeout.as_secs()
            )),
            (None, Some(101)) => Built::NotGraded(format!(
                "the compiler crashed building {what} (an internal compiler error, not a mistake in the code):\n{}",
                compiler_errors(text)
            )),
            (None, _) if what == "the lab's crate" => Built::DoesNotCompile(compiler_errors(text)),
            (None, _) => Built::DoesNotCompile(format!(
                "the lab's code compiles, but not as the course's contract (was a public item renamed or removed?):\n{}",
                compiler_errors(text)
            )),
        }
    }
}

/// How one attempt at a build ended.
enum Step {
    /// Both compiler runs succeeded.
    Built,
    /// A compiler run failed: what that means.
    Failed(Built),
    /// The compiler run of this part was stopped at the time limit.
    Stopped(&'static str),
}

/// Output kept of one compiler run.
const COMPILER_OUTPUT_LIMIT: usize = 1 << 20;

/// The module a guest crate's compiler run writes (its crate name, `.wasm`).
fn module_file(guest: &RustcCall) -> Result<String, Error> {
    guest
        .option("--crate-name")
        .map(|name| format!("{name}.wasm"))
        .ok_or_else(|| Error::Failed {
            what: "the guest crate's compiler record".into(),
            reason: "it has no --crate-name".into(),
        })
}

/// A compiler run's environment variables.
type Environment = Vec<(String, String)>;

/// `call`'s arguments and variables with its paths moved into the jail seen from `root`:
/// sources relative to `/build` as they were to the tree, prebuilt crates in `/deps` (the lab
/// crate `lab_name` itself in `/build/out`), output to `/build/out`, the toolchain's sysroot
/// `/toolchain`; cargo's incremental state, JSON messages and colours dropped. A path of this
/// machine left in an argument is the grader's error: nothing of it may reach the build.
fn in_jail(
    call: &RustcCall,
    host: &HostPaths,
    root: &Path,
    lab_name: &str,
    lab: LabId,
) -> Result<(Vec<String>, Environment), Error> {
    let inside = |path: &str| root.join(path).to_string_lossy().into_owned();
    let deps = inside(jail::DEPS);
    let out = inside(jail::OUT);
    let mut args = Vec::new();
    let mut given = call.args.iter();
    let mut deps_named = false;
    while let Some(arg) = given.next() {
        let (name, value) = match arg.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n, Some(v.to_string())),
            _ => (arg.as_str(), None),
        };
        let take = |given: &mut std::slice::Iter<String>| {
            value
                .clone()
                .or_else(|| given.next().cloned())
                .unwrap_or_default()
        };
        match name {
            "--error-format" | "--json" | "--color" | "--remap-path-prefix" => {
                take(&mut given);
            }
            "--out-dir" => {
                take(&mut given);
                args.extend(["--out-dir".to_string(), out.clone()]);
            }
            "-C" => {
                let codegen = take(&mut given);
                if !codegen.starts_with("incremental=") {
                    args.extend(["-C".to_string(), codegen]);
                }
            }
            "-L" => {
                let search = take(&mut given);
                if search.starts_with("dependency=") {
                    if !deps_named {
                        args.extend(["-L".to_string(), format!("dependency={deps}")]);
                        deps_named = true;
                    }
                } else {
                    args.extend(["-L".to_string(), search]);
                }
            }
            "--extern" => {
                let named = take(&mut given);
                let moved = match named.split_once('=') {
                    Some((crate_name, path)) => {
                        let file = Path::new(path)
                            .file_name()
                            .unwrap_or_default()
                            .to_string_lossy();
                        let dir = if crate_name == lab_name { &out } else { &deps };
                        format!("{crate_name}={dir}/{file}")
                    }
                    None => named,
                };
                args.extend(["--extern".to_string(), moved]);
            }
            _ => args.push(arg.clone()),
        }
    }
    args.extend([
        "--error-format=human".to_string(),
        "--color=never".to_string(),
        "--sysroot".to_string(),
        inside(jail::TOOLCHAIN),
    ]);
    let build = inside(jail::BUILD);
    let mut env = Vec::new();
    // What `env!` may read of cargo's: the package's fields and where it is. Not the jobserver
    // (`CARGO_MAKEFLAGS`), whose descriptors the jail does not pass on, nor cargo's own path.
    let kept = |key: &str| {
        key.starts_with("CARGO_PKG_")
            || matches!(
                key,
                "CARGO_CRATE_NAME"
                    | "CARGO_MANIFEST_DIR"
                    | "CARGO_MANIFEST_PATH"
                    | "CARGO_PRIMARY_PACKAGE"
            )
    };
    for (key, value) in call.env.iter().filter(|(key, _)| kept(key)) {
        let value = match key.as_str() {
            // The grading's own version tag is no part of the course's crate.
            "CARGO_PKG_VERSION" => value.split("-grading.").next().unwrap_or(value).to_string(),
            "CARGO_PKG_VERSION_PRE" if value.starts_with("grading.") => String::new(),
            _ => value.replace(&*host.tree.to_string_lossy(), &build),
        };
        // cargo's own path and the like: nothing the build needs.
        if is_host_path(&value, host) && !value.starts_with(&build) {
            continue;
        }
        env.push((key.clone(), value));
    }
    // Unsandboxed, the jail's own files are named where they are on this machine.
    let isolated = root == Path::new("/");
    if let Some(arg) = args.iter().find(|a| isolated && is_host_path(a, host)) {
        return Err(Error::Failed {
            what: format!("the compiler record of {lab}"),
            reason: format!(
                "an argument names a place of this machine, which the build may not see: {arg}"
            ),
        });
    }
    Ok((args, env))
}

/// Whether `text` names the tree, the target directory or another private place of the host.
fn is_host_path(text: &str, host: &HostPaths) -> bool {
    std::iter::once(host.tree)
        .chain(std::iter::once(host.target))
        .chain(host.private.iter().map(PathBuf::as_path))
        .filter(|p| p.as_os_str().len() > 1)
        .any(|p| text.contains(&*p.to_string_lossy()))
        || text.contains("/.rustup/")
        || text.contains("/.cargo/")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn call(args: &[&str], env: &[(&str, &str)]) -> RustcCall {
        RustcCall {
            args: args.iter().map(|a| a.to_string()).collect(),
            env: env
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
        }
    }

    #[test]
    fn a_recorded_command_line_is_moved_into_the_jail() {
        let tree = Path::new("/g/.grading/tree");
        let target = Path::new("/g/target");
        let host = HostPaths {
            tree,
            target,
            private: &[PathBuf::from("/root")],
        };
        let recorded = call(
            &[
                "--crate-name",
                "lab02_guest_0badf00d",
                "--edition=2024",
                "labs/lab02/guest/lib.rs",
                "--error-format=json",
                "--json=diagnostic-rendered-ansi,artifacts,future-incompat",
                "--crate-type",
                "cdylib",
                "-C",
                "incremental=/g/target/wasm32-unknown-unknown/debug/incremental",
                "--out-dir",
                "/g/target/wasm32-unknown-unknown/debug/deps",
                "-L",
                "dependency=/g/target/wasm32-unknown-unknown/debug/deps",
                "-L",
                "dependency=/g/target/debug/deps",
                "--extern",
                "lab02=/g/target/wasm32-unknown-unknown/debug/deps/liblab02-1.rlib",
                "--extern",
                "contracts=/g/target/wasm32-unknown-unknown/debug/deps/libcontracts-2.rlib",
                "--remap-path-prefix=/root/.cargo/registry/src=/registry",
                "--forbid=unsafe_code",
            ],
            &[
                ("CARGO", "/root/.rustup/toolchains/x/bin/cargo"),
                (
                    "CARGO_MAKEFLAGS",
                    "-j --jobserver-fds=8,9 --jobserver-auth=8,9",
                ),
                ("CARGO_MANIFEST_DIR", "/g/.grading/tree/labs/lab02/guest"),
                ("CARGO_PKG_VERSION", "0.1.0-grading.0badf00d"),
                ("CARGO_PKG_VERSION_PRE", "grading.0badf00d"),
                ("CARGO_CRATE_NAME", "lab02_guest_0badf00d"),
            ],
        );
        let (args, env) = in_jail(&recorded, &host, Path::new("/"), "lab02", LabId::of(2)).unwrap();
        assert_eq!(
            args,
            [
                "--crate-name",
                "lab02_guest_0badf00d",
                "--edition=2024",
                "labs/lab02/guest/lib.rs",
                "--crate-type",
                "cdylib",
                "--out-dir",
                "/build/out",
                "-L",
                "dependency=/deps",
                "--extern",
                "lab02=/build/out/liblab02-1.rlib",
                "--extern",
                "contracts=/deps/libcontracts-2.rlib",
                "--forbid=unsafe_code",
                "--error-format=human",
                "--color=never",
                "--sysroot",
                "/toolchain",
            ]
        );
        assert_eq!(
            env,
            [
                (
                    "CARGO_MANIFEST_DIR".into(),
                    "/build/labs/lab02/guest".into()
                ),
                ("CARGO_PKG_VERSION".into(), "0.1.0".into()),
                ("CARGO_PKG_VERSION_PRE".into(), String::new()),
                ("CARGO_CRATE_NAME".into(), "lab02_guest_0badf00d".into()),
            ]
        );
        // Unsandboxed the jail's own files are named where they are.
        let (args, _) = in_jail(
            &recorded,
            &host,
            Path::new("/g/.grading/jail"),
            "lab02",
            LabId::of(2),
        )
        .unwrap();
        assert!(
            args.contains(&"dependency=/g/.grading/jail/deps".to_string()),
            "{args:?}"
        );
    }

    #[test]
    fn a_host_path_left_in_a_command_line_is_refused() {
        let host = HostPaths {
            tree: Path::new("/g/.grading/tree"),
            target: Path::new("/g/target"),
            private: &[],
        };
        let recorded = call(&["--crate-name", "lab02", "-Clink-arg=/g/target/x.o"], &[]);
        let error = in_jail(&recorded, &host, Path::new("/"), "lab02", LabId::of(2))
            .unwrap_err()
            .to_string();
        assert!(error.contains("/g/target/x.o"), "{error}");
    }
}

//! Where student code is built and run: a bubblewrap sandbox with resource limits.
//!
//! Every `cargo` build of a submission and every exercise's test process runs inside
//! `bwrap` (Debian's `bubblewrap`) with new user, mount, PID, network, IPC and UTS namespaces:
//! no network, no capabilities, no nested namespaces, a fresh `/dev` and `/tmp`, and of the
//! machine's files only the system's libraries and what the step needs, read-only:
//!
//! - a **build** sees the toolchain, cargo's registry cache, the grading tree (read-only) and
//!   the target directory (read-write: only the compiler writes there, since a lab crate has
//!   no build script or procedural macro of the student's);
//! - an **exercise** sees its test executable and its lab's directory (golden data,
//!   snapshots) read-only, and its own fresh scratch directory read-write — no `/proc`, no
//!   toolchain, no grading tree, no other student's files, no reports.
//!
//! Both get limits through `prlimit` (address space, CPU seconds, file size, open files, no
//! core dumps) and, where this user may create one, a `pids` control group that bounds the
//! number of processes (`RLIMIT_NPROC` does that for a user other than root). With
//! `--unshare-pid` and `--die-with-parent`, the whole sandbox — every process the student's
//! code started, detached or not — ends when its first process does or is killed.
//!
//! Without bubblewrap, `raylab grade` refuses to run unless told `--unsandboxed`; then the
//! limits still apply, processes run in a process group of their own that is killed at the
//! end, and every report says that the run was not sandboxed.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use framework::Error;

/// Resource limits of one build or exercise.
#[derive(Clone, Debug)]
pub struct Limits {
    /// Address space of an exercise's process, bytes.
    pub memory: u64,
    /// Address space of each compiler process, bytes.
    pub build_memory: u64,
    /// Processes (and threads) at once.
    pub processes: u64,
    /// Largest file an exercise's process may write, bytes.
    pub file_size: u64,
    /// Largest file a build may write, bytes: the framework's library with its checks for
    /// every lab is larger than anything an exercise needs to write.
    pub build_file_size: u64,
    /// CPU seconds of an exercise's process.
    pub cpu_seconds: u64,
}

/// How student code is isolated.
pub struct Sandbox {
    /// `bwrap`, or `None` when grading unsandboxed.
    bwrap: Option<PathBuf>,
    /// The toolchain's sysroot (`rustc --print sysroot`): its `bin/cargo` runs the builds.
    sysroot: PathBuf,
    /// Cargo's home, whose `registry/` the builds read.
    cargo_home: PathBuf,
    /// A `pids` control group the sandboxes are put in, if one could be made.
    pids_cgroup: Option<PathBuf>,
    limits: Limits,
}

/// Printed by an exercise's sandbox when the test left processes running.
pub const LINGERING: &str = "RAYLAB-SANDBOX: processes left running";

/// Directories of the system the sandboxes see read-only (those that exist).
const SYSTEM: &[&str] = &["/usr", "/bin", "/lib", "/lib64", "/lib32", "/sbin"];

/// Files of `/etc` a build needs: the dynamic linker's cache and the `cc` alternative.
const SYSTEM_ETC: &[&str] = &[
    "/etc/alternatives",
    "/etc/ld.so.cache",
    "/etc/ld.so.conf",
    "/etc/ld.so.conf.d",
];

impl Sandbox {
    /// The sandbox of this machine: bubblewrap, checked to start; `unsandboxed` only when the
    /// instructor asked for it. An error says what is missing and how to get it.
    pub fn new(unsandboxed: bool, limits: Limits) -> Result<Self, Error> {
        let bwrap = if unsandboxed {
            None
        } else {
            Some(find_bwrap()?)
        };
        let sysroot = toolchain_sysroot()?;
        let cargo_home = std::env::var_os("CARGO_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cargo")))
            .ok_or_else(|| Error::Invalid {
                what: "CARGO_HOME".into(),
                reason: "neither CARGO_HOME nor HOME is set: cannot find cargo's registry".into(),
            })?;
        let pids_cgroup = pids_cgroup(limits.processes);
        let sandbox = Self {
            bwrap,
            sysroot,
            cargo_home,
            pids_cgroup,
            limits,
        };
        if sandbox.bwrap.is_some() {
            sandbox.check_it_starts()?;
        }
        Ok(sandbox)
    }

    /// The address space an exercise may use, bytes.
    pub fn memory_limit(&self) -> u64 {
        self.limits.memory
    }

    /// Whether student code runs in bubblewrap.
    pub fn is_sandboxed(&self) -> bool {
        self.bwrap.is_some()
    }

    /// One line for the reports: how the code was isolated and limited.
    pub fn describe(&self) -> String {
        let l = &self.limits;
        let processes = if self.pids_cgroup.is_some() {
            format!("{} processes (pids control group)", l.processes)
        } else if is_root() {
            "processes not limited (no pids control group could be made)".to_string()
        } else {
            format!("{} processes (RLIMIT_NPROC)", l.processes)
        };
        let limits = format!(
            "{} MiB of address space, {} CPU seconds, files up to {} MiB (builds {} MiB), {processes}",
            l.memory >> 20,
            l.cpu_seconds,
            l.file_size >> 20,
            l.build_file_size >> 20
        );
        match self.bwrap {
            Some(_) => format!(
                "sandboxed with bubblewrap (no network, no /proc, nothing writable but a scratch directory; answer key, repository and other submissions not visible); {limits}"
            ),
            None => format!(
                "NOT SANDBOXED (--unsandboxed): student code ran as the grader's user with access to everything that user can read and write; {limits}"
            ),
        }
    }

    /// `cargo ARGS` in the grading tree `tree` with target directory `target`, the directories
    /// `hidden` replaced by empty ones (unsandboxed, they stay in view: the report says so).
    pub fn cargo(&self, tree: &Path, target: &Path, args: &[&str], hidden: &[PathBuf]) -> Command {
        let cargo = self.sysroot.join("bin/cargo");
        let path = format!("{}:/usr/bin:/bin", self.sysroot.join("bin").display());
        let Some(bwrap) = &self.bwrap else {
            let mut command = self.limited(
                &cargo,
                self.limits.build_memory,
                self.limits.build_file_size,
                None,
            );
            command
                .args(args)
                .current_dir(tree)
                .env("CARGO_TARGET_DIR", target)
                .env("CARGO_TERM_COLOR", "never")
                .env("PATH", path)
                .stdin(Stdio::null());
            return command;
        };
        let mut command = self.limited(
            bwrap,
            self.limits.build_memory,
            self.limits.build_file_size,
            None,
        );
        base_arguments(&mut command);
        command.args(["--proc", "/proc"]);
        for etc in SYSTEM_ETC {
            command.arg("--ro-bind-try").arg(etc).arg(etc);
        }
        let home = Path::new("/tmp/cargo-home");
        command
            .arg("--ro-bind")
            .arg(&self.sysroot)
            .arg(&self.sysroot)
            .arg("--dir")
            .arg(home)
            .arg("--ro-bind")
            .arg(self.cargo_home.join("registry"))
            .arg(home.join("registry"))
            .arg("--ro-bind-try")
            .arg(self.cargo_home.join("config.toml"))
            .arg(home.join("config.toml"))
            .arg("--ro-bind")
            .arg(tree)
            .arg(tree);
        for dir in hidden {
            command.arg("--tmpfs").arg(dir).arg("--remount-ro").arg(dir);
        }
        command
            .arg("--bind")
            .arg(target)
            .arg(target)
            .arg("--chdir")
            .arg(tree)
            .args(["--setenv", "PATH", &path])
            .arg("--setenv")
            .arg("CARGO_HOME")
            .arg(home)
            .arg("--setenv")
            .arg("CARGO_TARGET_DIR")
            .arg(target)
            .args(["--setenv", "HOME", "/tmp"])
            .args(["--setenv", "CARGO_TERM_COLOR", "never"])
            .arg("--")
            .arg(&cargo)
            .args(args)
            .stdin(Stdio::null());
        command
    }

    /// The test `executable ARGS` of lab directory `lab_dir`, in the scratch directory
    /// `scratch`, with `env` set.
    pub fn exercise(
        &self,
        executable: &Path,
        lab_dir: &Path,
        scratch: &Path,
        args: &[&str],
        env: &[(&str, &str)],
    ) -> Command {
        let cpu = Some(self.limits.cpu_seconds);
        let Some(bwrap) = &self.bwrap else {
            let mut command =
                self.limited(executable, self.limits.memory, self.limits.file_size, cpu);
            command
                .args(args)
                .current_dir(scratch)
                .env_clear()
                .env("PATH", "/usr/bin:/bin")
                .env("HOME", scratch)
                .envs(env.iter().copied());
            return command;
        };
        let mut command = self.limited(bwrap, self.limits.memory, self.limits.file_size, cpu);
        base_arguments(&mut command);
        command
            .arg("--ro-bind")
            .arg(executable)
            .arg(executable)
            .arg("--ro-bind")
            .arg(lab_dir)
            .arg(lab_dir)
            .arg("--bind")
            .arg(scratch)
            .arg(scratch)
            .arg("--chdir")
            .arg(scratch)
            .args(["--setenv", "PATH", "/usr/bin:/bin"])
            .arg("--setenv")
            .arg("HOME")
            .arg(scratch);
        for (key, value) in env {
            command.args(["--setenv", key, value]);
        }
        // bwrap's init is PID 1 and the shell PID 2: once the test has ended, `kill -0 -1`
        // succeeds only if a process the student's code started is still alive (the sandbox
        // then ends them all). A signal that ended the test is passed on as an exit status
        // 128 + N, as bwrap passes it on.
        command
            .arg("--")
            .arg("/bin/sh")
            .arg("-c")
            .arg(format!(
                "\"$@\"; status=$?; if kill -0 -1 2>/dev/null; then echo; echo '{LINGERING}'; fi; exit $status"
            ))
            .arg("sh")
            .arg(executable)
            .args(args);
        command
    }

    /// `program` under `prlimit` with the limits, at most `memory` bytes of address space and
    /// files of `file_size` bytes (and in the pids control group, if any).
    fn limited(&self, program: &Path, memory: u64, file_size: u64, cpu: Option<u64>) -> Command {
        let mut limits = vec![
            format!("--as={memory}"),
            format!("--fsize={file_size}"),
            "--core=0".to_string(),
            "--nofile=1024".to_string(),
        ];
        if let Some(cpu) = cpu {
            limits.push(format!("--cpu={cpu}"));
        }
        if !is_root() {
            limits.push(format!(
                "--nproc={}",
                self.limits.processes + processes_of_this_user()
            ));
        }
        let mut command = match &self.pids_cgroup {
            // The shell joins the control group, then becomes prlimit, then the program: all
            // they start is counted there.
            Some(cgroup) => {
                let mut c = Command::new("/bin/sh");
                c.arg("-c")
                    .arg("echo $$ > \"$0/cgroup.procs\" && exec \"$@\"")
                    .arg(cgroup)
                    .arg("prlimit");
                c
            }
            None => Command::new("prlimit"),
        };
        command.args(limits).arg("--").arg(program);
        command
    }

    /// Runs `true` in a sandbox like an exercise's, so that a machine where bubblewrap cannot
    /// make its namespaces says so before any submission is graded.
    fn check_it_starts(&self) -> Result<(), Error> {
        let scratch =
            std::env::temp_dir().join(format!("raylab-sandbox-check-{}", std::process::id()));
        fs::create_dir_all(&scratch).map_err(|e| Error::io(&scratch, e))?;
        let truth = Path::new("/bin/true");
        let output = self
            .exercise(truth, &scratch, &scratch, &[], &[])
            .stdin(Stdio::null())
            .output();
        let _ = fs::remove_dir(&scratch);
        match output {
            Ok(o) if o.status.success() => Ok(()),
            Ok(o) => Err(Error::Invalid {
                what: "the grading sandbox (bubblewrap)".into(),
                reason: format!(
                    "bwrap could not start a sandbox: {} — user namespaces may be disabled on this machine (kernel.unprivileged_userns_clone, or a container without them); fix that, or grade with --unsandboxed",
                    String::from_utf8_lossy(&o.stderr).trim()
                ),
            }),
            Err(e) => Err(Error::Invalid {
                what: "the grading sandbox (bubblewrap)".into(),
                reason: format!("could not run prlimit or bwrap: {e}"),
            }),
        }
    }
}

impl Drop for Sandbox {
    fn drop(&mut self) {
        if let Some(cgroup) = &self.pids_cgroup {
            let _ = fs::remove_dir(cgroup);
        }
    }
}

/// The namespaces and mounts every sandbox has.
fn base_arguments(command: &mut Command) {
    command.args([
        "--unshare-all",
        "--unshare-user",
        "--disable-userns",
        "--die-with-parent",
        "--new-session",
        "--cap-drop",
        "ALL",
        "--clearenv",
        "--dev",
        "/dev",
        "--tmpfs",
        "/tmp",
    ]);
    for dir in SYSTEM {
        command.args(["--ro-bind-try", dir, dir]);
    }
}

/// `bwrap` on the `PATH`, or an error saying how to install it.
fn find_bwrap() -> Result<PathBuf, Error> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join("bwrap"))
            .find(|p| p.is_file())
    });
    found.ok_or_else(|| Error::Invalid {
        what: "the grading sandbox".into(),
        reason: "bubblewrap (`bwrap`) is not installed: install it (Debian/Ubuntu: `apt-get install bubblewrap`), or pass --unsandboxed to run student code without isolation (the reports will say so)".into(),
    })
}

/// The sysroot of the toolchain that builds the grading tree.
fn toolchain_sysroot() -> Result<PathBuf, Error> {
    let output = Command::new("rustc")
        .args(["--print", "sysroot"])
        .stdin(Stdio::null())
        .output()
        .map_err(|e| Error::io(Path::new("rustc"), e))?;
    let sysroot = PathBuf::from(String::from_utf8_lossy(&output.stdout).trim());
    if !output.status.success() || !sysroot.join("bin/cargo").is_file() {
        return Err(Error::Invalid {
            what: "the Rust toolchain".into(),
            reason: format!(
                "`rustc --print sysroot` gave {:?}, which has no bin/cargo",
                sysroot.display()
            ),
        });
    }
    Ok(sysroot)
}

fn is_root() -> bool {
    // SAFETY: geteuid has no preconditions and cannot fail.
    unsafe { libc::geteuid() == 0 }
}

/// How many processes this user has now (RLIMIT_NPROC counts them all).
fn processes_of_this_user() -> u64 {
    use std::os::unix::fs::MetadataExt;
    // SAFETY: getuid has no preconditions and cannot fail.
    let uid = unsafe { libc::getuid() };
    fs::read_dir("/proc")
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .bytes()
                .all(|b| b.is_ascii_digit())
        })
        .filter(|e| e.metadata().is_ok_and(|m| m.uid() == uid))
        .count() as u64
}

/// A `pids` control group of its own with `pids.max = processes`, where this user may make
/// one (cgroup v1's `pids` hierarchy, or v2 with the controller enabled).
fn pids_cgroup(processes: u64) -> Option<PathBuf> {
    let name = format!("raylab-grade-{}", std::process::id());
    let v2 = Path::new("/sys/fs/cgroup");
    let candidates = [
        Path::new("/sys/fs/cgroup/pids").to_path_buf(),
        v2.to_path_buf(),
    ];
    for root in candidates {
        let v2_ready = fs::read_to_string(root.join("cgroup.subtree_control"))
            .is_ok_and(|c| c.split_whitespace().any(|c| c == "pids"));
        if root == v2 && !v2_ready {
            continue;
        }
        let dir = root.join(&name);
        if fs::create_dir(&dir).is_ok() {
            if fs::write(dir.join("pids.max"), processes.to_string()).is_ok() {
                return Some(dir);
            }
            let _ = fs::remove_dir(&dir);
        }
    }
    None
}

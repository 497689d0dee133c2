//! Where student code is built and run: bubblewrap sandboxes with resource limits.
//!
//! Every compiler run of a submission's build and every exercise's test process runs inside
//! `bwrap` (Debian's `bubblewrap`) with new user, mount, PID, network, IPC and UTS namespaces:
//! no network, no capabilities, no nested namespaces:
//!
//! - a **build** has the build jail (`super::jail`) as its whole file system, read-only but
//!   for its own output directory: the submission's sources, the prebuilt crates and the
//!   compiler; no `/proc`, no `/dev`, no `/etc`, no grading tree, no target directory;
//! - an **exercise** sees the system's libraries, its test executable and its lab's directory
//!   (golden data, snapshots) read-only, and its own fresh scratch directory read-write — no
//!   `/proc`, no toolchain, no grading tree, no other student's files, no reports.
//!
//! Both get limits through `prlimit` (address space, CPU seconds, file size, open files, no
//! core dumps) and, where this user may create one, a `pids` control group that bounds the
//! number of processes (`RLIMIT_NPROC` does that for a user other than root). With
//! `--unshare-pid` and `--die-with-parent`, the whole sandbox — every process the student's
//! code started, detached or not — ends when its first process does or is killed.
//!
//! Where bubblewrap cannot make its namespaces (a container without user namespaces, such as
//! Gradescope's), a grader running as root can use `--run-as USER` instead: a build runs as
//! that unprivileged user `chroot`ed into the build jail (the same file system as in
//! bubblewrap), and each exercise as that user under the same limits, in a scratch directory
//! it owns. It cannot write the grader's files (the test executables, the reports, the
//! results), nor read the answer key's source (made readable by root alone); when a build or
//! an exercise has ended, every process of that user is killed.
//!
//! Without either, `raylab grade` refuses to run unless told `--unsandboxed`; then the
//! limits still apply, processes run in a process group of their own that is killed at the
//! end, and every report says that the run was not sandboxed.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use raylab_core::Error;

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
    /// CPU seconds of one compiler run of a submission's build.
    pub build_cpu_seconds: u64,
}

/// The unprivileged account exercises run as under `--run-as`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunAs {
    /// The name it was given by (a user name, or a number).
    pub name: String,
    /// Its user id.
    pub uid: u32,
    /// Its primary group id.
    pub gid: u32,
}

impl RunAs {
    /// The account `user` (a name, or a numeric user id; a number's group is the same
    /// number), which must not be root.
    pub fn resolve(user: &str) -> Result<Self, Error> {
        let invalid = |reason: String| Error::Invalid {
            what: format!("--run-as {user}"),
            reason,
        };
        let (uid, gid) = match user.parse::<u32>() {
            Ok(uid) => (uid, uid),
            Err(_) => {
                let id = |flag: &str| -> Result<u32, Error> {
                    let out = Command::new("id")
                        .args([flag, user])
                        .stdin(Stdio::null())
                        .output()
                        .map_err(|e| Error::io(Path::new("id"), e))?;
                    String::from_utf8_lossy(&out.stdout)
                        .trim()
                        .parse()
                        .map_err(|_| invalid("no such user on this machine".into()))
                };
                (id("-u")?, id("-g")?)
            }
        };
        if uid == 0 || gid == 0 {
            return Err(invalid(
                "expected an unprivileged user, not root or the root group".into(),
            ));
        }
        Ok(Self {
            name: user.to_string(),
            uid,
            gid,
        })
    }

    /// `setpriv` arguments that become this user, with no supplementary groups.
    fn setpriv_args(&self) -> [String; 4] {
        [
            format!("--reuid={}", self.uid),
            format!("--regid={}", self.gid),
            "--clear-groups".to_string(),
            "--".to_string(),
        ]
    }
}

/// How student code is isolated.
pub struct Sandbox {
    /// `bwrap`, or `None` when grading unsandboxed or as another user.
    bwrap: Option<PathBuf>,
    /// The user exercises run as, without bubblewrap (`--run-as`).
    run_as: Option<RunAs>,
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

impl Sandbox {
    /// The sandbox of this machine: bubblewrap, checked to start; exercises as the user
    /// `run_as` instead, or `unsandboxed`, only when the instructor asked for it. An error says
    /// what is missing and how to get it.
    pub fn new(unsandboxed: bool, run_as: Option<RunAs>, limits: Limits) -> Result<Self, Error> {
        if run_as.is_some() && !is_root() {
            return Err(Error::Invalid {
                what: "--run-as".into(),
                reason: "running exercises as another user needs the grader to run as root".into(),
            });
        }
        let bwrap = if unsandboxed || run_as.is_some() {
            None
        } else {
            Some(find_bwrap()?)
        };
        let sysroot = toolchain_sysroot()?;
        let cargo_home = std::env::var_os("CARGO_HOME")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".cargo")))
            .ok_or_else(|| Error::Failed {
                what: "CARGO_HOME".into(),
                reason: "neither CARGO_HOME nor HOME is set: cannot find cargo's registry".into(),
            })?;
        let pids_cgroup = pids_cgroup(limits.processes);
        let sandbox = Self {
            bwrap,
            run_as,
            sysroot,
            cargo_home,
            pids_cgroup,
            limits,
        };
        if sandbox.bwrap.is_some() || sandbox.run_as.is_some() {
            sandbox.check_it_starts()?;
        }
        Ok(sandbox)
    }

    /// The address space an exercise may use, bytes.
    pub fn memory_limit(&self) -> u64 {
        self.limits.memory
    }

    /// The address space a compiler run of a submission's build may use, bytes.
    pub fn build_memory_limit(&self) -> u64 {
        self.limits.build_memory
    }

    /// The toolchain that builds the grading tree and whose compiler the build jail holds.
    pub fn sysroot(&self) -> &Path {
        &self.sysroot
    }

    /// Cargo's home, whose registry the shared builds read.
    pub fn cargo_home(&self) -> &Path {
        &self.cargo_home
    }

    /// Whether student code runs isolated: in bubblewrap, or as another user.
    pub fn is_sandboxed(&self) -> bool {
        self.bwrap.is_some() || self.run_as.is_some()
    }

    /// Makes `dir` (an exercise's scratch directory, just made) the exercise's own: under
    /// `--run-as`, owned by that user; otherwise nothing to do.
    pub fn give_scratch(&self, dir: &Path) -> Result<(), Error> {
        match &self.run_as {
            Some(user) => std::os::unix::fs::chown(dir, Some(user.uid), Some(user.gid))
                .map_err(|e| Error::io(dir, e)),
            None => Ok(()),
        }
    }

    /// Makes `dir` (the answer key's source in the grading tree) readable by the grader alone
    /// under `--run-as`; the builds, which read it, run as the grader.
    pub fn hide_from_exercises(&self, dir: &Path) -> Result<(), Error> {
        use std::os::unix::fs::PermissionsExt;
        match &self.run_as {
            Some(_) => fs::set_permissions(dir, fs::Permissions::from_mode(0o700))
                .map_err(|e| Error::io(dir, e)),
            None => Ok(()),
        }
    }

    /// Under `--run-as`, kills every process of that user: what a build or an exercise left
    /// running.
    pub fn end_exercise(&self) {
        if let Some(user) = &self.run_as {
            // `kill -1` as that user signals all its processes but the one sending.
            let _ = Command::new("setpriv")
                .args(user.setpriv_args())
                .args(["kill", "-KILL", "-1"])
                .stdin(Stdio::null())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .status();
        }
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
        if let Some(user) = &self.run_as {
            return format!(
                "built as the unprivileged user {} (uid {}; `--run-as`, not in bubblewrap) in a chroot that holds the submission's sources, the prebuilt crates and the compiler alone, and run as that user: could not write the grader's files nor read the answer key's source; {limits}",
                user.name, user.uid
            );
        }
        match self.bwrap {
            Some(_) => format!(
                "built and run in bubblewrap (no network, no /proc; the build saw the submission's sources, the prebuilt crates and the compiler alone; nothing writable but its own output and scratch directories; answer key, repository and other submissions not visible); {limits}"
            ),
            None => format!(
                "NOT SANDBOXED (--unsandboxed): student code was built and ran as the grader's user with access to everything that user can read and write; {limits}"
            ),
        }
    }

    /// The jail's compiler (`/toolchain/bin/rustc` in it) with `args` and `env`, run with the
    /// jail at `jail` as its whole file system ([`super::jail`]): its root bind-mounted
    /// read-only by bubblewrap, or `chroot` into it as the unprivileged user under `--run-as`;
    /// writable only `/build/out`. Unsandboxed, the jail's files are named by their paths on
    /// this machine ([`Self::jail_root`]) and nothing is hidden.
    pub fn jailed(&self, jail: &Path, args: &[String], env: &[(String, String)]) -> Command {
        let l = &self.limits;
        let root = self.jail_root(jail);
        let inside = |path: &str| root.join(path).to_string_lossy().into_owned();
        let mut vars = vec![
            ("LD_LIBRARY_PATH".to_string(), inside("toolchain/lib")),
            ("TMPDIR".to_string(), inside(super::jail::OUT)),
        ];
        vars.extend(env.iter().cloned());
        let rustc = root.join("toolchain/bin/rustc");
        if let Some(bwrap) = &self.bwrap {
            let mut command = self.limited(
                bwrap,
                l.build_memory,
                l.build_file_size,
                Some(l.build_cpu_seconds),
                false,
            );
            command
                .args([
                    "--unshare-all",
                    "--unshare-user",
                    "--disable-userns",
                    "--die-with-parent",
                    "--new-session",
                    "--cap-drop",
                    "ALL",
                    "--clearenv",
                ])
                .arg("--ro-bind")
                .arg(jail)
                .arg("/")
                .arg("--bind")
                .arg(jail.join(super::jail::OUT))
                .arg(Path::new("/").join(super::jail::OUT))
                .arg("--chdir")
                .arg(Path::new("/").join(super::jail::BUILD));
            for (key, value) in &vars {
                command.args(["--setenv", key, value]);
            }
            command
                .arg("--")
                .arg(&rustc)
                .args(args)
                .stdin(Stdio::null());
            return command;
        }
        let Some(user) = &self.run_as else {
            let mut command = self.limited(
                &rustc,
                l.build_memory,
                l.build_file_size,
                Some(l.build_cpu_seconds),
                false,
            );
            command
                .args(args)
                .current_dir(jail.join(super::jail::BUILD))
                .env_clear()
                .envs(vars)
                .stdin(Stdio::null());
            return command;
        };
        let mut command = Command::new(&rustc);
        command
            .args(args)
            .env_clear()
            .envs(vars)
            .stdin(Stdio::null());
        let limits = [
            (libc::RLIMIT_AS, l.build_memory),
            (libc::RLIMIT_FSIZE, l.build_file_size),
            (libc::RLIMIT_CPU, l.build_cpu_seconds),
            (libc::RLIMIT_CORE, 0),
            (libc::RLIMIT_NOFILE, 1024),
            (libc::RLIMIT_NPROC, l.processes + processes_of(user.uid)),
        ];
        let jail = std::ffi::CString::new(jail.as_os_str().as_encoded_bytes())
            .expect("a path has no NUL byte");
        let (uid, gid) = (user.uid, user.gid);
        let step = |ok: bool| {
            if ok {
                Ok(())
            } else {
                Err(std::io::Error::last_os_error())
            }
        };
        // SAFETY: between fork and exec only async-signal-safe calls on memory prepared before
        // the fork. Limits first, then the root (as root), then the unprivileged user, who
        // cannot leave the new root: it holds no directory outside and may not chroot again.
        unsafe {
            std::os::unix::process::CommandExt::pre_exec(&mut command, move || {
                for (resource, value) in limits {
                    let limit = libc::rlimit {
                        rlim_cur: value,
                        rlim_max: value,
                    };
                    step(libc::setrlimit(resource, &limit) == 0)?;
                }
                step(libc::chroot(jail.as_ptr()) == 0)?;
                step(libc::chdir(c"/build".as_ptr()) == 0)?;
                step(libc::setgroups(0, std::ptr::null()) == 0)?;
                step(libc::setgid(gid) == 0)?;
                step(libc::setuid(uid) == 0)?;
                Ok(())
            });
        }
        command
    }

    /// The directory under which a program in the jail at `jail` names the jail's files: `/`
    /// where it is its root, the jail itself when nothing is isolated (`--unsandboxed`).
    pub fn jail_root(&self, jail: &Path) -> PathBuf {
        if self.is_sandboxed() {
            PathBuf::from("/")
        } else {
            jail.to_path_buf()
        }
    }

    /// The user and group that own a build's output directory: the unprivileged user under
    /// `--run-as`.
    pub fn build_owner(&self) -> Option<(u32, u32)> {
        self.run_as.as_ref().map(|u| (u.uid, u.gid))
    }

    /// The CPU seconds an exercise's process may use.
    pub fn cpu_limit(&self) -> u64 {
        self.limits.cpu_seconds
    }

    /// The test `executable ARGS` of lab directory `lab_dir`, in the scratch directory
    /// `scratch`, with `env` set, and `cpu_seconds` of CPU time at most.
    pub fn exercise(
        &self,
        executable: &Path,
        lab_dir: &Path,
        scratch: &Path,
        args: &[&str],
        env: &[(&str, &str)],
        cpu_seconds: u64,
    ) -> Command {
        let cpu = Some(cpu_seconds);
        let Some(bwrap) = &self.bwrap else {
            let mut command = self.limited(
                executable,
                self.limits.memory,
                self.limits.file_size,
                cpu,
                true,
            );
            command
                .args(args)
                .current_dir(scratch)
                .env_clear()
                .env("PATH", "/usr/bin:/bin")
                .env("HOME", scratch)
                .envs(env.iter().copied());
            return command;
        };
        let mut command =
            self.limited(bwrap, self.limits.memory, self.limits.file_size, cpu, false);
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
    /// files of `file_size` bytes (and in the pids control group, if any); for student code
    /// (`student`) under `--run-as`, as that user.
    fn limited(
        &self,
        program: &Path,
        memory: u64,
        file_size: u64,
        cpu: Option<u64>,
        student: bool,
    ) -> Command {
        let as_user = self.run_as.as_ref().filter(|_| student);
        let mut limits = vec![
            format!("--as={memory}"),
            format!("--fsize={file_size}"),
            "--core=0".to_string(),
            "--nofile=1024".to_string(),
        ];
        if let Some(cpu) = cpu {
            limits.push(format!("--cpu={cpu}"));
        }
        // RLIMIT_NPROC counts the processes of the real user, which root is exempt from.
        if let Some(user) = as_user {
            limits.push(format!(
                "--nproc={}",
                self.limits.processes + processes_of(user.uid)
            ));
        } else if !is_root() {
            // SAFETY: getuid has no preconditions and cannot fail.
            let uid = unsafe { libc::getuid() };
            limits.push(format!(
                "--nproc={}",
                self.limits.processes + processes_of(uid)
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
        command.args(limits).arg("--");
        if let Some(user) = as_user {
            command.arg("setpriv").args(user.setpriv_args());
        }
        command.arg(program);
        command
    }

    /// Runs `true` in a sandbox like an exercise's, so that a machine where bubblewrap cannot
    /// make its namespaces (or `setpriv` is missing) says so before any submission is graded.
    fn check_it_starts(&self) -> Result<(), Error> {
        // One directory per check: sandboxes made at once in one process must not share it.
        static CHECKS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let n = CHECKS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let scratch =
            std::env::temp_dir().join(format!("raylab-sandbox-check-{}-{n}", std::process::id()));
        fs::create_dir_all(&scratch).map_err(|e| Error::io(&scratch, e))?;
        let truth = Path::new("/bin/true");
        let output = self.give_scratch(&scratch).and_then(|()| {
            self.exercise(truth, &scratch, &scratch, &[], &[], self.cpu_limit())
                .stdin(Stdio::null())
                .output()
                .map_err(|e| Error::io(Path::new("prlimit"), e))
        });
        let _ = fs::remove_dir(&scratch);
        let (what, fix) = match &self.run_as {
            Some(user) => (
                format!("--run-as {}", user.name),
                "setpriv (util-linux) could not become that user".to_string(),
            ),
            None => (
                "the grading sandbox (bubblewrap)".to_string(),
                "bwrap could not start a sandbox — user namespaces may be disabled on this machine (kernel.unprivileged_userns_clone, or a container without them); fix that, grade as root with --run-as USER, or grade with --unsandboxed".to_string(),
            ),
        };
        match output {
            Ok(o) if o.status.success() => Ok(()),
            Ok(o) => Err(Error::Failed {
                what,
                reason: format!("{fix}: {}", String::from_utf8_lossy(&o.stderr).trim()),
            }),
            Err(e) => Err(Error::Failed {
                what,
                reason: format!("could not start the sandbox's first process: {e}"),
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
    found.ok_or_else(|| Error::Failed {
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
        return Err(Error::Failed {
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

/// How many processes the user `uid` has now (RLIMIT_NPROC counts them all).
fn processes_of(uid: u32) -> u64 {
    use std::os::unix::fs::MetadataExt;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exercise_run_as_another_user_cannot_touch_the_graders_files_nor_outlive_its_end() {
        if !is_root() {
            // `--run-as` is refused without root (the next test); CI grades as root.
            return;
        }
        let dir = std::env::temp_dir().join(format!("raylab-run-as-{}", std::process::id()));
        let scratch = dir.join("scratch");
        fs::create_dir_all(&scratch).unwrap();
        let secret = dir.join("answer-key.rs");
        fs::write(&secret, "the answer").unwrap();
        fs::set_permissions(&secret, std::os::unix::fs::PermissionsExt::from_mode(0o600)).unwrap();
        let limits = Limits {
            memory: 1 << 30,
            build_memory: 1 << 30,
            processes: 64,
            file_size: 1 << 20,
            build_file_size: 1 << 20,
            cpu_seconds: 10,
            build_cpu_seconds: 10,
        };
        let user = RunAs::resolve("65534").unwrap();
        let sandbox = Sandbox::new(false, Some(user), limits).unwrap();
        assert!(sandbox.is_sandboxed() && sandbox.describe().contains("uid 65534"));
        sandbox.give_scratch(&scratch).unwrap();
        let script = format!(
            "id -u; cat {secret} 2>&1; echo forged > {forged} 2>&1; echo mine > own; sleep 300 >/dev/null 2>&1 & echo \"sleeper $!\"",
            secret = secret.display(),
            forged = dir.join("results.json").display(),
        );
        let output = sandbox
            .exercise(
                Path::new("/bin/sh"),
                &scratch,
                &scratch,
                &["-c", &script],
                &[],
                10,
            )
            .stdin(Stdio::null())
            .output()
            .unwrap();
        let printed = String::from_utf8_lossy(&output.stdout);
        assert!(printed.starts_with("65534\n"), "{printed}");
        assert!(!printed.contains("the answer"), "{printed}");
        assert!(!dir.join("results.json").exists(), "{printed}");
        assert_eq!(fs::read_to_string(scratch.join("own")).unwrap(), "mine\n");
        let sleeper = printed
            .lines()
            .find_map(|l| l.strip_prefix("sleeper "))
            .expect("the script started a process");
        // Alive: it exists and is not a zombie (which a container's init may not reap).
        let stat = Path::new("/proc").join(sleeper).join("stat");
        let alive = || fs::read_to_string(&stat).is_ok_and(|s| !s.contains(") Z "));
        assert!(alive(), "the process left running is alive before the end");
        sandbox.end_exercise();
        let gone = (0..100).any(|_| {
            std::thread::sleep(std::time::Duration::from_millis(20));
            !alive()
        });
        assert!(gone, "the process the exercise left running outlived it");
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn run_as_refuses_root_and_unknown_users() {
        let error = RunAs::resolve("0").unwrap_err().to_string();
        assert!(
            error.contains("--run-as 0") && error.contains("unprivileged"),
            "{error}"
        );
        let error = RunAs::resolve("no-such-user-here").unwrap_err().to_string();
        assert!(error.contains("no such user"), "{error}");
        let nobody = RunAs::resolve("65534").unwrap();
        assert_eq!((nobody.uid, nobody.gid), (65534, 65534));
    }
}

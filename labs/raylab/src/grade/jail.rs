//! The build jail: the one directory a submission's build sees as its whole file system.
//!
//! A student's code runs at compile time (macros, `include_str!`, `#[path]`, `env!`), so the
//! compiler that builds it must reach nothing worth reading. The jail holds only
//!
//! - `/toolchain`: the compiler, its libraries, the standard library for `wasm32` and the
//!   linker (a subset of the toolchain's sysroot);
//! - the system libraries those programs load, at their own paths (`ldd` names them);
//! - `/deps`: the prebuilt crates a lab compiles against (`contracts` and what it depends on,
//!   built from the handout's stubs before any submission) — nothing of the answer key;
//! - `/build/labs/labNN/guest/lib.rs`: the one line that makes a lab a module;
//! - for one build at a time, `/build/labs/labNN/src/` (the submission's sources) and
//!   `/build/out/` (the build's output, the only place it may write).
//!
//! No `/proc`, no `/dev`, no `/etc`, no `/tmp`, no home, no cargo, no grading tree, no target
//! directory, no other submission. [`super::sandbox`] runs the compiler with this directory as
//! its root: bind-mounted read-only by bubblewrap, or by `chroot` as an unprivileged user
//! under `--run-as`.

use std::fs;
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};

use course::LabId;
use raylab_core::Error;

use crate::handout::io;

/// The toolchain's place in the jail.
pub const TOOLCHAIN: &str = "toolchain";

/// The prebuilt crates' place in the jail.
pub const DEPS: &str = "deps";

/// The build's working directory in the jail: sources are named relative to it, as cargo names
/// them relative to the workspace.
pub const BUILD: &str = "build";

/// The build's output directory, the one writable place.
pub const OUT: &str = "build/out";

/// A build jail on disk.
pub struct Jail {
    root: PathBuf,
}

impl Jail {
    /// The jail at `root`, made from the toolchain at `sysroot` (host triple `host`) unless it
    /// already holds that toolchain; its prebuilt crates replaced by `deps` (files of the
    /// target directory), its guest crates by `guests` (each lab's `lib.rs`).
    pub fn prepare(
        root: &Path,
        sysroot: &Path,
        host: &str,
        deps: &[PathBuf],
        guests: &[(LabId, String)],
    ) -> Result<Self, Error> {
        let jail = Self {
            root: root.to_path_buf(),
        };
        let stamp = root.with_extension("stamp");
        let wanted = format!(
            "{}\n{host}\n{}\n",
            sysroot.display(),
            toolchain_version(sysroot)?
        );
        if fs::read_to_string(&stamp).ok().as_deref() != Some(wanted.as_str()) {
            if root.exists() {
                fs::remove_dir_all(root).map_err(io(root))?;
            }
            jail.install_toolchain(sysroot, host)?;
            fs::write(&stamp, &wanted).map_err(io(&stamp))?;
        }
        let dir = root.join(DEPS);
        if dir.exists() {
            fs::remove_dir_all(&dir).map_err(io(&dir))?;
        }
        make_dir(&dir)?;
        for file in deps {
            let name = file.file_name().ok_or_else(|| Error::Failed {
                what: file.display().to_string(),
                reason: "a prebuilt crate without a file name".into(),
            })?;
            copy(file, &dir.join(name))?;
        }
        let libraries: Vec<PathBuf> = deps
            .iter()
            .filter(|d| d.extension().is_some_and(|e| e == "so"))
            .cloned()
            .collect();
        jail.install_libraries_of(&libraries, sysroot)?;
        let build = root.join(BUILD);
        if build.exists() {
            fs::remove_dir_all(&build).map_err(io(&build))?;
        }
        for (lab, lib_rs) in guests {
            let guest = build.join(format!("labs/{lab}/guest"));
            make_dir(&guest)?;
            let path = guest.join("lib.rs");
            fs::write(&path, lib_rs).map_err(io(&path))?;
        }
        make_dir(&build)?;
        Ok(jail)
    }

    /// The jail's root directory on the host.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// Puts the directory `src` (a submission's `labs/labNN/src/` as intake took it: regular
    /// files and directories) in as lab `lab`'s sources, and an empty output directory, for one
    /// build; `owner` (a user and group id) owns the output directory, when the build runs as
    /// another user.
    pub fn stage(&self, lab: LabId, src: &Path, owner: Option<(u32, u32)>) -> Result<(), Error> {
        self.clear()?;
        copy_tree(
            src,
            &self.root.join(BUILD).join(format!("labs/{lab}/src")),
            &mut |_| {},
        )?;
        let out = self.root.join(OUT);
        make_dir(&out)?;
        if let Some((uid, gid)) = owner {
            std::os::unix::fs::chown(&out, Some(uid), Some(gid)).map_err(io(&out))?;
        }
        Ok(())
    }

    /// The output directory of the build on the host.
    pub fn out(&self) -> PathBuf {
        self.root.join(OUT)
    }

    /// Removes what one build staged and wrote: the next sees none of it.
    pub fn clear(&self) -> Result<(), Error> {
        let labs = self.root.join(BUILD).join("labs");
        for entry in fs::read_dir(&labs).into_iter().flatten().flatten() {
            let src = entry.path().join("src");
            if src.exists() {
                fs::remove_dir_all(&src).map_err(io(&src))?;
            }
        }
        let out = self.out();
        if out.exists() {
            fs::remove_dir_all(&out).map_err(io(&out))?;
        }
        Ok(())
    }

    /// Copies the parts of the toolchain a `wasm32` build uses, and the system libraries its
    /// programs load.
    fn install_toolchain(&self, sysroot: &Path, host: &str) -> Result<(), Error> {
        let toolchain = self.root.join(TOOLCHAIN);
        let rustc = sysroot.join("bin/rustc");
        copy(&rustc, &toolchain.join("bin/rustc"))?;
        let mut programs = vec![rustc];
        let lib = sysroot.join("lib");
        for entry in fs::read_dir(&lib).map_err(io(&lib))? {
            let path = entry.map_err(io(&lib))?.path();
            if path.is_file() {
                copy(
                    &path,
                    &toolchain
                        .join("lib")
                        .join(path.file_name().unwrap_or_default()),
                )?;
                programs.push(path);
            }
        }
        // The standard library for `wasm32`, and the linker (`rust-lld`, which rustc runs for
        // `wasm32`, and `gcc-ld/`, its wrappers).
        for (dir, executables) in [
            (format!("lib/rustlib/{WASM}/lib"), false),
            (format!("lib/rustlib/{host}/bin/gcc-ld"), true),
        ] {
            let from = sysroot.join(&dir);
            if !from.is_dir() {
                return Err(Error::Failed {
                    what: format!("the toolchain at {}", sysroot.display()),
                    reason: format!(
                        "it has no {dir}/ (install the target with `rustup target add {WASM}`)"
                    ),
                });
            }
            copy_tree(&from, &toolchain.join(&dir), &mut |file| {
                if executables {
                    programs.push(file.to_path_buf());
                }
            })?;
        }
        let lld = format!("lib/rustlib/{host}/bin/rust-lld");
        copy(&sysroot.join(&lld), &toolchain.join(&lld))?;
        programs.push(sysroot.join(lld));
        self.install_libraries_of(&programs, sysroot)
    }

    /// Installs the shared libraries `programs` load (as `ldd` finds them, the dynamic loader
    /// included), each at its own path with the symbolic links that lead to it; those of the
    /// toolchain at `sysroot` are in `/toolchain/lib` already.
    fn install_libraries_of(&self, programs: &[PathBuf], sysroot: &Path) -> Result<(), Error> {
        let sysroot = fs::canonicalize(sysroot).map_err(io(sysroot))?;
        for program in programs {
            for library in loaded_libraries(program, &sysroot.join("lib"))? {
                let real = fs::canonicalize(&library).map_err(io(&library))?;
                if !real.starts_with(&sysroot) {
                    self.install_host_path(&library)?;
                }
            }
        }
        Ok(())
    }

    /// Mirrors the host's absolute `path` into the jail: each symbolic link on the way made
    /// again (so that `/lib64/ld-linux-x86-64.so.2` resolves there as here), the file at its
    /// end copied.
    fn install_host_path(&self, path: &Path) -> Result<(), Error> {
        // Owned components still to walk, last first.
        let owned = |p: &Path| -> Vec<PathBuf> {
            p.components()
                .rev()
                .map(|c| PathBuf::from(c.as_os_str()))
                .collect()
        };
        let mut pending = owned(path);
        let mut at = PathBuf::from("/");
        let mut links = 0;
        while let Some(component) = pending.pop() {
            match component.components().next() {
                Some(Component::RootDir) => at = PathBuf::from("/"),
                Some(Component::ParentDir) => {
                    at.pop();
                }
                Some(Component::Normal(name)) => {
                    let next = at.join(name);
                    let meta = fs::symlink_metadata(&next).map_err(io(&next))?;
                    let inside = self.root.join(next.strip_prefix("/").unwrap_or(&next));
                    if meta.file_type().is_symlink() {
                        links += 1;
                        if links > 40 {
                            return Err(Error::Failed {
                                what: path.display().to_string(),
                                reason: "too many symbolic links".into(),
                            });
                        }
                        let target = fs::read_link(&next).map_err(io(&next))?;
                        if fs::symlink_metadata(&inside).is_err() {
                            if let Some(parent) = inside.parent() {
                                make_dir(parent)?;
                            }
                            std::os::unix::fs::symlink(&target, &inside).map_err(io(&inside))?;
                        }
                        pending.extend(owned(&target));
                    } else {
                        if pending.is_empty() && fs::symlink_metadata(&inside).is_err() {
                            copy(&next, &inside)?;
                        }
                        at = next;
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// The WebAssembly target labs are compiled to.
pub const WASM: &str = "wasm32-unknown-unknown";

/// `rustc -vV` of the toolchain at `sysroot`: what makes a jail's toolchain this one.
fn toolchain_version(sysroot: &Path) -> Result<String, Error> {
    let rustc = sysroot.join("bin/rustc");
    let output = Command::new(&rustc)
        .arg("-vV")
        .stdin(Stdio::null())
        .output()
        .map_err(io(&rustc))?;
    Ok(String::from_utf8_lossy(&output.stdout).into_owned())
}

/// The host triple of the toolchain at `sysroot`.
pub fn host_triple(sysroot: &Path) -> Result<String, Error> {
    let version = toolchain_version(sysroot)?;
    version
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .map(str::to_string)
        .ok_or_else(|| Error::Failed {
            what: format!("{} -vV", sysroot.join("bin/rustc").display()),
            reason: format!("no `host:` line in {version:?}"),
        })
}

/// The shared libraries `program` loads, by `ldd`: absolute paths, the loader among them; one
/// `ldd` cannot find is an error unless it is in `toolchain_lib` (the jail's `LD_LIBRARY_PATH`).
fn loaded_libraries(program: &Path, toolchain_lib: &Path) -> Result<Vec<PathBuf>, Error> {
    let output = Command::new("ldd")
        .arg(program)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| Error::Failed {
            what: "ldd".into(),
            reason: format!(
                "cannot run it to find the libraries the compiler loads ({e}); it is in Debian's libc-bin"
            ),
        })?;
    let text = String::from_utf8_lossy(&output.stdout);
    let mut libraries = Vec::new();
    for line in text.lines() {
        // `libc.so.6 => /lib/x86_64-linux-gnu/libc.so.6 (0x…)`, `/lib64/ld-linux-x86-64.so.2 (0x…)`,
        // `linux-vdso.so.1 (0x…)` (the kernel's, no file), `statically linked`.
        let path = match line.split_once("=>") {
            Some((_, right)) => right.split_whitespace().next(),
            None => line.split_whitespace().next(),
        };
        if let Some(path) = path.filter(|p| p.starts_with('/')) {
            libraries.push(PathBuf::from(path));
        } else if line.contains("not found")
            && !line
                .split_whitespace()
                .next()
                .is_some_and(|name| toolchain_lib.join(name).is_file())
        {
            return Err(Error::Failed {
                what: program.display().to_string(),
                reason: format!("a library it loads is missing: {}", line.trim()),
            });
        }
    }
    Ok(libraries)
}

/// Makes `dir` and its parents, readable by every user (the build may run as another one).
fn make_dir(dir: &Path) -> Result<(), Error> {
    use std::os::unix::fs::DirBuilderExt;
    fs::DirBuilder::new()
        .recursive(true)
        .mode(0o755)
        .create(dir)
        .map_err(io(dir))
}

/// Puts the file `from` at `to`: a hard link where the file systems allow, else a copy;
/// readable by every user either way.
fn copy(from: &Path, to: &Path) -> Result<(), Error> {
    use std::os::unix::fs::PermissionsExt;
    if let Some(parent) = to.parent() {
        make_dir(parent)?;
    }
    if fs::hard_link(from, to).is_ok() {
        return Ok(());
    }
    fs::copy(from, to).map_err(io(from))?;
    let mode = fs::metadata(from).map_err(io(from))?.permissions().mode();
    fs::set_permissions(to, fs::Permissions::from_mode((mode & 0o755) | 0o444)).map_err(io(to))
}

/// Copies the directory `from` to `to` (files and directories; symbolic links made again),
/// calling `each` with every file copied.
fn copy_tree(from: &Path, to: &Path, each: &mut dyn FnMut(&Path)) -> Result<(), Error> {
    make_dir(to)?;
    for entry in fs::read_dir(from).map_err(io(from))? {
        let entry = entry.map_err(io(from))?;
        let (path, target) = (entry.path(), to.join(entry.file_name()));
        let kind = entry.file_type().map_err(io(&path))?;
        if kind.is_dir() {
            copy_tree(&path, &target, each)?;
        } else if kind.is_symlink() {
            let link = fs::read_link(&path).map_err(io(&path))?;
            std::os::unix::fs::symlink(link, &target).map_err(io(&target))?;
        } else {
            copy(&path, &target)?;
            each(&path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grade::sandbox::{Limits, RunAs, Sandbox};

    /// A crate of one file, `src/lib.rs`, compiled for `wasm32` in the jail by `sandbox`: the
    /// compiler's output, and whether it succeeded.
    fn compile_in(sandbox: &Sandbox, jail: &Jail, lib_rs: &str) -> (bool, String) {
        let src = jail.root().with_extension("src");
        let _ = fs::remove_dir_all(&src);
        fs::create_dir_all(&src).unwrap();
        fs::write(src.join("lib.rs"), lib_rs).unwrap();
        jail.stage(LabId::of(2), &src, sandbox.build_owner())
            .unwrap();
        let root = sandbox.jail_root(jail.root());
        let args: Vec<String> = [
            "--crate-name",
            "lab02",
            "--edition=2024",
            "--crate-type",
            "cdylib",
            "--target",
            WASM,
            "labs/lab02/src/lib.rs",
            "--out-dir",
            &root.join(OUT).to_string_lossy(),
            "--sysroot",
            &root.join(TOOLCHAIN).to_string_lossy(),
            "--error-format=short",
        ]
        .map(String::from)
        .to_vec();
        let output = sandbox
            .jailed(
                jail.root(),
                &args,
                &[("CARGO_MANIFEST_DIR".into(), "/build/labs/lab02".into())],
            )
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        sandbox.end_exercise();
        let built = output.status.success() && jail.out().join("lab02.wasm").is_file();
        jail.clear().unwrap();
        (built, String::from_utf8_lossy(&output.stderr).into_owned())
    }

    /// Done when: a build of a submission, asked to read any file outside its own sources,
    /// fails to compile — in bubblewrap, and as another user in a chroot (as root).
    #[test]
    fn a_build_in_the_jail_reads_nothing_but_its_sources() {
        let test = "a_build_in_the_jail_reads_nothing_but_its_sources";
        if !grading::prerequisite::rust_target_or_skip(test, WASM) {
            return;
        }
        let mut sandboxes = Vec::new();
        let limits = Limits {
            memory: 1 << 30,
            build_memory: 4 << 30,
            processes: 64,
            file_size: 1 << 20,
            build_file_size: 256 << 20,
            cpu_seconds: 60,
            build_cpu_seconds: 120,
        };
        if grading::prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap") {
            sandboxes.push((
                "bubblewrap",
                Sandbox::new(false, None, limits.clone()).unwrap(),
            ));
        }
        // SAFETY: geteuid has no preconditions and cannot fail.
        if unsafe { libc::geteuid() } == 0 {
            let user = RunAs::resolve("65534").unwrap();
            sandboxes.push(("--run-as", Sandbox::new(false, Some(user), limits).unwrap()));
        }
        let dir = std::env::temp_dir().join(format!("raylab-jail-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        // Something only root may read, and a neighbour of the sources on this machine.
        let secret = dir.join("root-only.txt");
        fs::write(&secret, "SECRET").unwrap();
        fs::set_permissions(&secret, std::os::unix::fs::PermissionsExt::from_mode(0o600)).unwrap();
        let sysroot = sandboxes.first().map(|(_, s)| s.sysroot().to_path_buf());
        let Some(sysroot) = sysroot else {
            return;
        };
        let host = host_triple(&sysroot).unwrap();
        let jail = Jail::prepare(&dir.join("jail"), &sysroot, &host, &[], &[]).unwrap();
        let home = std::env::var("HOME").unwrap_or_default();
        let reads = [
            secret.to_string_lossy().into_owned(),
            dir.join("jail.stamp").to_string_lossy().into_owned(),
            env!("CARGO_MANIFEST_DIR").to_string() + "/Cargo.toml",
            "/proc/self/mountinfo".into(),
            "/proc/self/cmdline".into(),
            "/etc/ld.so.conf".into(),
            "/etc/passwd".into(),
            "/dev/zero".into(),
            format!("{home}/.cargo/config.toml"),
            format!("{}/bin/cargo", sysroot.display()),
            "../../../Cargo.toml".into(),
            "/build/out/../../toolchain/../build/labs/lab02/src/../../../../etc/passwd".into(),
        ];
        for (mode, sandbox) in &sandboxes {
            let (built, errors) = compile_in(
                sandbox,
                &jail,
                "pub const OWN: &str = include_str!(\"lib.rs\");\npub const DIR: &str = env!(\"CARGO_MANIFEST_DIR\");\n",
            );
            assert!(
                built,
                "{mode}: the sources do not build in the jail:\n{errors}"
            );
            for read in &reads {
                let (built, errors) = compile_in(
                    sandbox,
                    &jail,
                    &format!("pub const READ: &[u8] = include_bytes!({read:?});\n"),
                );
                assert!(!built, "{mode}: the build read {read}");
                assert!(errors.contains("couldn't read"), "{mode}: {read}: {errors}");
            }
            // bubblewrap sets `PWD` to the working directory: the jail's.
            let (built, errors) = compile_in(
                sandbox,
                &jail,
                "const fn same(a: &[u8], b: &[u8]) -> bool {\n    if a.len() != b.len() { return false; }\n    let mut i = 0;\n    while i < a.len() { if a[i] != b[i] { return false; } i += 1; }\n    true\n}\nconst _: () = assert!(match option_env!(\"PWD\") { None => true, Some(p) => same(p.as_bytes(), b\"/build\") });\n",
            );
            assert!(built, "{mode}: PWD names more than the jail:\n{errors}");
            for var in ["HOME", "CARGO_HOME", "PATH", "USER", "CARGO"] {
                let (built, errors) = compile_in(
                    sandbox,
                    &jail,
                    &format!("pub const VAR: &str = env!({var:?});\n"),
                );
                assert!(!built, "{mode}: the build has {var}: {errors}");
            }
        }
        fs::remove_dir_all(&dir).unwrap();
    }
}

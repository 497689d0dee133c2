//! The graded path: a lab crate compiled to WebAssembly (`raylab_guest::serve!`), run by
//! `wasm_host::StudentModule` and checked through its contract's wire, as `raylab grade` checks
//! a submission. The answer key compiled as a student's crate passes every exercise; the stubs
//! fail each cleanly; a panic, a runaway allocation and a stack overflow in the student's code
//! are that exercise's failure, with the student's message and line.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use contracts::wire::Remote;
use grading::corpus;
use wasm_host::StudentModule;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Compiles `lib_rs` as the code of the crate `lab` to WebAssembly, in a scratch project named
/// `name` under the target directory; the module's path.
fn compile(name: &str, lab: &str, lib_rs: &str) -> PathBuf {
    let root = root();
    let scratch = root.join("target/graded-wasm-tests");
    let dir = scratch.join(name);
    let student = dir.join("student");
    std::fs::create_dir_all(student.join("src")).unwrap();
    std::fs::write(
        student.join("Cargo.toml"),
        format!(
            "[package]\nname = \"{lab}\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n\
             [dependencies]\ncontracts = {{ path = \"{}\" }}\n\n\
             [lints.rust]\nunsafe_code = \"forbid\"\n",
            root.join("framework/contracts").display()
        ),
    )
    .unwrap();
    std::fs::write(student.join("src/lib.rs"), lib_rs).unwrap();
    let guest = dir.join("guest");
    grading::graded::write_guest_crate(
        &guest,
        lab,
        "test",
        &student,
        &root.join("framework"),
        true,
    )
    .unwrap();
    std::fs::copy(root.join("Cargo.lock"), guest.join("Cargo.lock")).unwrap();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = Command::new(cargo)
        .args([
            "build",
            "--quiet",
            "--release",
            "--target",
            "wasm32-unknown-unknown",
        ])
        .arg("--manifest-path")
        .arg(guest.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(scratch.join("target"))
        // The tests' own clippy wrapper (CI) has nothing to lint here.
        .env_remove("RUSTC_WORKSPACE_WRAPPER")
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "the guest of {name} does not build (is the target installed? \
         `rustup target add wasm32-unknown-unknown`):\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    scratch
        .join("target/wasm32-unknown-unknown/release")
        .join(grading::graded::module_file(lab, "test"))
}

/// The answer key of `lab` as a student's `src/lib.rs`.
fn key_as_student(lab: &str) -> String {
    let key = std::fs::read_to_string(root().join(format!("reference/src/{lab}.rs"))).unwrap();
    let name = format!("Lab{}", &lab[3..]);
    key.replace(&format!("struct {name};"), "struct Student;")
        .replace(&format!(" for {name} "), " for Student ")
}

fn stubs(lab: &str) -> String {
    std::fs::read_to_string(root().join(format!("labs/{lab}/src/lib.rs"))).unwrap()
}

#[test]
fn lab01_in_webassembly() {
    if !grading::prerequisite::rust_target_or_skip("lab01_in_webassembly", "wasm32-unknown-unknown")
    {
        return;
    }
    let checks = lab01_checks::checks::exercises();
    let lab = lab01_checks::checks::LAB;
    let ctx = corpus::context(
        lab,
        &root().join("labs/lab01").display().to_string(),
        reference::pipeline(lab.number()),
        reference::KEYS,
    );
    let run =
        |name: &str, lib_rs: &str, exercises: &[grading::Exercise<contracts::lab01::Contract>]| {
            let module = StudentModule::load(&compile(name, "lab01", lib_rs)).unwrap();
            let code: Arc<contracts::lab01::Contract> =
                Arc::new(Remote::<contracts::lab01::Contract>::new(Arc::new(module)));
            corpus::run_all(exercises, &code, &ctx)
        };
    corpus::assert_all_pass(run("lab01-key", &key_as_student("lab01"), &checks));
    // The same module compiled once to machine code, as the grader runs it.
    let wasm = compile("lab01-key", "lab01", &key_as_student("lab01"));
    let cwasm = wasm.with_extension("cwasm");
    StudentModule::precompile(&wasm, &cwasm).unwrap();
    // SAFETY: written just above by `precompile`.
    let module = unsafe { StudentModule::load_precompiled(&cwasm) }.unwrap();
    let code: Arc<contracts::lab01::Contract> =
        Arc::new(Remote::<contracts::lab01::Contract>::new(Arc::new(module)));
    corpus::assert_all_pass(corpus::run_all(&checks, &code, &ctx));
    corpus::assert_all_fail_cleanly(&checks, run("lab01-stubs", &stubs("lab01"), &checks));

    // A panic, a runaway allocation and a recursion without end in one exercise each.
    let hostile = key_as_student("lab01")
        .replacen(
            "fn field_of_view(&self, focal_distance: f32) -> f32 {",
            "fn field_of_view(&self, focal_distance: f32) -> f32 {\n\
             if focal_distance > 0.0 { panic!(\"the lens fell off at {focal_distance}\"); }",
            1,
        )
        .replacen(
            "fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {",
            "fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {\n\
             let mut hog: Vec<Vec<u8>> = Vec::new(); loop { hog.push(vec![1; 1 << 26]); }",
            1,
        )
        .replacen(
            "fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {",
            "fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {\n\
             if raster.x > -1.0 { return self.image_plane_coords(raster + Vec2::ONE, resolution) * raster; }",
            1,
        );
    // Not 1.6, whose render would run each of them for every pixel.
    let some: Vec<_> = lab01_checks::checks::exercises()
        .into_iter()
        .filter(|e| e.id != "1.6")
        .collect();
    let outcomes = run("lab01-hostile", &hostile, &some);
    let failure = |id: &str| {
        let (_, outcome) = outcomes.iter().find(|(e, _)| *e == id).unwrap();
        outcome.clone().expect_err(id)
    };
    let lens = failure("1.3");
    assert!(lens.contains("the lens fell off"), "{lens}");
    assert!(lens.contains("src/lib.rs"), "the student's line: {lens}");
    let hog = failure("1.5");
    assert!(hog.contains("ran out of memory"), "{hog}");
    let deep = failure("1.1");
    assert!(deep.contains("stack"), "{deep}");
    assert!(outcomes.iter().any(|(id, r)| *id == "1.2" && r.is_ok()));
}

#[test]
fn lab02_in_webassembly() {
    if !grading::prerequisite::rust_target_or_skip("lab02_in_webassembly", "wasm32-unknown-unknown")
    {
        return;
    }
    let checks = lab02_checks::checks::exercises();
    let lab = lab02_checks::checks::LAB;
    let ctx = corpus::context(
        lab,
        &root().join("labs/lab02").display().to_string(),
        reference::pipeline(lab.number()),
        reference::KEYS,
    );
    let module =
        StudentModule::load(&compile("lab02-key", "lab02", &key_as_student("lab02"))).unwrap();
    let code: Arc<contracts::lab02::Contract> =
        Arc::new(Remote::<contracts::lab02::Contract>::new(Arc::new(module)));
    corpus::assert_all_pass(corpus::run_all(&checks, &code, &ctx));
}

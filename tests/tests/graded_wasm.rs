//! The graded path: a lab crate compiled to WebAssembly (`raylab_guest::serve!`), run by
//! `wasm_host::StudentModule` and checked through its contract's wire, as `raylab grade` checks
//! a submission. The answer key compiled as a student's crate passes every exercise; the stubs
//! fail each cleanly; a panic, a runaway allocation and a stack overflow in the student's code
//! are that exercise's failure, with the student's message and line. In a process of an
//! exercise's limits (4 GiB of address space) the key passes labs 1 and 2 at 32 threads, and an
//! endless loop fails its own exercise alone, as a time-out, after a fixed budget of work; each
//! run of a check starts the student's code afresh.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use contracts::wire::Remote;
use grading::{FailureKind, Judge, Judgement, corpus};
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
    // A module file of its own for each name: the tests build their guests into one target
    // directory, at once.
    let tag = name.replace('-', "_");
    grading::graded::write_guest_crate(&guest, lab, &tag, &student, &root.join("framework"), true)
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
        .join(grading::graded::module_file(lab, &tag))
}

/// The answer key of `lab` as a student's `src/lib.rs`.
fn key_as_student(lab: &str) -> String {
    raylab_tests::workflow::correct_code(lab[3..].parse().unwrap())
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

/// Each run of a check starts the student's code afresh: a function that counts its calls in
/// a static answers the same in every run (`contracts::wire::begin_run`), so the code cannot
/// tell a re-judge from the first run.
#[test]
fn each_run_starts_the_student_s_code_afresh() {
    if !grading::prerequisite::rust_target_or_skip(
        "each_run_starts_afresh",
        "wasm32-unknown-unknown",
    ) {
        return;
    }
    let counting = key_as_student("lab01").replacen(
        "fn field_of_view(&self, focal_distance: f32) -> f32 {",
        "fn field_of_view(&self, focal_distance: f32) -> f32 {\n\
         static CALLS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);\n\
         if focal_distance < 0.0 { return (CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1) as f32; }",
        1,
    );
    let module = StudentModule::load(&compile("lab01-counting", "lab01", &counting)).unwrap();
    let code: Arc<contracts::lab01::Contract> =
        Arc::new(Remote::<contracts::lab01::Contract>::new(Arc::new(module)));
    contracts::wire::begin_run();
    let first = code.field_of_view(-1.0);
    // Within a run the statics live on, as natively.
    let again = code.field_of_view(-1.0);
    contracts::wire::begin_run();
    let next_run = code.field_of_view(-1.0);
    assert_eq!((first, again, next_run), (1.0, 2.0, 1.0));
}

/// The environment variable that hands a precompiled module to a test run in a process of its
/// own.
const MODULE_OF: &str = "RAYLAB_TEST_MODULE_";

/// The module of `lab` compiled from `lib_rs` and precompiled to machine code, as the grader
/// runs it: its path.
fn precompiled(name: &str, lab: &str, lib_rs: &str) -> PathBuf {
    let wasm = compile(name, lab, lib_rs);
    let cwasm = wasm.with_extension("cwasm");
    StudentModule::precompile(&wasm, &cwasm).unwrap();
    cwasm
}

/// The module a test in a process of its own was handed for `lab`.
fn handed(lab: &str) -> Arc<StudentModule> {
    let path = std::env::var_os(format!("{MODULE_OF}{lab}"))
        .unwrap_or_else(|| panic!("run by the test that hands it {lab}'s module"));
    // SAFETY: written by `precompiled` of the test that started this process.
    Arc::new(unsafe { StudentModule::load_precompiled(Path::new(&path)) }.unwrap())
}

/// Runs this program's test `name` alone, in a process of its own under the address-space
/// limit of an exercise's process in `raylab grade` (4096 MiB, `prlimit --as`), with the
/// modules `modules` handed to it and `env`; panics with its output unless it passes.
fn in_an_exercise_s_process(name: &str, modules: &[(&str, &Path)], env: &[(&str, &str)]) {
    let mut command = Command::new("prlimit");
    command
        .arg(format!("--as={}", 4096u64 << 20))
        .arg(std::env::current_exe().unwrap())
        .args([name, "--exact", "--include-ignored", "--nocapture"])
        .envs(env.iter().copied());
    for (lab, path) in modules {
        command.env(format!("{MODULE_OF}{lab}"), path);
    }
    let output = command.output().expect("prlimit (util-linux) runs");
    let printed = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    println!("{printed}");
    assert!(
        output.status.success(),
        "{name}: {}\n{printed}",
        output.status
    );
}

/// Every exercise of a lab (hidden ones too) judged on `code` as the grader judges it, each
/// alone (a judge of its own): its id, its judgement and its seconds.
fn judge_each<S: ?Sized + contracts::Mix + 'static>(
    exercises: Vec<grading::Exercise<S>>,
    code: &Arc<S>,
    ctx: grading::LabContext,
) -> Vec<(String, Judgement, f64)> {
    let table: Vec<Arc<grading::Exercise<S>>> = exercises.into_iter().map(Arc::new).collect();
    let ctx = Arc::new(ctx);
    table
        .iter()
        .map(|exercise| {
            let started = std::time::Instant::now();
            let judgement = Judge::new(&table, code, &ctx).judge(exercise);
            let seconds = started.elapsed().as_secs_f64();
            println!(
                "{} {:>7.2} s {}",
                exercise.id,
                seconds,
                match &judgement.outcome {
                    Ok(()) => format!("passed {:?}", judgement.key_for),
                    Err(f) => format!("{:?}: {}", f.kind, f.reason.lines().next().unwrap_or("")),
                }
            );
            (exercise.id.clone(), judgement, seconds)
        })
        .collect()
}

/// The context of a lab's checks with every key.
macro_rules! context {
    ($checks:ident) => {{
        let lab = $checks::checks::LAB;
        corpus::context(
            lab,
            &root().join(lab.folder()).display().to_string(),
            reference::pipeline(lab.number()),
            reference::KEYS,
        )
    }};
}

/// Lab `$lab`'s key compiled as a student's crate, judged exercise by exercise through the
/// module `$module`: each exercise's id, judgement and seconds.
macro_rules! judge_lab {
    ($lab:ident, $checks:ident, $module:expr) => {{
        let code: Arc<contracts::$lab::Contract> =
            Arc::new(Remote::<contracts::$lab::Contract>::new($module));
        judge_each($checks::checks::exercises(), &code, context!($checks))
    }};
}

/// Panics unless every exercise of `judged` passed on the student's code alone.
fn assert_all_passed(lab: &str, judged: &[(String, Judgement, f64)]) {
    for (id, judgement, _) in judged {
        assert_eq!(
            judgement,
            &Judgement {
                outcome: Ok(()),
                key_for: Vec::new(),
                note: String::new()
            },
            "{lab}: Exercise {id}"
        );
    }
}

/// An honest submission passes lab 1 (1.6, the render, included) and lab 2 (whose checks
/// render in parallel) in a process of an exercise's limits whatever the number of threads:
/// at 32 rendering threads the instances of the student's module are as few as at 2, where
/// one instance per thread, each reserving 256 MiB, ran out of the 4 GiB.
#[test]
fn an_honest_submission_passes_at_32_threads_in_4_gib() {
    if !grading::prerequisite::rust_target_or_skip(
        "an_honest_submission_passes_at_32_threads_in_4_gib",
        "wasm32-unknown-unknown",
    ) {
        return;
    }
    let lab01 = precompiled("lab01-key", "lab01", &key_as_student("lab01"));
    let lab02 = precompiled("lab02-key", "lab02", &key_as_student("lab02"));
    in_an_exercise_s_process(
        "honest_labs_1_and_2_alone",
        &[("lab01", &lab01), ("lab02", &lab02)],
        &[("RAYON_NUM_THREADS", "32")],
    );
}

/// Run by [`an_honest_submission_passes_at_32_threads_in_4_gib`] in a process of its own.
#[test]
#[ignore = "run in a process of its own by an_honest_submission_passes_at_32_threads_in_4_gib"]
fn honest_labs_1_and_2_alone() {
    assert_all_passed("lab01", &judge_lab!(lab01, lab01_checks, handed("lab01")));
    assert_all_passed("lab02", &judge_lab!(lab02, lab02_checks, handed("lab02")));
}

/// The seconds an exercise with an endless loop may take: a third of `raylab grade`'s default
/// time limit of 60 s (0.8 s for 1.1, 2.4 s for 1.6 on the 2-core machine).
const LOOP_SECONDS: f64 = 20.0;

/// An endless loop in `image_plane_coords` fails Exercise 1.1 alone, as a time-out that names
/// its budget, in the same way every time and far inside the grader's time limit; 1.6, whose
/// render calls it for every pixel, passes with the key's 1.1 in its place.
#[test]
fn an_endless_loop_times_out_its_own_exercise_alone() {
    if !grading::prerequisite::rust_target_or_skip(
        "an_endless_loop_times_out_its_own_exercise_alone",
        "wasm32-unknown-unknown",
    ) {
        return;
    }
    let looping = key_as_student("lab01").replacen(
        "fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {",
        "fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {\n\
         while std::hint::black_box(true) { std::hint::spin_loop(); }",
        1,
    );
    let module = precompiled("lab01-looping", "lab01", &looping);
    in_an_exercise_s_process("a_looping_lab_1_alone", &[("lab01", &module)], &[]);
}

/// Run by [`an_endless_loop_times_out_its_own_exercise_alone`] in a process of its own.
#[test]
#[ignore = "run in a process of its own by an_endless_loop_times_out_its_own_exercise_alone"]
fn a_looping_lab_1_alone() {
    let judged = judge_lab!(lab01, lab01_checks, handed("lab01"));
    for (id, judgement, seconds) in &judged {
        assert!(
            *seconds < LOOP_SECONDS,
            "Exercise {id} took {seconds:.1} s, more than {LOOP_SECONDS} s"
        );
        match id.as_str() {
            "1.1" => {
                let failure = judgement.outcome.as_ref().expect_err("1.1 loops");
                assert_eq!(failure.kind, FailureKind::TimedOut, "{}", failure.message);
                assert!(
                    failure.message.contains(contracts::wire::OUT_OF_WORK)
                        && failure.message.contains(&grouped(wasm_host::CALL_FUEL)),
                    "the message names the budget: {}",
                    failure.message
                );
            }
            "1.6" => assert_eq!(judgement.key_for, ["1.1"], "{:?}", judgement.outcome),
            _ => assert_eq!(judgement.outcome, Ok(()), "Exercise {id}"),
        }
        assert!(judgement.outcome.is_ok() || id == "1.1", "Exercise {id}");
    }
    // The same work and the same message every time.
    let again = judge_lab!(lab01, lab01_checks, handed("lab01"));
    assert_eq!(judged[0].1, again[0].1);
}

/// `n` with its digits in groups of three, as the messages write budgets.
fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// The measurement behind the budgets of work (`framework/wasm-host/src/budget.rs`): every
/// lab's key compiled as a student's crate and judged exercise by exercise, as the grader does;
/// prints per lab the calls, the most fuel one call and one run used and the slowest
/// exercise, and fails unless the budgets leave 10 times (a call) and 5 times (a run) that.
/// `cargo test -p raylab-tests --test graded_wasm every_lab_s_key -- --ignored --nocapture`
#[test]
#[ignore = "a measurement of some minutes: run by hand when a lab's checks or key change"]
fn every_lab_s_key_within_the_budgets() {
    let mut worst = wasm_host::Work::default();
    let mut lines = Vec::new();
    macro_rules! measure {
        ($($lab:ident, $checks:ident);* $(;)?) => {$({
            let name = stringify!($lab);
            let wasm = compile(&format!("{name}-key"), name, &key_as_student(name));
            let module = Arc::new(StudentModule::load(&wasm).unwrap());
            let judged = judge_lab!($lab, $checks, module.clone());
            assert_all_passed(name, &judged);
            let work = module.work();
            let (slowest, seconds) = judged
                .iter()
                .map(|(id, _, s)| (id.clone(), *s))
                .fold((String::new(), 0.0), |a, b| if b.1 > a.1 { b } else { a });
            lines.push(format!(
                "{name}: {} calls ({} nested), most in one call {:.2e}, in one run {:.2e}; \
                 slowest exercise {slowest} {seconds:.1} s",
                work.calls,
                work.nested_calls,
                work.most_in_one_call as f64,
                work.most_in_one_run as f64
            ));
            worst.most_in_one_call = worst.most_in_one_call.max(work.most_in_one_call);
            worst.most_in_one_run = worst.most_in_one_run.max(work.most_in_one_run);
        })*};
    }
    measure!(
        lab01, lab01_checks; lab02, lab02_checks; lab03, lab03_checks; lab04, lab04_checks;
        lab05, lab05_checks; lab06, lab06_checks; lab07, lab07_checks; lab08, lab08_checks;
        lab09, lab09_checks; lab10, lab10_checks; lab11, lab11_checks; lab12, lab12_checks;
    );
    println!("{}", lines.join("\n"));
    assert!(
        worst.most_in_one_call * 10 <= wasm_host::CALL_FUEL,
        "one call used {:.2e}",
        worst.most_in_one_call as f64
    );
    assert!(
        worst.most_in_one_run * 5 <= wasm_host::RUN_FUEL,
        "one run used {:.2e}",
        worst.most_in_one_run as f64
    );
}

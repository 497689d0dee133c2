//! The course's one list of labs (the registry `labs/course.toml`) and what is derived from it
//! agree: every lab has its crate, its docs page, a row in the README's table and its key in the
//! reference; every lab crate is on the list; exercise numbers belong to their lab; every lab's
//! program and corpus are the framework's one-line calls.

use std::collections::BTreeSet;
use std::fs;

use raylab_tests::workflow::{read, root, workspace_metadata};

#[test]
fn every_lab_of_the_course_has_its_crate_docs_and_readme_row() {
    let readme = read(&root().join("README.md"));
    for id in course::labs() {
        let lab = course::lab(id).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            root().join(id.folder()).join("Cargo.toml").is_file(),
            "no crate {}",
            id.folder()
        );
        assert!(root().join(id.docs()).is_file(), "no {}", id.docs());
        assert!(
            readme
                .lines()
                .any(|l| l.starts_with(&format!("| {id} |"))
                    && l.contains(&format!("({})", id.docs()))),
            "README.md's table has no row for {id} linking {}",
            id.docs()
        );
        assert!(
            reference::KEYS.contains(&id.number()),
            "reference::KEYS lacks lab {}",
            id.number()
        );
        assert!(!lab.exercises.is_empty(), "{id} has no exercises");
    }
    // The contracts' and the key's modules are their `src/labNN.rs` files: one per lab of the
    // registry, no more.
    let registered: Vec<String> = course::labs().iter().map(|l| l.to_string()).collect();
    for dir in ["framework/contracts/src", "reference/src"] {
        let mut files: Vec<String> = fs::read_dir(root().join(dir))
            .unwrap()
            .filter_map(|e| e.unwrap().file_name().into_string().ok())
            .filter_map(|n| n.strip_suffix(".rs").map(str::to_string))
            .filter(|n| n.starts_with("lab"))
            .collect();
        files.sort();
        assert_eq!(
            files, registered,
            "{dir}'s lab files are not the registry's labs"
        );
    }
}

#[test]
fn every_lab_crate_is_on_the_course_list() {
    for entry in fs::read_dir(root().join("labs")).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        let Ok(id) = name.parse::<course::LabId>() else {
            continue;
        };
        assert!(
            course::title(id).is_some(),
            "labs/{name} is not in labs/course.toml"
        );
    }
}

/// Each lab's program and corpus are the one line the scaffold writes, naming the lab's own
/// crates and the answer key's: the harness and the corpus tests are the framework's, not
/// copies (a corpus may say how its variants are the lab's code: `, code = change`).
#[test]
fn every_lab_has_its_program_and_its_corpus() {
    for lab in course::labs() {
        let dir = root().join(lab.folder());
        let call = |name: &str| format!("grading::{name}!({lab}, {lab}_checks, reference");
        let program = fs::read_to_string(dir.join("tests/checks.rs")).unwrap();
        let whole = format!("{});", call("lab_program"));
        assert!(
            program.contains(&whole),
            "{lab}/tests/checks.rs is not `{whole}`"
        );
        let corpus = fs::read_to_string(dir.join("tests/corpus.rs"))
            .unwrap_or_else(|e| panic!("{lab} has no mutant corpus tests/corpus.rs: {e}"));
        assert!(
            corpus.contains(&call("corpus_tests")),
            "{lab}/tests/corpus.rs does not end with `{}…);`",
            call("corpus_tests")
        );
    }
}

/// The lines `cargo tree --prefix none --format FORMAT ARGS` prints.
fn cargo_tree(format: &str, args: &[&str]) -> Vec<String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(["tree", "--locked", "--prefix", "none", "--format", format])
        .args(args)
        .current_dir(root())
        .output()
        .expect("cargo tree runs");
    assert!(
        output.status.success(),
        "cargo tree {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

/// Units as `cargo tree` names them: a package ("name v1.2.3") and its features.
type Units = BTreeSet<(String, Vec<String>)>;

/// The units (package and features) `cargo tree` lists for `args`: what cargo would build.
fn build_units(args: &[&str]) -> Units {
    cargo_tree("{p}|{f}", args)
        .iter()
        .filter_map(|line| {
            let (package, features) = line.split_once('|')?;
            let mut features: Vec<String> = features
                .replace("(*)", "")
                .split(',')
                .map(|f| f.trim().to_string())
                .filter(|f| !f.is_empty())
                .collect();
            features.sort();
            // "name v1.2.3 (path)" or "… (*)": the name and version say which package.
            let package: Vec<&str> = package.split_whitespace().take(2).collect();
            Some((package.join(" "), features))
        })
        .collect()
}

/// The units linked into what `args` builds: those reached through `edges` without passing
/// through a proc macro. The dev profile has `lto = "off"`, and cargo passes `-C lto=off` to these
/// but not to a unit only proc macros or build scripts need, so a unit on this side in one
/// command and not in another is compiled twice, and so is every crate compiled above it.
fn run_time_units(edges: &str, args: &[&str]) -> BTreeSet<(String, Vec<String>)> {
    let edges = format!("{edges},no-proc-macro");
    let mut all = vec!["-e", &edges];
    all.extend(args);
    build_units(&all)
}

/// The workspace's proc-macro crates, as `cargo tree` names them ("name v1.2.3").
fn workspace_proc_macros() -> BTreeSet<String> {
    let metadata: serde_json::Value = serde_json::from_slice(&workspace_metadata()).unwrap();
    metadata["packages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| {
            p["targets"].as_array().unwrap().iter().any(|t| {
                t["kind"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|k| k == "proc-macro")
            })
        })
        .map(|p| {
            format!(
                "{} v{}",
                p["name"].as_str().unwrap(),
                p["version"].as_str().unwrap()
            )
        })
        .collect()
}

/// The units of `units` linked into one command's programs and not into the other's, or the
/// other way round: each would be compiled twice.
fn run_time_disagreements<'a>(
    units: &'a BTreeSet<(String, Vec<String>)>,
    one: &BTreeSet<(String, Vec<String>)>,
    other: &BTreeSet<(String, Vec<String>)>,
) -> Vec<&'a (String, Vec<String>)> {
    units
        .iter()
        .filter(|u| one.contains(*u) != other.contains(*u))
        .collect()
}

/// The units of `needed` that `built` builds with other features: a package both build, whose
/// second build compiles it again (and everything above it).
fn built_again<'a>(
    needed: &'a BTreeSet<(String, Vec<String>)>,
    built: &BTreeSet<(String, Vec<String>)>,
) -> Vec<&'a (String, Vec<String>)> {
    let packages: BTreeSet<&String> = built.iter().map(|(p, _)| p).collect();
    needed
        .iter()
        .filter(|u| packages.contains(&u.0) && !built.contains(*u))
        .collect()
}

/// One build for everything a student runs: every unit `cargo test -p labNN` (which `raylab
/// status` runs too, for each lab's program) shares with `cargo run -p raylab` (the README's
/// first command) is built with the same features and the same `-C lto` — in the course
/// repository and in a handout, whose command line has no instructor features. A dependency
/// added to the command line with features the labs do not ask for, or one linked into it that
/// the labs need only at build time, breaks this; the framework's manifest ("One build") is
/// where to ask for them.
#[test]
fn a_lab_s_tests_reuse_the_command_line_s_build() {
    for cli in [&[][..], &["--no-default-features"][..]] {
        let mut args = vec!["-p", "raylab", "-e", "normal,build"];
        args.extend(cli);
        let built = build_units(&args);
        let mut cli_args = vec!["-p", "raylab"];
        cli_args.extend(cli);
        let cli_run_time = run_time_units("normal", &cli_args);
        for lab in course::labs() {
            let name = lab.to_string();
            let needed = build_units(&["-p", &name, "-e", "normal,build,dev"]);
            let missing = built_again(&needed, &built);
            assert!(
                missing.is_empty(),
                "`cargo test -p {name}` would build these again, with other features than `cargo run -p raylab {}` did: {missing:?}",
                cli.join(" ")
            );
            // `raylab grade` builds the student's code alone first (`cargo build --lib`), then
            // its tests, which must find that build fresh.
            let lib = build_units(&["-p", &name, "-e", "normal,build"]);
            let other: Vec<_> = lib.difference(&needed).collect();
            assert!(
                other.is_empty(),
                "`cargo build --lib -p {name}` (a student's build of the lab alone) builds these with other features than `cargo test -p {name}`, which would then compile the student's code again: {other:?}; ask for the features in raylab-types' manifest"
            );
            let lib_run_time = run_time_units("normal", &["-p", &name]);
            let lab_run_time = run_time_units("normal,dev", &["-p", &name]);
            let twice = run_time_disagreements(&lib, &lib_run_time, &lab_run_time);
            assert!(
                twice.is_empty(),
                "`cargo test -p {name}` would compile the student's code again after `cargo build --lib -p {name}`: {twice:?} are linked into one and needed only at build time in the other"
            );
            let shared: BTreeSet<_> = needed.intersection(&built).cloned().collect();
            let twice = run_time_disagreements(&shared, &lab_run_time, &cli_run_time);
            assert!(
                twice.is_empty(),
                "`cargo test -p {name}` would build these again, and what is compiled above them: they are linked into one command's programs and needed only by proc macros or build scripts in the other's (`cargo run -p raylab {}`): {twice:?}; make them a dependency of the framework",
                cli.join(" ")
            );
        }
    }
}

/// Fails when `command` (what `cargo tree` selects with `args`, through `edges`) would build a
/// unit that the whole workspace's test build (`cargo test --workspace --features reference`)
/// builds with other features or another `-C lto`; `fix` says where to ask for features.
fn assert_reuses_the_test_build(command: &str, args: &[&str], edges: &str, fix: &str) {
    static TESTED: std::sync::OnceLock<(Units, Units, BTreeSet<String>)> =
        std::sync::OnceLock::new();
    let (tested, tested_run_time, proc_macros) = TESTED.get_or_init(|| {
        let workspace = ["--workspace", "--features", "reference"];
        let mut all = vec!["-e", "normal,build,dev"];
        all.extend(workspace);
        (
            build_units(&all),
            run_time_units("normal,dev", &workspace),
            // A proc-macro member is a root of `--workspace` and so listed on its run-time
            // side, but a proc macro is compiled for the host alone, once, whichever command
            // selects it.
            workspace_proc_macros(),
        )
    });
    let build_edges = format!("{edges},build");
    let mut all = vec!["-e", build_edges.as_str()];
    all.extend(args);
    let built = build_units(&all);
    let missing: Vec<_> = built.difference(tested).collect();
    assert!(
        missing.is_empty(),
        "`cargo test --workspace --features reference` would build these again, with other features than {command} did: {missing:?}{fix}"
    );
    let built: Units = built
        .into_iter()
        .filter(|(package, _)| !proc_macros.contains(package))
        .collect();
    let twice = run_time_disagreements(&built, &run_time_units(edges, args), tested_run_time);
    assert!(
        twice.is_empty(),
        "`cargo test --workspace --features reference` would build these again, and what is compiled above them: they are linked into one command's programs and needed only by proc macros or build scripts in {command}'s: {twice:?}; make them a dependency of the framework"
    );
}

/// One build in CI: `cargo run -p raylab -- golden` (the golden data: the command line, then
/// each lab's program with its key, `cargo test -p labNN --features reference --no-run`) builds
/// no unit that the whole workspace's test build (`cargo test --workspace --features
/// reference`) then builds again with other features or another `-C lto`.
#[test]
fn the_workspace_s_tests_reuse_the_golden_data_s_build() {
    assert_reuses_the_test_build("`cargo run -p raylab`", &["-p", "raylab"], "normal", "");
    for lab in course::labs() {
        let name = lab.to_string();
        assert_reuses_the_test_build(
            &format!("`cargo test -p {name} --features reference`"),
            &["-p", &name, "--features", "reference"],
            "normal,dev",
            "",
        );
    }
}

/// One build for the grader: a graded program (`raylab grade`'s `labNN-graded`, whose
/// dependencies are the lab's checks, `contracts`, `grading`, `wasm-host` and `reference`,
/// `grading::graded`) builds no unit with other features than the workspace's test build, so
/// that a grading whose target directory holds that build (as the workflow tests' does) compiles
/// only the tree's own crates, not wasmtime and Cranelift again.
#[test]
fn the_graded_programs_reuse_the_workspace_s_build() {
    for lab in course::labs() {
        let checks = format!("{lab}-checks");
        let packages = ["contracts", "grading", "wasm-host", "reference"];
        let mut args = vec!["-p", checks.as_str()];
        for package in packages {
            args.extend(["-p", package]);
        }
        assert_reuses_the_test_build(
            &format!("{lab}'s graded program"),
            &args,
            "normal",
            "; ask for the features in wasm-host's manifest",
        );
    }
}

/// Each exercise is stated once, in its lab's table (`labs/labNN/exercises.toml`: number,
/// function, title, points, visibility, hint — `raylab hint` reads it); the stub, the docs
/// page's table of exercises and its section agree with it: the stub names the exercise and its
/// function, the docs table the number, function and points of each exercise students see, and
/// the docs page has a section `Exercise N.M — title` for each.
#[test]
fn stubs_and_docs_pages_agree_with_the_exercise_tables() {
    let mut problems = Vec::new();
    for lab in course::labs() {
        let table = course::lab(lab).unwrap();
        let stub = read(&root().join(lab.folder()).join("src/lib.rs"));
        let docs = read(&root().join(format!("docs/{lab}.md")));
        let headings: Vec<&str> = docs
            .lines()
            .filter_map(|l| l.strip_prefix("## ").or_else(|| l.strip_prefix("### ")))
            .collect();
        for e in &table.exercises {
            let (id, function, points) = (&e.id, &e.function, e.points);
            let heading = format!("Exercise {id} — {}", e.title);
            if !headings.contains(&heading.as_str()) {
                problems.push(format!("docs/{lab}.md: no section `{heading}`"));
            }
            if e.visibility != course::Visibility::Visible {
                continue;
            }
            for expected in [
                format!("**Exercise {id}**"),
                format!("todo!(\"Exercise {id}: {function} (docs/{lab}.md"),
            ] {
                if !stub.contains(&expected) {
                    problems.push(format!("{}/src/lib.rs: no `{expected}`", lab.folder()));
                }
            }
            let row = format!("| {id} | `{function}` |");
            match docs.lines().find(|l| l.starts_with(&row)) {
                None => problems.push(format!("docs/{lab}.md: no table row `{row} …`")),
                Some(line) if !line.trim_end().ends_with(&format!("| {points} |")) => problems
                    .push(format!(
                        "docs/{lab}.md: the row of {id} does not end with its {points} points: {line}"
                    )),
                Some(_) => {}
            }
        }
    }
    assert!(
        problems.is_empty(),
        "{} disagreements:\n{}",
        problems.len(),
        problems.join("\n")
    );
}

/// Each lab whose docs ask questions has its answers file, `labs/labNN/answers.md`, with those
/// questions as its headings: the file a student answers in, which `raylab report` shows and
/// `raylab grade` collects. `RAYLAB_WRITE_ANSWERS=1` writes the files from the docs.
#[test]
fn every_lab_with_questions_has_its_answers_file() {
    let write = std::env::var_os("RAYLAB_WRITE_ANSWERS").is_some();
    let mut with_questions = 0;
    for id in course::labs() {
        let questions = course::answers::questions(&read(&root().join(id.docs())));
        let path = root().join(id.answers());
        if questions.is_empty() {
            assert!(
                !path.exists(),
                "{} has no numbered list under `## Questions`, so no {}",
                id.docs(),
                id.answers()
            );
            continue;
        }
        with_questions += 1;
        let title = course::title(id).unwrap_or_default();
        let wanted = course::answers::template(id, title, &questions);
        if write {
            fs::write(&path, &wanted).unwrap();
        }
        assert_eq!(
            fs::read_to_string(&path).unwrap_or_default(),
            wanted,
            "{} is not the answers file of {}'s questions: run this test with RAYLAB_WRITE_ANSWERS=1",
            id.answers(),
            id.docs()
        );
    }
    assert!(
        with_questions >= 7,
        "only {with_questions} labs ask questions"
    );
}

/// The methods of lab `lab`'s contract, the functions a student writes.
fn contract_methods(lab: u32) -> Vec<&'static str> {
    use contracts::ContractMethods;
    fn of<C: ?Sized + ContractMethods>() -> Vec<&'static str> {
        C::METHODS.to_vec()
    }
    match lab {
        1 => of::<contracts::lab01::Contract>(),
        // Lab 02's contract is its two traits together.
        2 => [
            of::<dyn contracts::lab02::Intersection>(),
            of::<dyn contracts::lab02::Shading>(),
        ]
        .concat(),
        3 => of::<contracts::lab03::Contract>(),
        4 => of::<contracts::lab04::Contract>(),
        5 => of::<contracts::lab05::Contract>(),
        6 => of::<contracts::lab06::Contract>(),
        7 => of::<contracts::lab07::Contract>(),
        8 => of::<contracts::lab08::Contract>(),
        9 => of::<contracts::lab09::Contract>(),
        10 => of::<contracts::lab10::Contract>(),
        11 => of::<contracts::lab11::Contract>(),
        12 => of::<contracts::lab12::Contract>(),
        _ => panic!("lab {lab} is new: name its contract here"),
    }
}

/// An exercise is one method of its lab's contract, worth points, or checks several together
/// (1.6, "`CameraRays` (all of it)"): then it is worth none of its own, since whatever it
/// catches is charged to the exercise of the function at fault (`grading::Judge`) and what
/// would be left to it is nothing but its callees' work.
#[test]
fn an_exercise_that_is_no_method_of_its_contract_is_worth_no_points() {
    let mut problems = Vec::new();
    let mut composites = 0;
    for lab in course::labs() {
        let methods = contract_methods(lab.number());
        for e in &course::lab(lab).unwrap().exercises {
            let method = methods.contains(&e.function.as_str());
            composites += usize::from(!method);
            if !method && e.points != 0 {
                problems.push(format!(
                    "Exercise {} (`{}`) is no method of {lab}'s contract and is worth {} points",
                    e.id, e.function, e.points
                ));
            }
            if method && e.points == 0 {
                problems.push(format!("Exercise {} is worth no points", e.id));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(
        composites >= 1,
        "no exercise checks several functions together"
    );
}

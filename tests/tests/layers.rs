//! The layers of docs/architecture.md ("Invariants"), as the manifests state them: what each
//! workspace crate may depend on among the others. Cargo refuses circles between crates, so a
//! layer that holds here cannot be run back up in code.

use std::collections::{BTreeMap, BTreeSet};

use raylab_tests::workflow::{root, workspace_metadata};

/// Each workspace package's normal (not dev, not build) dependencies on other workspace packages.
fn workspace_dependencies() -> BTreeMap<String, BTreeSet<String>> {
    let metadata: serde_json::Value = serde_json::from_slice(&workspace_metadata()).unwrap();
    let packages = metadata["packages"].as_array().unwrap();
    let members: BTreeSet<String> = packages
        .iter()
        .map(|p| p["name"].as_str().unwrap().to_string())
        .collect();
    packages
        .iter()
        .map(|p| {
            let deps = p["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["kind"].is_null())
                .map(|d| d["name"].as_str().unwrap().to_string())
                .filter(|d| members.contains(d))
                .collect();
            (p["name"].as_str().unwrap().to_string(), deps)
        })
        .collect()
}

/// Whether `name` is a student's crate (`labNN`) or a lab's checks (`labNN-checks`).
fn lab_crate(name: &str) -> Option<(u32, bool)> {
    let rest = name.strip_prefix("lab")?;
    let (number, checks) = match rest.strip_suffix("-checks") {
        Some(n) => (n, true),
        None => (rest, false),
    };
    Some((number.parse().ok()?, checks))
}

#[test]
fn each_crate_depends_only_on_the_layers_below_it() {
    let deps = workspace_dependencies();
    let allowed = |name: &str| -> Option<Vec<&str>> {
        Some(match name {
            "raylab-types" | "course" | "contract-macros" => vec![],
            "raylab-core" => vec!["raylab-types"],
            "contracts" => vec!["raylab-types", "contract-macros"],
            "pipeline" => vec!["raylab-core", "contracts", "course"],
            // `view` only behind grading's `view` feature (a lab program built for `raylab view`).
            "grading" => vec!["course", "raylab-core", "contracts", "pipeline", "view"],
            "view" => vec!["raylab-core", "pipeline"],
            "figures" => vec!["course", "raylab-core", "pipeline"],
            // The command line links no lab's code, nor its checks: what needs them runs in
            // the lab's program (`cargo test -p labNN`), so a broken lab stops only its own row.
            "raylab" => vec![
                "course",
                "raylab-core",
                "contracts",
                "pipeline",
                "grading",
                "reference",
            ],
            // The answer key knows no student crate: a lab without its key has a waiting slot.
            "reference" => vec!["contracts", "pipeline"],
            _ => match lab_crate(name)? {
                // A student's crate sees the contracts and nothing that renders or checks.
                (_, false) => vec!["contracts"],
                // A lab's checks stand on the framework, never on a student's crate, the answer
                // key or another lab's checks.
                (_, true) => vec![
                    "course",
                    "raylab-core",
                    "contracts",
                    "pipeline",
                    "grading",
                    "figures",
                ],
            },
        })
    };
    let mut problems = Vec::new();
    for (name, on) in &deps {
        let Some(allowed) = allowed(name) else {
            continue;
        };
        for dep in on {
            if !allowed.contains(&dep.as_str()) {
                problems.push(format!("{name} depends on {dep}"));
            }
        }
    }
    // Every framework crate is there to be checked.
    for framework in [
        "raylab-types",
        "raylab-core",
        "contracts",
        "pipeline",
        "grading",
        "figures",
        "view",
        "raylab",
    ] {
        assert!(deps.contains_key(framework), "no crate {framework}");
    }
    assert!(problems.is_empty(), "layers run back up: {problems:?}");
}

/// The lines `cargo tree -p PACKAGE` prints for everything `cargo test -p PACKAGE` builds.
fn packages_built_by_tests_of(package: &str) -> BTreeSet<String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(["tree", "--offline", "--prefix", "none", "--format", "{p}"])
        .args(["-e", "normal,dev,build", "-p", package])
        .current_dir(root())
        .output()
        .expect("cargo tree runs");
    assert!(output.status.success(), "cargo tree -p {package} failed");
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_string)
        .collect()
}

/// A lab's tests build that lab and its checks and no other lab's crate: a broken lab never
/// stops another's tests.
#[test]
fn a_lab_s_tests_build_no_other_lab() {
    for lab in course::labs() {
        let name = lab.to_string();
        let others: Vec<String> = packages_built_by_tests_of(&name)
            .into_iter()
            .filter(|p| lab_crate(p).is_some_and(|(n, _)| n != lab.number()))
            .collect();
        assert!(
            others.is_empty(),
            "`cargo test -p {name}` builds other labs' crates: {others:?}"
        );
    }
}

/// A lab's plain tests build no web server: `raylab view`'s crate and its HTTP server come only
/// with the lab's `view` feature (issue 35: a lab's first test build stays short).
#[test]
fn a_lab_s_tests_build_no_web_server() {
    for lab in course::labs() {
        let built = packages_built_by_tests_of(&lab.to_string());
        for server in ["view", "tiny_http"] {
            assert!(
                !built.contains(server),
                "`cargo test -p {lab}` builds {server}"
            );
        }
    }
}

/// The modules a file of `framework/core/src/` imports outside its tests: each `crate::NAME`
/// and `super::NAME` of its `use` lines before `#[cfg(test)]`.
fn core_imports(file: &str) -> BTreeSet<String> {
    let text = std::fs::read_to_string(root().join("framework/core/src").join(file))
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut found = BTreeSet::new();
    for line in code.lines().map(str::trim) {
        let Some(path) = line
            .strip_prefix("use ")
            .or_else(|| line.strip_prefix("pub use "))
        else {
            continue;
        };
        for prefix in ["crate::", "super::"] {
            if let Some(rest) = path.strip_prefix(prefix) {
                let name: String = rest
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                found.insert(format!("{prefix}{name}"));
            }
        }
    }
    found
}

/// Inside the core, the acceleration structure's files import one way (`sah` ← `wide` ← `slabs`
/// ← `bvh` ← `triangles`, `stats` a leaf) and of the rest of the crate only `math` and the
/// kernels of `geometry`; the kernels import only `math`.
#[test]
fn the_core_s_acceleration_and_kernels_import_one_way() {
    let order = ["sah", "wide", "slabs", "stats", "bvh", "triangles"];
    let mut problems = Vec::new();
    for (rank, module) in order.iter().enumerate() {
        for import in core_imports(&format!("accel/{module}.rs")) {
            // An item `accel/mod.rs` re-exports stands for its module.
            let import = reexported_by_accel(&import).unwrap_or(import);
            let allowed = match import.split_once("::") {
                Some(("crate", name)) => ["math", "geometry"].contains(&name),
                Some(("super", name)) => order[..rank].contains(&name) && *name != **module,
                _ => false,
            };
            if !allowed {
                problems.push(format!("accel/{module}.rs imports {import}"));
            }
        }
    }
    for kernel in ["plane", "sphere", "triangle"] {
        for import in core_imports(&format!("geometry/{kernel}.rs")) {
            if import != "crate::math" {
                problems.push(format!("geometry/{kernel}.rs imports {import}"));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// `super::MODULE` for `super::ITEM` when `framework/core/src/accel/mod.rs` re-exports ITEM
/// from MODULE (`pub use bvh::Bvh;`).
fn reexported_by_accel(import: &str) -> Option<String> {
    let item = import.strip_prefix("super::")?;
    let text = std::fs::read_to_string(root().join("framework/core/src/accel/mod.rs")).ok()?;
    text.lines().find_map(|line| {
        let (module, items) = line.trim().strip_prefix("pub use ")?.split_once("::")?;
        let listed = items
            .trim_end_matches(';')
            .trim_matches(|c| c == '{' || c == '}')
            .split(',')
            .any(|i| i.trim() == item);
        listed.then(|| format!("super::{module}"))
    })
}

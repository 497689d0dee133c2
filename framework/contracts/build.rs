//! Writes the contracts' module lines, one per lab of the registry `labs/course.toml`
//! (`src/labNN.rs`), so that a new lab's contract needs no line here; a registered lab without
//! its contract file stops the build, naming the file.

use std::fmt::Write;
use std::path::Path;

#[path = "../course/src/registry.rs"]
#[allow(dead_code)]
mod registry;

fn main() {
    // Relative to the package root, as the course crate's build script reads the registry.
    let registry_file = Path::new("../../labs/course.toml");
    println!("cargo::rerun-if-changed={}", registry_file.display());
    let text = std::fs::read_to_string(registry_file)
        .unwrap_or_else(|e| fail(&format!("cannot read labs/course.toml: {e}")));
    let labs = registry::parse(&text).unwrap_or_else(|e| fail(&format!("labs/course.toml:{e}")));
    let src = Path::new(&std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it")).join("src");
    let mut modules = String::new();
    for lab in &labs {
        let name = format!("lab{:02}", lab.number);
        let file = src.join(format!("{name}.rs"));
        if !file.is_file() {
            fail(&format!(
                "labs/course.toml lists {name}, but its contract framework/contracts/src/{name}.rs is not in the tree"
            ));
        }
        let path = file
            .to_str()
            .unwrap_or_else(|| fail("the tree's path is not UTF-8"));
        writeln!(modules, "#[path = {path:?}]\npub mod {name};").expect("a String");
    }
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("labs.rs");
    std::fs::write(out, modules).expect("OUT_DIR is writable");
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

//! Embeds the course: the registry `labs/course.toml` and the exercise table of every lab it
//! lists (`labs/labNN/exercises.toml`), so that the command line and the checks know the course
//! without reading the tree at run time. The registry is read with the crate's own parser
//! (`src/registry.rs`), so a malformed line stops the build with its line number.

use std::path::{Path, PathBuf};

#[path = "src/registry.rs"]
#[allow(dead_code)]
mod registry;

fn main() {
    // Paths relative to the package root, which is the build script's working directory: the
    // same compiled script serves every copy of the tree (a handout, the grading tree), and
    // cargo resolves relative `rerun-if-changed` paths against the copy being built.
    let root = Path::new("../..");
    let registry_file = root.join("labs/course.toml");
    println!("cargo::rerun-if-changed={}", registry_file.display());
    let text = std::fs::read_to_string(&registry_file)
        .unwrap_or_else(|e| fail(&format!("cannot read labs/course.toml: {e}")));
    let labs = registry::parse(&text).unwrap_or_else(|e| fail(&format!("labs/course.toml:{e}")));
    let mut tables = String::from("&[\n");
    for lab in &labs {
        let name = format!("lab{:02}", lab.number);
        let table: PathBuf = root.join("labs").join(&name).join("exercises.toml");
        println!("cargo::rerun-if-changed={}", table.display());
        let Ok(text) = std::fs::read_to_string(&table) else {
            fail(&format!(
                "labs/course.toml lists {name}, but labs/{name}/exercises.toml cannot be read"
            ))
        };
        tables.push_str(&format!("    ({}, {:?}),\n", lab.number, text));
    }
    tables.push(']');
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(out.join("tables.rs"), tables).expect("OUT_DIR is writable");
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

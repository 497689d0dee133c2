//! Embeds the course: the registry `labs/course.toml` and the exercise table of every lab it
//! lists (`labs/labNN/exercises.toml`), so that the command line and the checks know the course
//! without reading the tree at run time. The registry is read with the crate's own parser
//! (`src/registry.rs`), so a malformed line stops the build with its line number.

use std::path::{Path, PathBuf};

#[path = "src/registry.rs"]
#[allow(dead_code)]
mod registry;

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let file = root.join("labs/course.toml");
    println!("cargo::rerun-if-changed={}", file.display());
    let text = std::fs::read_to_string(&file)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", file.display())));
    let labs = registry::parse(&text).unwrap_or_else(|e| fail(&format!("labs/course.toml:{e}")));
    let mut tables = String::from("&[\n");
    for lab in &labs {
        let name = format!("lab{:02}", lab.number);
        let table: PathBuf = root.join("labs").join(&name).join("exercises.toml");
        if !table.is_file() {
            fail(&format!(
                "labs/course.toml lists {name}, but labs/{name}/exercises.toml does not exist"
            ));
        }
        println!("cargo::rerun-if-changed={}", table.display());
        let table = table.canonicalize().expect("the table exists");
        tables.push_str(&format!(
            "    ({}, include_str!({:?})),\n",
            lab.number,
            table.display().to_string()
        ));
    }
    tables.push(']');
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(out.join("tables.rs"), tables).expect("OUT_DIR is writable");
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

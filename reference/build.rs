//! Reads which labs' solutions this crate holds: those of the registry `labs/course.toml` whose
//! `src/labNN.rs` is in the tree (every lab in the course's repository, the released ones in a
//! handout). It writes their module lines, `KEYS`, and the reference pipeline's filling
//! (`install_keys`, each key's own `install`) into `keys.rs`: no list of labs is written by hand.

use std::fmt::Write;
use std::path::Path;

#[path = "../framework/course/src/registry.rs"]
#[allow(dead_code)]
mod registry;

fn main() {
    // Relative to the package root (the build script's working directory), as the course
    // crate's build script reads the registry.
    let registry_file = Path::new("../labs/course.toml");
    println!("cargo::rerun-if-changed={}", registry_file.display());
    println!("cargo::rerun-if-changed=src");
    let text = std::fs::read_to_string(registry_file)
        .unwrap_or_else(|e| fail(&format!("cannot read labs/course.toml: {e}")));
    let labs = registry::parse(&text).unwrap_or_else(|e| fail(&format!("labs/course.toml:{e}")));
    let src = Path::new(&std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it")).join("src");
    let mut modules = String::new();
    let mut install = String::new();
    let mut keys = Vec::new();
    for lab in &labs {
        let name = format!("lab{:02}", lab.number);
        let file = src.join(format!("{name}.rs"));
        if !file.is_file() {
            continue;
        }
        let path = file
            .to_str()
            .unwrap_or_else(|| fail("the tree's path is not UTF-8"));
        writeln!(modules, "#[path = {path:?}]\npub mod {name};").expect("a String");
        write!(
            install,
            "|p| p.with_part::<contracts::{name}::Contract>(std::sync::Arc::new({name}::Lab{:02})), ",
            lab.number
        )
        .expect("a String");
        keys.push(lab.number.to_string());
    }
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("keys.rs");
    std::fs::write(
        &out,
        format!(
            "{modules}\n\
             /// The labs whose solution this crate holds: the slots of [`pipeline`] that are the\n\
             /// answer key. Checks compare a student's function with the key's where it is present\n\
             /// (`LabContext::with_key_labs`), and judge by golden cases and properties elsewhere.\n\
             pub const KEYS: &[u32] = &[{}];\n\n\
             /// `pipeline` with the code of every lab whose solution this crate holds.\n\
             fn install_keys(pipeline: Pipeline) -> Pipeline {{\n\
             \x20   let keys: [fn(Pipeline) -> Pipeline; {}] = [{install}];\n\
             \x20   keys.into_iter().fold(pipeline, |pipeline, install| install(pipeline))\n}}\n",
            keys.join(", "),
            keys.len()
        ),
    )
    .expect("OUT_DIR is writable");
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}

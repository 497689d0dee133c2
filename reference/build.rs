//! Lists the labs whose solution this crate holds — its `key-labNN` features — as `KEYS`, and
//! stops with a clear message when a feature asks for a solution whose file is not in the tree
//! (a handout's lab whose solution is not released yet).

use std::path::Path;

fn main() {
    let mut keys = Vec::new();
    for (name, _) in std::env::vars() {
        let Some(lab) = name.strip_prefix("CARGO_FEATURE_KEY_LAB") else {
            continue;
        };
        let Ok(number) = lab.parse::<u32>() else {
            continue;
        };
        let file = format!("src/lab{number:02}.rs");
        if !Path::new(&file).exists() {
            eprintln!(
                "error: the solution of lab {number} is not in this tree (it is not released yet), so \
                 `--features reference` has nothing to check for lab{number:02}; \
                 `cargo test -p lab{number:02}` checks your own code"
            );
            std::process::exit(1);
        }
        keys.push(number);
    }
    keys.sort_unstable();
    let list = keys
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    let out = Path::new(&std::env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("keys.rs");
    std::fs::write(
        &out,
        format!(
            "/// The labs whose solution this crate holds: the slots of [`pipeline`] that are the\n\
             /// answer key. Checks compare a student's function with the key's where it is present\n\
             /// (`LabContext::with_key_labs`), and judge by golden cases and properties elsewhere.\n\
             pub const KEYS: &[u32] = &[{list}];\n"
        ),
    )
    .expect("OUT_DIR is writable");
    println!("cargo::rerun-if-changed=src");
}

//! This build script does nothing but exist: the crate's build-dependencies are there to give
//! build-time crates the features the command line's build gives them (see `Cargo.toml`, "One
//! build"), and cargo builds build-dependencies only for a package with a build script.

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
}

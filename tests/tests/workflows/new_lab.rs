//! The course author's workflow: `raylab new-lab` in a copy of the repository writes the new
//! lab's places and its registry line and nothing else, and right after it the lab's checks fail
//! its one exercise cleanly on the stubs and pass on the answer key. Its contract file alone
//! then makes its exercise a material the path tracer draws.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use raylab_tests::workflow::{cargo_in as cargo, root, target_dir};

/// Every file under `dir` (but `target/` and `.git/`): its path relative to `dir` and its bytes.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(dir: &Path, at: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for entry in fs::read_dir(at).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap();
            if name == "target" || name == ".git" {
                continue;
            }
            if path.is_dir() {
                walk(dir, &path, out);
            } else {
                let relative = path
                    .strip_prefix(dir)
                    .unwrap()
                    .to_string_lossy()
                    .into_owned();
                out.insert(relative, fs::read(&path).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// The repository's files as git lists them (tracked, and new ones not ignored), copied to `to`.
fn copy_repository(to: &Path) {
    let listed = std::process::Command::new("git")
        .args([
            "ls-files",
            "-z",
            "--cached",
            "--others",
            "--exclude-standard",
        ])
        .current_dir(root())
        .output()
        .expect("git runs");
    assert!(listed.status.success());
    for file in listed.stdout.split(|&b| b == 0).filter(|f| !f.is_empty()) {
        let file = PathBuf::from(String::from_utf8(file.to_vec()).unwrap());
        let from = root().join(&file);
        if !from.is_file() {
            continue; // deleted in the work tree
        }
        let dest = to.join(&file);
        fs::create_dir_all(dest.parent().unwrap()).unwrap();
        fs::copy(&from, &dest).unwrap();
    }
}

/// The lines of `after` that `before` does not have, when `after` only adds lines.
fn added_lines(before: &[u8], after: &[u8]) -> Option<Vec<String>> {
    let (before, after) = (
        String::from_utf8_lossy(before),
        String::from_utf8_lossy(after),
    );
    let mut old = before.lines().peekable();
    let mut added = Vec::new();
    for line in after.lines() {
        if old.peek() == Some(&line) {
            old.next();
        } else {
            added.push(line.to_string());
        }
    }
    old.peek().is_none().then_some(added)
}

#[test]
fn new_lab_writes_only_the_lab_s_places_and_its_registry_line() {
    let work = target_dir().join("raylab-new-lab-test");
    let _ = fs::remove_dir_all(&work);
    let tree = work.join("tree");
    copy_repository(&tree);
    // A version of its own: cargo gives a path crate of the same version and place in the
    // workspace the same unit in a shared target directory, and this copy's course (its
    // registry embedded) must not be the repository's.
    let manifest = tree.join("Cargo.toml");
    let text = fs::read_to_string(&manifest).unwrap();
    let tagged = text.replacen(
        "\nversion = \"0.1.0\"\n",
        "\nversion = \"0.1.0-new-lab\"\n",
        1,
    );
    assert_ne!(text, tagged, "the workspace's version is 0.1.0");
    fs::write(&manifest, tagged).unwrap();
    let before = files(&tree);

    let next = course::last().number() + 1;
    let lab = format!("lab{next:02}");
    let tree_arg = tree.to_string_lossy().into_owned();
    let args = [
        "run",
        "--quiet",
        "-p",
        "raylab",
        "--",
        "new-lab",
        &next.to_string(),
        "--title",
        "Path tracing",
        "--root",
        &tree_arg,
    ];
    // The command builds the new lab's program in the copy with the cargo and the target
    // directory it runs with: this test run's, whose dependencies the copy's crates reuse.
    let (ok, out) = cargo(&root(), &target_dir(), &args);
    assert!(ok, "raylab new-lab failed:\n{out}");

    let after = files(&tree);
    let own = [
        format!("labs/{lab}/"),
        format!("framework/contracts/src/{lab}.rs"),
        format!("reference/src/{lab}.rs"),
        format!("docs/{lab}.md"),
    ];
    let mut problems = Vec::new();
    for (path, bytes) in &after {
        let is_own = own
            .iter()
            .any(|p| path == p || (p.ends_with('/') && path.starts_with(p)));
        match before.get(path) {
            None if is_own => {}
            None => problems.push(format!("new file outside the lab's places: {path}")),
            Some(old) if old == bytes => {}
            Some(old) => {
                let added = added_lines(old, bytes);
                let expected = match path.as_str() {
                    "labs/course.toml" => Some(format!("{lab} = \"Path tracing\"")),
                    "README.md" => Some(format!(
                        "| {lab} | path tracing | [docs/{lab}.md](docs/{lab}.md) |"
                    )),
                    // Cargo's own record of the workspace's packages.
                    "Cargo.lock" => None,
                    _ => {
                        problems.push(format!("changed outside the lab's places: {path}"));
                        continue;
                    }
                };
                if let Some(line) = expected
                    && added.as_deref() != Some(std::slice::from_ref(&line))
                {
                    problems.push(format!(
                        "{path}: expected one new line `{line}`, got {added:?}"
                    ));
                }
            }
        }
    }
    for path in before.keys().filter(|p| !after.contains_key(*p)) {
        problems.push(format!("removed: {path}"));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    assert!(after.contains_key(&format!("labs/{lab}/golden/luminance.json")));

    // The stubs fail the one exercise cleanly; the answer key passes it, with the corpus.
    let target = target_dir();
    let (ok, out) = cargo(&tree, &target, &["test", "-p", &lab, "--test", "checks"]);
    assert!(!ok, "the stubs pass:\n{out}");
    assert!(
        out.contains(&format!("Exercise {next}.1 — `luminance`"))
            && out.contains("is not implemented yet")
            && out.contains("0 passed; 1 failed"),
        "{out}"
    );
    let (ok, out) = cargo(
        &tree,
        &target,
        &["test", "-p", &lab, "--features", "reference"],
    );
    assert!(
        ok && out.contains("1 passed; 0 failed"),
        "the answer key fails:\n{out}"
    );

    // The same number again is refused before anything is written.
    let built = files(&tree);
    let (ok, out) = cargo(&root(), &target_dir(), &args);
    assert!(!ok && out.contains("a new lab comes after it"), "{out}");
    assert!(files(&tree) == built, "a refused new-lab changed the tree");

    // A lab whose exercise the path tracer calls: the lab's own contract file registers its
    // code as a surface model, "grey" (a Lambertian surface whose reflectance is the luminance
    // of its diffuse colour, Exercise N.1); a scene's material names it, and `raylab render`
    // in the copy draws it so — with no framework file edited.
    let contract = tree.join(format!("framework/contracts/src/{lab}.rs"));
    let text = fs::read_to_string(&contract).unwrap();
    let registered = text.replacen(
        "#[crate::contract]",
        "#[crate::contract(register = grey_surface)]",
        1,
    );
    assert_ne!(text, registered, "the new contract is a #[crate::contract]");
    fs::write(&contract, registered + GREY_SURFACE).unwrap();
    fs::write(tree.join("grey.toml"), GREY_SCENE).unwrap();
    fs::write(
        tree.join("red.toml"),
        GREY_SCENE.replace("model = \"grey\"\n", ""),
    )
    .unwrap();
    let centre = |scene: &str| {
        let output = work.join(format!("{scene}.exr"));
        let output_arg = output.to_string_lossy().into_owned();
        let (ok, out) = cargo(
            &tree,
            &target,
            &[
                "run",
                "--quiet",
                "-p",
                "raylab",
                "--",
                "render",
                "--lab",
                &next.to_string(),
                "--scene",
                scene,
                "--width",
                "9",
                "--height",
                "9",
                "--spp",
                "8",
                "-o",
                &output_arg,
            ],
        );
        assert!(ok, "raylab render {scene} failed:\n{out}");
        let film = raylab_core::film::read_exr(&output).unwrap();
        film.pixels[(4 * film.width + 4) as usize]
    };
    let grey = centre("grey.toml");
    let red = centre("red.toml");
    // Lit head-on by a point light at the eye: the surface model's reflectance, grey, where the
    // path tracer's own Lambertian lobe reflects the material's red.
    assert!(
        grey.x > 0.0
            && (grey.x - grey.y).abs() <= 1e-4 * grey.x
            && (grey.y - grey.z).abs() <= 1e-4 * grey.x,
        "the grey surface model is not drawn: {grey}"
    );
    assert!(red.x > 5.0 * red.y && red.y > 0.0, "{red}");
    let luminance = 0.2126 * 0.9 + 0.7152 * 0.1 + 0.0722 * 0.1;
    assert!(
        (grey.x / red.x - luminance / 0.9).abs() < 1e-3,
        "grey {grey} against red {red}: expected the ratio of the luminance to the red"
    );
    let changed: Vec<String> = files(&tree)
        .into_iter()
        .filter(|(path, bytes)| built.get(path) != Some(bytes))
        .map(|(path, _)| path)
        .collect();
    assert_eq!(
        changed,
        [
            format!("framework/contracts/src/{lab}.rs"),
            "grey.toml".into(),
            "red.toml".into()
        ],
        "only the new lab's contract file is edited"
    );
}

/// The surface model "grey" of the new lab's contract file: Lambertian, of the luminance of the
/// diffuse colour, drawn by the cosine.
const GREY_SURFACE: &str = r#"
/// The path tracer's surface model "grey": this lab's code as a material.
fn grey_surface(code: std::sync::Arc<Contract>, parts: &mut crate::Parts) {
    parts.add_surface("grey", code, |code| std::sync::Arc::new(Grey(code)));
}

/// A Lambertian surface whose reflectance is the luminance of its diffuse colour.
struct Grey(std::sync::Arc<Contract>);

impl crate::surface::SurfaceModel for Grey {
    fn bsdf(
        &self,
        _: &crate::scene::Material,
        diffuse: Vec3,
        normal: Vec3,
        _: Vec3,
        wi: Vec3,
    ) -> crate::lab12::BsdfValue {
        let pi = std::f32::consts::PI;
        crate::lab12::BsdfValue {
            value: Vec3::splat(self.0.luminance(diffuse) / pi),
            pdf: normal.dot(wi).max(0.0) / pi,
        }
    }

    fn sample_bsdf(
        &self,
        material: &crate::scene::Material,
        diffuse: Vec3,
        normal: Vec3,
        wo: Vec3,
        rng: &mut crate::sampling::Rng,
    ) -> Option<crate::lab12::BsdfSample> {
        let (u1, u2) = (rng.next_f32(), rng.next_f32());
        let (r, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
        let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
        let wi = crate::math::Onb::from_w(normal).to_world(local).normalize();
        let value = self.bsdf(material, diffuse, normal, wo, wi);
        Some(crate::lab12::BsdfSample {
            direction: wi,
            value: value.value,
            pdf: value.pdf,
        })
    }
}
"#;

/// A red sphere of the surface model "grey", lit head-on by a point light at the eye, over a
/// black background.
const GREY_SCENE: &str = r#"
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
up = [0, 1, 0]
focal_distance = 1.0

[materials.red]
diffuse = [0.9, 0.1, 0.1]
model = "grey"

[[lights]]
type = "point"
position = [0, 0, 4]
intensity = [20, 20, 20]

[[spheres]]
center = [0, 0, 0]
radius = 1
material = "red"
"#;

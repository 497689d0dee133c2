//! Scenes compiled into the framework: their scene files, OBJ meshes and MTL libraries (under
//! `framework/scenes/`) are embedded, so they need no file on disk at run time.

use std::io;
use std::path::Path;

use super::Scene;
use super::file::parse_scene_with;
use crate::Error;

/// Names of the built-in scenes, for [`builtin_scene`].
pub const BUILTIN_SCENES: &[&str] = &["default", "cornell", "cornell-ceiling", "cornell-spheres"];

/// Directory the embedded files pretend to live in (it appears in error messages).
const BUILTIN_DIR: &str = "<builtin>";

/// The embedded files by name.
const FILES: &[(&str, &str)] = &[
    ("default.toml", include_str!("../../scenes/default.toml")),
    ("cornell.toml", include_str!("../../scenes/cornell.toml")),
    (
        "cornell-ceiling.toml",
        include_str!("../../scenes/cornell-ceiling.toml"),
    ),
    (
        "cornell-spheres.toml",
        include_str!("../../scenes/cornell-spheres.toml"),
    ),
    ("torus.obj", include_str!("../../scenes/torus.obj")),
    (
        "cornell_room.obj",
        include_str!("../../scenes/cornell_room.obj"),
    ),
    (
        "cornell_blocks.obj",
        include_str!("../../scenes/cornell_blocks.obj"),
    ),
    ("cornell.mtl", include_str!("../../scenes/cornell.mtl")),
];

/// The embedded file that `path` names (only its file name counts).
fn embedded(path: &Path) -> io::Result<String> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
    FILES
        .iter()
        .find(|(file, _)| *file == name)
        .map(|(_, text)| (*text).to_string())
        .ok_or_else(|| {
            io::Error::new(
                io::ErrorKind::NotFound,
                format!("'{name}' is not one of the built-in scene files"),
            )
        })
}

/// Builds one of the [`BUILTIN_SCENES`]:
///
/// - `"default"`: a ground plane, a red, a mirror and a glass sphere, a torus mesh, a point and
///   a directional light, sky-blue background (metres);
/// - `"cornell"`: the Cornell box with its two blocks and ceiling light, plus a point light
///   just below the ceiling light (millimetres);
/// - `"cornell-spheres"`: the Cornell box with a mirror and a glass sphere instead of blocks.
pub fn builtin_scene(name: &str) -> Result<Scene, Error> {
    let file = format!("{name}.toml");
    let text = BUILTIN_SCENES
        .contains(&name)
        .then(|| embedded(Path::new(&file)).ok())
        .flatten();
    let Some(text) = text else {
        return Err(Error::Invalid {
            what: format!("built-in scene '{name}'"),
            reason: format!("expected one of {}", BUILTIN_SCENES.join(", ")),
        });
    };
    let dir = Path::new(BUILTIN_DIR);
    parse_scene_with(&dir.join(&file), &text, dir, &embedded)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::{CameraSetup, IllumModel, Light};

    /// Image-plane coordinates of `p` (the image plane is 1 high at distance `focal_distance`,
    /// x axis `normalize(view × up)`), or `None` behind the camera.
    fn project(camera: &CameraSetup, p: Vec3) -> Option<(f32, f32)> {
        let view = (camera.look_at - camera.eye).normalize();
        let x_axis = view.cross(camera.up).normalize();
        let y_axis = x_axis.cross(view);
        let d = p - camera.eye;
        let z = d.dot(view);
        (z > 0.0).then(|| {
            (
                d.dot(x_axis) / z * camera.focal_distance,
                d.dot(y_axis) / z * camera.focal_distance,
            )
        })
    }

    /// Whether `p` is in the picture of a 4:3 image.
    fn in_view(camera: &CameraSetup, p: Vec3) -> bool {
        project(camera, p).is_some_and(|(x, y)| x.abs() <= 0.5 * 4.0 / 3.0 && y.abs() <= 0.5)
    }

    #[test]
    fn every_builtin_scene_loads() {
        for name in BUILTIN_SCENES {
            let scene = builtin_scene(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(scene.name, *name);
        }
    }

    #[test]
    fn unknown_name_lists_the_builtin_scenes() {
        for name in ["nope", "torus", "cornell.mtl", ""] {
            match builtin_scene(name) {
                Err(e @ Error::Invalid { .. }) => {
                    let message = e.to_string();
                    assert!(
                        message.contains("default, cornell, cornell-ceiling, cornell-spheres"),
                        "{message}"
                    );
                }
                other => panic!("expected an invalid-name error, got {other:?}"),
            }
        }
    }

    #[test]
    fn default_scene_contents() {
        let scene = builtin_scene("default").unwrap();
        assert_eq!(scene.planes.len(), 1);
        assert_eq!(scene.spheres.len(), 3);
        assert_eq!(scene.mesh.faces.len(), 1536);
        assert_eq!(scene.mesh.normals.len(), scene.mesh.positions.len());
        assert_eq!(scene.mesh.texcoords.len(), scene.mesh.positions.len());
        assert!(
            scene
                .mesh
                .normals
                .iter()
                .all(|n| (n.length() - 1.0).abs() < 1e-4)
        );
        assert_eq!(scene.background, Vec3::new(0.1, 0.3, 0.6));
        assert_eq!(scene.lights.len(), 2);
        assert!(matches!(scene.lights[0], Light::Point(_)));
        assert!(matches!(scene.lights[1], Light::Directional(_)));
        let illums: Vec<IllumModel> = scene
            .spheres
            .iter()
            .map(|s| scene.material(s.material).illum)
            .collect();
        assert_eq!(
            illums,
            [
                IllumModel::Lambertian,
                IllumModel::Mirror,
                IllumModel::Transparent
            ]
        );
        let glass = scene.material(scene.spheres[2].material);
        assert_eq!(glass.ior, 1.5);
        // Everything is in view: the spheres' silhouettes (approximated by their bounding
        // boxes' corners) and every vertex of the torus; nothing is below the ground.
        for s in &scene.spheres {
            let b = s.bounds();
            for i in 0..8 {
                let corner = Vec3::new(
                    if i & 1 == 0 { b.min.x } else { b.max.x },
                    if i & 2 == 0 { b.min.y } else { b.max.y },
                    if i & 4 == 0 { b.min.z } else { b.max.z },
                );
                assert!(in_view(&scene.camera, corner), "{corner} is out of view");
            }
            assert!(s.center.y - s.radius >= -1e-6);
        }
        for p in &scene.mesh.positions {
            assert!(in_view(&scene.camera, *p), "{p} is out of view");
            assert!(p.y >= -1e-6);
        }
    }

    #[test]
    fn cornell_scene_contents() {
        let scene = builtin_scene("cornell").unwrap();
        // Room: floor, ceiling, back, left and right walls and the light, two triangles each;
        // blocks: top and four sides each.
        assert_eq!(scene.mesh.faces.len(), 12 + 20);
        assert!(scene.planes.is_empty() && scene.spheres.is_empty());
        assert_eq!(scene.lights.len(), 2);
        let Light::Point(point) = &scene.lights[0] else {
            panic!("expected the point light first: {:?}", scene.lights)
        };
        let Light::Area(area) = &scene.lights[1] else {
            panic!("expected an area light: {:?}", scene.lights)
        };
        assert_eq!(area.faces.len(), 2);
        assert!((area.area - 0.130 * 0.105).abs() < 1e-6, "{}", area.area);
        for &f in &area.faces {
            let [a, b, c] = scene.mesh.triangle(f as usize);
            assert!([a, b, c].iter().all(|p| p.y < 0.5488 && p.y > 0.5480));
            // Facing down, into the box.
            assert!((b - a).cross(c - a).y < 0.0);
            let m = scene.material(scene.mesh.face_materials[f as usize]);
            assert_eq!(m.emission, Vec3::new(17.0, 12.0, 4.0));
        }
        // The point light lights the white floor below it with radiance of order 1.
        let floor = scene
            .materials
            .iter()
            .find(|m| m.name == "white")
            .unwrap()
            .diffuse;
        let r = point.position.y;
        let radiance = floor * point.intensity / (r * r) / std::f32::consts::PI;
        assert!(
            radiance.min_element() > 0.5 && radiance.max_element() < 2.0,
            "{radiance}"
        );
        assert!((point.position - Vec3::new(0.278, 0.548, 0.2795)).length() < 1e-3);
        assert_eq!(scene.camera.focal_distance, 1.4);
    }

    #[test]
    fn cornell_walls_are_red_on_the_left_and_green_on_the_right() {
        for name in ["cornell", "cornell-spheres"] {
            let scene = builtin_scene(name).unwrap();
            let mut seen = 0;
            for f in 0..scene.mesh.faces.len() {
                let material = &scene.material(scene.mesh.face_materials[f]).name;
                let [a, b, c] = scene.mesh.triangle(f);
                let (x, _) = project(&scene.camera, (a + b + c) / 3.0).unwrap();
                match material.as_str() {
                    "red" => assert!(x < -0.3, "{name}: red wall at image x = {x}"),
                    "green" => assert!(x > 0.3, "{name}: green wall at image x = {x}"),
                    _ => continue,
                }
                seen += 1;
            }
            assert_eq!(seen, 4, "{name}: two triangles per coloured wall");
        }
    }

    #[test]
    fn cornell_box_fills_the_view() {
        let scene = builtin_scene("cornell").unwrap();
        // The front edges of the box (z = 0) lie just outside the square picture of the
        // Cornell camera; the back wall is well inside it.
        for p in [
            Vec3::new(0.0, 0.0, 0.5592),
            Vec3::new(0.556, 0.5488, 0.5592),
        ] {
            let (x, y) = project(&scene.camera, p).unwrap();
            assert!(x.abs() < 0.5 && y.abs() < 0.5, "{p}: ({x}, {y})");
        }
        for p in [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.556, 0.5488, 0.0)] {
            let (x, y) = project(&scene.camera, p).unwrap();
            assert!(x.abs() > 0.45 && y.abs() > 0.45, "{p}: ({x}, {y})");
        }
    }

    #[test]
    fn cornell_spheres_scene_contents() {
        let scene = builtin_scene("cornell-spheres").unwrap();
        assert_eq!(scene.mesh.faces.len(), 12);
        assert_eq!(scene.spheres.len(), 2);
        assert_eq!(scene.lights.len(), 2);
        let illums: Vec<IllumModel> = scene
            .spheres
            .iter()
            .map(|s| scene.material(s.material).illum)
            .collect();
        assert_eq!(illums, [IllumModel::Mirror, IllumModel::Transparent]);
        for s in &scene.spheres {
            // On the floor and inside the box.
            assert!((s.center.y - s.radius).abs() < 1e-3);
            assert!(s.center.x - s.radius > 0.0 && s.center.x + s.radius < 0.5496);
            assert!(s.center.z - s.radius > 0.0 && s.center.z + s.radius < 0.5592);
        }
    }

    /// The parsed form of a built-in scene, as text: everything but the mesh's vertices, which
    /// are summed up (counts, bounds, faces per material, total area).
    fn parsed_form(name: &str) -> String {
        let scene = builtin_scene(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        let mesh = &scene.mesh;
        let (lo, hi) = mesh.positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let mut faces_per_material = vec![0usize; scene.materials.len()];
        let mut area = 0.0f64;
        for (f, face) in mesh.faces.iter().enumerate() {
            if let Some(n) = faces_per_material.get_mut(mesh.face_materials[f].0 as usize) {
                *n += 1;
            }
            let [a, b, c] = face.map(|i| mesh.positions[i as usize]);
            area += 0.5 * f64::from((b - a).cross(c - a).length());
        }
        let mut text = format!(
            "name: {}\ncamera: {:#?}\nbackground: {:?}\nenvironment: {}\n",
            scene.name,
            scene.camera,
            scene.background,
            scene.environment.is_some()
        );
        for (k, m) in scene.materials.iter().enumerate() {
            text += &format!("material {k} ({} faces): {m:#?}\n", faces_per_material[k]);
        }
        text += &format!(
            "lights: {:#?}\nplanes: {:#?}\nspheres: {:#?}\n",
            scene.lights, scene.planes, scene.spheres
        );
        text += &format!(
            "mesh: {} positions, {} normals, {} texture coordinates, {} faces, bounds {lo:?} to {hi:?}, area {area:.6}\n",
            mesh.positions.len(),
            mesh.normals.len(),
            mesh.texcoords.len(),
            mesh.faces.len()
        );
        text
    }

    /// What the scene files, OBJ meshes and MTL libraries of the built-in scenes parse to: a
    /// change in the parser or in the files shows here, to be reviewed with `cargo insta
    /// review`.
    #[test]
    fn the_parsed_builtin_scenes_stay_the_same() {
        for name in BUILTIN_SCENES {
            insta::assert_snapshot!(format!("builtin_{name}"), parsed_form(name));
        }
    }
}

//! The TOML scene file format (documented in `docs/scene-format.md`).
//!
//! ```toml
//! background = [0.1, 0.3, 0.6]
//! [camera]
//! eye = [0, 1, 5]
//! look_at = [0, 0, 0]
//! up = [0, 1, 0]
//! focal_distance = 1.0
//! [materials.red]
//! diffuse = [0.8, 0.1, 0.1]
//! [[spheres]]
//! center = [0, 1, 0]
//! radius = 1
//! material = "red"
//! ```

use std::cell::Cell;
use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Quat, Vec3};
use serde::Deserialize;
use toml::Spanned;

use super::TextureFile;
use super::obj::{ObjData, ReadText, accepted_illums, load_obj_with, name_list, read_text};
use super::{
    CameraSetup, DirectionalLight, IllumModel, Light, Material, MaterialId, Mesh, Plane,
    PointLight, Scene, SceneDescription, Sphere, Texture,
};
use super::{EnvironmentMap, ProbeMapping};
use crate::Error;
use crate::film::one_line;

/// Loads a TOML scene file; OBJ meshes and textures it names are found relative to its
/// directory. See `docs/scene-format.md` for the format.
pub fn load_scene_file(path: &Path) -> Result<Scene, Error> {
    let text = read_text(path).map_err(|e| Error::io(path, e))?;
    let base_dir = path.parent().unwrap_or(Path::new(""));
    parse_scene_with(path, &text, base_dir, &read_text)
}

/// Parses scene-file text. `name` stands for the file in error messages (and its stem is the
/// scene's name unless the text sets one); files it names are found relative to `base_dir`.
pub fn parse_scene_str(name: &str, text: &str, base_dir: &Path) -> Result<Scene, Error> {
    parse_scene_with(Path::new(name), text, base_dir, &read_text)
}

/// Parses scene-file text that stands for the file `path`, reading the OBJ and MTL files it
/// names (relative to `base_dir`) through `read`. Textures are always read from disk.
pub(crate) fn parse_scene_with(
    path: &Path,
    text: &str,
    base_dir: &Path,
    read: ReadText<'_>,
) -> Result<Scene, Error> {
    let file: SceneToml = toml::from_str(text).map_err(|e| Error::SceneFile {
        path: path.to_path_buf(),
        reason: match e.span() {
            Some(span) => format!("{}: {}", position(text, span.start), one_line(e.message())),
            None => one_line(e.message()),
        },
    })?;
    Builder {
        path,
        text,
        at: Cell::new(None),
        base_dir,
        read,
    }
    .build(file)
}

/// "line L, column C" of the byte offset `at` of `text` (both 1-based; columns count
/// characters).
fn position(text: &str, at: usize) -> String {
    let at = at.min(text.len());
    let before = text.get(..at).unwrap_or(text);
    let line = 1 + before.matches('\n').count();
    let column = 1 + before.rsplit('\n').next().map_or(0, |l| l.chars().count());
    format!("line {line}, column {column}")
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneToml {
    name: Option<String>,
    background: Option<Spanned<[f32; 3]>>,
    environment: Option<Spanned<EnvironmentToml>>,
    camera: Option<Spanned<CameraToml>>,
    #[serde(default)]
    materials: BTreeMap<String, Spanned<MaterialToml>>,
    #[serde(default)]
    lights: Vec<Spanned<LightToml>>,
    #[serde(default)]
    planes: Vec<Spanned<PlaneToml>>,
    #[serde(default)]
    spheres: Vec<Spanned<SphereToml>>,
    #[serde(default)]
    meshes: Vec<Spanned<MeshToml>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct EnvironmentToml {
    probe: PathBuf,
    mapping: String,
    scale: Option<f32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraToml {
    eye: [f32; 3],
    look_at: [f32; 3],
    up: [f32; 3],
    focal_distance: f32,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialToml {
    #[serde(default = "default_illum")]
    illum: i64,
    diffuse: Option<[f32; 3]>,
    specular: Option<[f32; 3]>,
    ambient: Option<[f32; 3]>,
    emission: Option<[f32; 3]>,
    shininess: Option<f32>,
    roughness: Option<f32>,
    ior: Option<f32>,
    transmission: Option<[f32; 3]>,
    texture: Option<PathBuf>,
    model: Option<String>,
}

fn default_illum() -> i64 {
    1
}

#[derive(Debug, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
enum LightToml {
    Point {
        position: [f32; 3],
        intensity: [f32; 3],
    },
    Directional {
        direction: [f32; 3],
        emission: [f32; 3],
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneToml {
    point: [f32; 3],
    normal: [f32; 3],
    material: String,
    tex_scale: Option<f32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereToml {
    center: [f32; 3],
    radius: f32,
    material: String,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MeshToml {
    file: String,
    scale: Option<Scale>,
    rotate_y_degrees: Option<f32>,
    translate: Option<[f32; 3]>,
    material: Option<String>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged, expecting = "a number or an array of three numbers")]
enum Scale {
    Uniform(f32),
    PerAxis([f32; 3]),
}

struct Builder<'a> {
    path: &'a Path,
    /// The scene file's text, for the line of an entry.
    text: &'a str,
    /// The byte offset of the entry being built, which an error names by its line.
    at: Cell<Option<usize>>,
    base_dir: &'a Path,
    read: ReadText<'a>,
}

/// The materials that scene entries can name: each name's id, and the names in order.
struct MaterialNames<'f> {
    ids: HashMap<String, MaterialId>,
    names: Vec<&'f String>,
}

impl Builder<'_> {
    fn fail(&self, reason: String) -> Error {
        Error::SceneFile {
            path: self.path.to_path_buf(),
            reason: match self.at.get() {
                Some(at) => format!("{}: {reason}", position(self.text, at)),
                None => reason,
            },
        }
    }

    /// Where the current entry is: "at scene.toml, line 8, column 1", or "in scene.toml"
    /// before any entry.
    fn place(&self) -> String {
        match self.at.get() {
            Some(at) => format!("at {}, {}", self.path.display(), position(self.text, at)),
            None => format!("in {}", self.path.display()),
        }
    }

    /// Makes later errors name the line of the entry `span`.
    fn entry(&self, span: std::ops::Range<usize>) {
        self.at.set(Some(span.start));
    }

    /// Builds the scene of a parsed scene file, checking its entries in this order.
    fn build(&self, file: SceneToml) -> Result<Scene, Error> {
        let name = self.scene_name(&file);
        let camera = self.place_camera(&file)?;
        let background = self.background(&file)?;
        let environment = self.load_environment(&file)?;
        let (mut materials, known) = self.build_materials(&file)?;
        let lights = self.place_lights(&file.lights)?;
        let planes = self.place_planes(&file.planes, &known)?;
        let spheres = self.place_spheres(&file.spheres, &known)?;
        let mesh = self.place_meshes(&file.meshes, &known, &mut materials)?;
        self.finish_scene(
            &file,
            SceneDescription {
                name,
                camera: Some(camera),
                background,
                environment,
                materials,
                lights,
                planes,
                spheres,
                mesh,
            },
        )
    }

    /// The scene's name: the file's `name`, or else the file's stem.
    fn scene_name(&self, file: &SceneToml) -> String {
        file.name.clone().unwrap_or_else(|| {
            self.path
                .file_stem()
                .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
        })
    }

    /// The `[camera]` table, which every scene must have.
    fn place_camera(&self, file: &SceneToml) -> Result<CameraSetup, Error> {
        let camera = file.camera.as_ref().ok_or_else(|| {
            self.fail(
                "the scene has no camera; expected a [camera] table with eye, look_at, up and focal_distance"
                    .into(),
            )
        })?;
        self.entry(camera.span());
        let camera = camera.get_ref();
        Ok(CameraSetup {
            eye: Vec3::from(camera.eye),
            look_at: Vec3::from(camera.look_at),
            up: Vec3::from(camera.up),
            focal_distance: camera.focal_distance,
        })
    }

    /// The background colour (black by default), checked to be finite.
    fn background(&self, file: &SceneToml) -> Result<Vec3, Error> {
        self.at
            .set(file.background.as_ref().map(|b| b.span().start));
        let background = file
            .background
            .as_ref()
            .map_or(Vec3::ZERO, |b| Vec3::from(*b.get_ref()));
        if !background.is_finite() {
            return Err(self.fail(format!(
                "background is {background}; expected finite numbers"
            )));
        }
        Ok(background)
    }

    /// The environment map of the `[environment]` table, if the scene has one.
    fn load_environment(&self, file: &SceneToml) -> Result<Option<EnvironmentMap>, Error> {
        Ok(match &file.environment {
            Some(env) => {
                self.entry(env.span());
                Some(self.environment(env.get_ref())?)
            }
            None => None,
        })
    }

    /// The `[materials.*]` tables, in the order of their names, with the ids of those names.
    fn build_materials<'f>(
        &self,
        file: &'f SceneToml,
    ) -> Result<(Vec<Material>, MaterialNames<'f>), Error> {
        let mut materials = Vec::new();
        let mut ids = HashMap::new();
        let mut textures = HashMap::new();
        for (key, m) in &file.materials {
            self.entry(m.span());
            let m = m.get_ref();
            ids.insert(key.clone(), MaterialId(materials.len() as u32));
            materials.push(self.material(key, m, &mut textures)?);
        }
        let names: Vec<&String> = file.materials.keys().collect();
        Ok((materials, MaterialNames { ids, names }))
    }

    /// The id of the material `name` that the entry `what` names.
    fn lookup(&self, known: &MaterialNames, what: String, name: &str) -> Result<MaterialId, Error> {
        let MaterialNames { ids, names } = known;
        ids.get(name).copied().ok_or_else(|| {
            self.fail(if names.is_empty() {
                format!(
                    "{what}: unknown material '{}'; no materials are defined (add a [materials.{0}] table)",
                    name.escape_debug()
                )
            } else {
                format!(
                    "{what}: unknown material '{}'; expected one of {}",
                    name.escape_debug(),
                    name_list(names)
                )
            })
        })
    }

    /// The `[[lights]]` entries: point lights and directional lights, checked.
    fn place_lights(&self, entries: &[Spanned<LightToml>]) -> Result<Vec<Light>, Error> {
        let mut lights = Vec::new();
        for (i, l) in entries.iter().enumerate() {
            self.entry(l.span());
            lights.push(match l.get_ref() {
                LightToml::Point {
                    position,
                    intensity,
                } => {
                    let (position, intensity) = (Vec3::from(*position), Vec3::from(*intensity));
                    if !(position.is_finite() && intensity.is_finite()) {
                        return Err(self.fail(format!(
                            "lights[{i}]: point light at {position} with intensity {intensity}; expected finite numbers"
                        )));
                    }
                    Light::Point(PointLight {
                        position,
                        intensity,
                    })
                }
                LightToml::Directional {
                    direction,
                    emission,
                } => {
                    let (direction, emission) = (Vec3::from(*direction), Vec3::from(*emission));
                    let unit = direction.normalize_or_zero();
                    if unit == Vec3::ZERO || !emission.is_finite() {
                        return Err(self.fail(format!(
                            "lights[{i}]: directional light with direction {direction} and emission {emission}; expected a non-zero finite direction and finite emission"
                        )));
                    }
                    Light::Directional(DirectionalLight {
                        direction: unit,
                        emission,
                    })
                }
            });
        }
        Ok(lights)
    }

    /// The `[[planes]]` entries, with their materials and texture scales.
    fn place_planes(
        &self,
        entries: &[Spanned<PlaneToml>],
        known: &MaterialNames,
    ) -> Result<Vec<Plane>, Error> {
        let mut planes = Vec::new();
        for (i, p) in entries.iter().enumerate() {
            self.entry(p.span());
            let p = p.get_ref();
            let (point, normal) = (Vec3::from(p.point), Vec3::from(p.normal));
            if !point.is_finite() || normal.normalize_or_zero() == Vec3::ZERO {
                return Err(self.fail(format!(
                    "planes[{i}]: point {point} and normal {normal}; expected finite numbers and a non-zero normal"
                )));
            }
            let mut plane = Plane::new(
                point,
                normal,
                self.lookup(known, format!("planes[{i}]"), &p.material)?,
            );
            if let Some(s) = p.tex_scale {
                if !(s.is_finite() && s > 0.0) {
                    return Err(self.fail(format!(
                        "planes[{i}]: tex_scale is {s}; expected a positive number"
                    )));
                }
                plane.tex_scale = s;
            }
            planes.push(plane);
        }
        Ok(planes)
    }

    /// The `[[spheres]]` entries, with their materials.
    fn place_spheres(
        &self,
        entries: &[Spanned<SphereToml>],
        known: &MaterialNames,
    ) -> Result<Vec<Sphere>, Error> {
        let mut spheres = Vec::new();
        for (i, s) in entries.iter().enumerate() {
            self.entry(s.span());
            let s = s.get_ref();
            let center = Vec3::from(s.center);
            if !(center.is_finite() && s.radius.is_finite() && s.radius > 0.0) {
                return Err(self.fail(format!(
                    "spheres[{i}]: centre {center} and radius {}; expected finite numbers and a positive radius",
                    s.radius
                )));
            }
            spheres.push(Sphere {
                center,
                radius: s.radius,
                material: self.lookup(known, format!("spheres[{i}]"), &s.material)?,
            });
        }
        Ok(spheres)
    }

    /// The `[[meshes]]` entries merged into one mesh; the materials of their OBJ files are
    /// appended to `materials` unless an entry overrides them.
    fn place_meshes(
        &self,
        entries: &[Spanned<MeshToml>],
        known: &MaterialNames,
        materials: &mut Vec<Material>,
    ) -> Result<Mesh, Error> {
        let mut mesh = Mesh::default();
        for (i, m) in entries.iter().enumerate() {
            self.entry(m.span());
            let m = m.get_ref();
            let what = format!("meshes[{i}]");
            let overridden = m
                .material
                .as_ref()
                .map(|name| self.lookup(known, what.clone(), name))
                .transpose()?;
            let obj = self.load_mesh_obj(&what, m)?;
            let mut part = self.transform(&what, m, obj.mesh)?;
            match overridden {
                Some(id) => part.face_materials.fill(id),
                None => {
                    let base = materials.len() as u32;
                    for id in &mut part.face_materials {
                        id.0 += base;
                    }
                    materials.extend(obj.materials);
                }
            }
            mesh.append(&part);
        }
        Ok(mesh)
    }

    /// Reads and parses the OBJ file of the mesh entry `what`.
    fn load_mesh_obj(&self, what: &str, m: &MeshToml) -> Result<ObjData, Error> {
        let obj_path = self.base_dir.join(&m.file);
        let text = (self.read)(&obj_path).map_err(|e| {
            self.fail(format!(
                "{what}: cannot read the OBJ file '{}': {e}",
                obj_path.display().to_string().escape_debug()
            ))
        })?;
        // A texture of the OBJ's materials names its MTL line, and then this entry.
        load_obj_with(&obj_path, &text, self.read).map_err(|e| match e {
            Error::Texture {
                path,
                named_by,
                reason,
            } => Error::Texture {
                path,
                named_by: Some(format!(
                    "{}, in the OBJ file of {what} {}",
                    named_by.as_deref().unwrap_or("the texture"),
                    self.place()
                )),
                reason,
            },
            other => other,
        })
    }

    /// Makes the scene of `description` and checks it as a whole.
    fn finish_scene(
        &self,
        file: &SceneToml,
        description: SceneDescription,
    ) -> Result<Scene, Error> {
        // The scene-wide checks (the camera, the merged geometry) name the file; a camera
        // error its table's line, the others no line.
        let camera_at = file.camera.as_ref().map(|c| c.span().start);
        Scene::new(description).map_err(|e| match e {
            Error::Scene { reason, .. } => {
                self.at
                    .set(camera_at.filter(|_| reason.starts_with("camera")));
                self.fail(reason)
            }
            other => other,
        })
    }

    /// The `[environment]` table: checks the mapping and scale, and loads the probe.
    fn environment(&self, env: &EnvironmentToml) -> Result<EnvironmentMap, Error> {
        let mapping = ProbeMapping::from_name(&env.mapping).ok_or_else(|| {
            self.fail(format!(
                "environment: mapping is '{}'; expected \"angular\" (a light probe's angular map) or \"latlong\" (a latitude–longitude map)",
                env.mapping.escape_debug()
            ))
        })?;
        let scale = env.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale > 0.0) {
            return Err(self.fail(format!(
                "environment: scale is {scale}; expected a positive number"
            )));
        }
        let path = self.base_dir.join(&env.probe);
        let named_by = format!("the probe of [environment] {}", self.place());
        let texture = Texture::load_for(&path, &named_by)?;
        Ok(EnvironmentMap {
            texture: Arc::new(texture),
            mapping,
            scale,
        })
    }

    /// A material table: checks its values and loads its texture.
    fn material(
        &self,
        key: &str,
        m: &MaterialToml,
        textures: &mut HashMap<PathBuf, Arc<Texture>>,
    ) -> Result<Material, Error> {
        let what = format!("materials.{}", key.escape_debug());
        let illum = u8::try_from(m.illum)
            .ok()
            .and_then(IllumModel::from_illum)
            .ok_or_else(|| {
                self.fail(format!(
                    "{what}: illum {} has no raylab shader; expected one of {}",
                    m.illum,
                    accepted_illums()
                ))
            })?;
        let colour = |field: &str, value: Option<[f32; 3]>, default: Vec3| {
            let c = value.map_or(default, Vec3::from);
            if c.is_finite() && c.min_element() >= 0.0 {
                Ok(c)
            } else {
                Err(self.fail(format!(
                    "{what}: {field} is {c}; expected finite non-negative numbers"
                )))
            }
        };
        let mut material =
            Material::lambertian(key, colour("diffuse", m.diffuse, Vec3::splat(0.8))?);
        material.illum = illum;
        material.specular = colour("specular", m.specular, Vec3::ZERO)?;
        material.ambient = colour("ambient", m.ambient, Vec3::ZERO)?;
        material.emission = colour("emission", m.emission, Vec3::ZERO)?;
        material.transmission = colour("transmission", m.transmission, Vec3::ONE)?;
        if let Some(s) = m.shininess {
            if !(s.is_finite() && s >= 0.0) {
                return Err(self.fail(format!(
                    "{what}: shininess is {s}; expected a non-negative number"
                )));
            }
            material.shininess = s;
        }
        if let Some(r) = m.roughness {
            if !(r > 0.0 && r <= 1.0) {
                return Err(self.fail(format!(
                    "{what}: roughness is {r}; expected a number in (0, 1]"
                )));
            }
            material.roughness = Some(r);
        }
        if let Some(model) = &m.model {
            let name_like = !model.is_empty()
                && model.len() <= 64
                && model
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
            if !name_like {
                return Err(self.fail(format!(
                    "{what}: model is {:?}; expected the name of a surface model (letters, digits, '-' and '_', at most 64)",
                    model.escape_debug().to_string()
                )));
            }
            material.model = Some(model.clone());
        }
        if let Some(ior) = m.ior {
            if !(ior.is_finite() && ior > 0.0) {
                return Err(self.fail(format!("{what}: ior is {ior}; expected a positive number")));
            }
            material.ior = ior;
        }
        if let Some(file) = &m.texture {
            let path = self.base_dir.join(file);
            let texture = match textures.get(&path) {
                Some(t) => Arc::clone(t),
                None => {
                    let statement = format!("the texture of {what} {}", self.place());
                    let t = Arc::new(Texture::load_for(&path, &statement)?);
                    textures.insert(path, Arc::clone(&t));
                    t
                }
            };
            material.diffuse_texture = Some(texture);
        }
        Ok(material)
    }

    /// Applies a mesh entry's transform: scale, then rotation about y, then translation.
    fn transform(&self, what: &str, m: &MeshToml, mut mesh: Mesh) -> Result<Mesh, Error> {
        let scale = match m.scale {
            None => Vec3::ONE,
            Some(Scale::Uniform(s)) => Vec3::splat(s),
            Some(Scale::PerAxis(s)) => Vec3::from(s),
        };
        if !scale.is_finite() || scale.cmpeq(Vec3::ZERO).any() {
            return Err(self.fail(format!(
                "{what}: scale is {scale}; expected finite non-zero numbers"
            )));
        }
        let degrees = m.rotate_y_degrees.unwrap_or(0.0);
        let translate = m.translate.map_or(Vec3::ZERO, Vec3::from);
        if !(degrees.is_finite() && translate.is_finite()) {
            return Err(self.fail(format!(
                "{what}: rotate_y_degrees {degrees} and translate {translate}; expected finite numbers"
            )));
        }
        let rotation = Quat::from_rotation_y(degrees.to_radians());
        for p in &mut mesh.positions {
            *p = rotation * (scale * *p) + translate;
        }
        // Normals transform by the inverse transpose of rotation·scale, i.e. rotation·scale⁻¹.
        let inverse_scale = scale.recip();
        for n in &mut mesh.normals {
            *n = (rotation * (inverse_scale * *n)).normalize_or_zero();
        }
        // A mirroring scale reverses the winding: swap two corners to keep the face normals
        // on the same side as the vertex normals.
        if scale.x * scale.y * scale.z < 0.0 {
            for f in &mut mesh.faces {
                f.swap(1, 2);
            }
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, empty directory under the system's temporary directory.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("raylab-scene-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const CAMERA: &str = "
[camera]
eye = [0, 1, 5]
look_at = [0, 0, 0]
up = [0, 1, 0]
focal_distance = 1.0
";

    #[test]
    fn environment_table_is_checked() {
        let e = scene_file_error(&format!(
            "[environment]\nprobe = \"sky.hdr\"\nmapping = \"sphere\"\n{CAMERA}"
        ));
        assert!(
            e.contains("line 1") && e.contains("mapping is 'sphere'") && e.contains("latlong"),
            "{e}"
        );
        let e = scene_file_error(&format!(
            "[environment]\nprobe = \"sky.hdr\"\nmapping = \"angular\"\nscale = -1\n{CAMERA}"
        ));
        assert!(e.contains("scale is -1"), "{e}");
        let e = parse_scene_str(
            "bad.toml",
            &format!("[environment]\nprobe = \"missing.hdr\"\nmapping = \"angular\"\n{CAMERA}"),
            Path::new("."),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("missing.hdr")
                && e.contains("the probe of [environment] at bad.toml, line 1"),
            "{e}"
        );
        let scene = parse_scene_str("ok.toml", CAMERA, Path::new(".")).unwrap();
        assert!(scene.environment.is_none());
    }

    /// The `SceneFile` error message for `text`.
    fn scene_file_error(text: &str) -> String {
        match parse_scene_str("bad.toml", text, Path::new(".")) {
            Err(e @ Error::SceneFile { .. }) => {
                let message = e.to_string();
                assert!(message.starts_with("bad.toml: "), "{message}");
                message
            }
            other => panic!("expected a scene file error, got {other:?}"),
        }
    }

    #[test]
    fn full_scene_parses() {
        let text = format!(
            r#"
name = "test scene"
background = [0.1, 0.3, 0.6]
{CAMERA}
[materials.red]
diffuse = [0.8, 0.1, 0.1]

[materials.glass]
illum = 4
ior = 1.5
specular = [1, 1, 1]
transmission = [0.9, 0.9, 1.0]
shininess = 10

[materials.lamp]
emission = [5, 5, 5]

[[lights]]
type = "point"
position = [0, 5, 0]
intensity = [10, 10, 10]

[[lights]]
type = "directional"
direction = [0, -2, 0]
emission = [1, 1, 1]

[[planes]]
point = [0, -1, 0]
normal = [0, 2, 0]
material = "red"
tex_scale = 0.5

[[spheres]]
center = [0, 0, 0]
radius = 1
material = "glass"
"#
        );
        let scene = parse_scene_str("full.toml", &text, Path::new(".")).unwrap();
        assert_eq!(scene.name, "test scene");
        assert_eq!(scene.background, Vec3::new(0.1, 0.3, 0.6));
        assert_eq!(scene.camera.eye, Vec3::new(0.0, 1.0, 5.0));
        assert_eq!(scene.camera.focal_distance, 1.0);
        // Materials sorted by name.
        let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["glass", "lamp", "red"]);
        let glass = &scene.materials[0];
        assert_eq!(glass.illum, IllumModel::Transparent);
        assert_eq!((glass.ior, glass.shininess), (1.5, 10.0));
        assert_eq!(glass.transmission, Vec3::new(0.9, 0.9, 1.0));
        assert_eq!(glass.diffuse, Vec3::splat(0.8));
        assert_eq!(scene.materials[1].emission, Vec3::splat(5.0));
        assert_eq!(scene.lights.len(), 2);
        assert_eq!(
            scene.lights[1],
            Light::Directional(DirectionalLight {
                direction: -Vec3::Y,
                emission: Vec3::ONE
            })
        );
        assert_eq!(scene.planes.len(), 1);
        assert_eq!(scene.planes[0].normal, Vec3::Y);
        assert_eq!(scene.planes[0].d, 1.0);
        assert_eq!(scene.planes[0].tex_scale, 0.5);
        assert_eq!(scene.planes[0].material, MaterialId(2));
        assert_eq!(scene.spheres[0].material, MaterialId(0));
        assert!(scene.mesh.faces.is_empty());
    }

    #[test]
    fn defaults_apply() {
        let scene = parse_scene_str("dir/minimal.toml", CAMERA, Path::new(".")).unwrap();
        assert_eq!(scene.name, "minimal");
        assert_eq!(scene.background, Vec3::ZERO);
        assert!(scene.lights.is_empty() && scene.materials.is_empty());
        let text = format!("{CAMERA}[materials.m]\n");
        let scene = parse_scene_str("m.toml", &text, Path::new(".")).unwrap();
        let m = &scene.materials[0];
        assert_eq!(
            (m.illum, m.diffuse),
            (IllumModel::Lambertian, Vec3::splat(0.8))
        );
        assert_eq!((m.ior, m.transmission), (1.0, Vec3::ONE));
    }

    #[test]
    fn scene_without_camera_is_rejected() {
        let message = scene_file_error("name = \"x\"\n");
        assert!(message.contains("[camera]"), "{message}");
        assert!(message.contains("focal_distance"), "{message}");
        let message = scene_file_error("[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\n");
        assert!(message.contains("up"), "{message}");
    }

    #[test]
    fn unknown_material_name_is_rejected_listing_the_defined_ones() {
        let text = format!(
            "{CAMERA}[materials.red]\n[materials.white]\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"blue\"\n"
        );
        let message = scene_file_error(&text);
        assert!(message.contains("spheres[0]"), "{message}");
        assert!(message.contains("'blue'"), "{message}");
        assert!(message.contains("'red', 'white'"), "{message}");
        let text = format!(
            "{CAMERA}[[planes]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"x\"\n"
        );
        let message = scene_file_error(&text);
        assert!(
            message.contains("planes[0]") && message.contains("'x'"),
            "{message}"
        );
    }

    #[test]
    fn unknown_key_is_rejected_with_its_line() {
        let text = format!("{CAMERA}[materials.red]\ncolour = [1, 0, 0]\n");
        let message = scene_file_error(&text);
        assert!(message.contains("line 8"), "{message}");
        assert!(message.contains("colour"), "{message}");
        let message = scene_file_error(&format!("fov = 45\n{CAMERA}"));
        assert!(
            message.contains("line 1") && message.contains("fov"),
            "{message}"
        );
        let message = scene_file_error(&format!(
            "{CAMERA}[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = [1, 1, 1]\nradius = 2\n"
        ));
        assert!(message.contains("radius"), "{message}");
        let message = scene_file_error(&format!(
            "{CAMERA}[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\n"
        ));
        assert!(message.contains("spot"), "{message}");
    }

    #[test]
    fn broken_syntax_reports_the_line() {
        let message = scene_file_error("name = \"x\"\n\neye = [0, 1\n");
        assert!(message.contains("line 3"), "{message}");
    }

    #[test]
    fn bad_values_are_rejected() {
        let message = scene_file_error(&format!("{CAMERA}[materials.m]\nillum = 9\n"));
        assert!(
            message.contains("materials.m") && message.contains("illum 9"),
            "{message}"
        );
        assert!(
            message.contains("0, 1, 2, 3, 4, 5, 6, 7, 11, 12"),
            "{message}"
        );
        let message = scene_file_error(&format!("{CAMERA}[materials.m]\ndiffuse = [1, -1, 0]\n"));
        assert!(message.contains("diffuse"), "{message}");
        let message = scene_file_error(&format!("{CAMERA}[materials.m]\nior = 0\n"));
        assert!(message.contains("ior"), "{message}");
        for bad in ["0", "1.5", "-0.5", "nan"] {
            let message = scene_file_error(&format!("{CAMERA}[materials.m]\nroughness = {bad}\n"));
            assert!(
                message.contains("materials.m: roughness") && message.contains("(0, 1]"),
                "{message}"
            );
        }
        for bad in ["", "a b", "gr\\u00e9y", &"x".repeat(65)] {
            let message = scene_file_error(&format!("{CAMERA}[materials.m]\nmodel = \"{bad}\"\n"));
            assert!(
                message.contains("materials.m: model") && message.contains("surface model"),
                "{message}"
            );
        }
        let named = format!("{CAMERA}[materials.m]\nmodel = \"grey-2_b\"\n");
        let scene = parse_scene_str("ok.toml", &named, Path::new(".")).unwrap();
        assert_eq!(scene.materials[0].model.as_deref(), Some("grey-2_b"));
        let message = scene_file_error(&format!("{CAMERA}[materials.m]\ndiffuse = [1, 0]\n"));
        assert!(message.contains("line 8"), "{message}");
        let message = scene_file_error(&format!(
            "{CAMERA}[[lights]]\ntype = \"directional\"\ndirection = [0, 0, 0]\nemission = [1, 1, 1]\n"
        ));
        assert!(message.contains("lights[0]"), "{message}");
        let message = scene_file_error(&format!(
            "{CAMERA}[materials.m]\n[[spheres]]\ncenter = [0, 0, 0]\nradius = -1\nmaterial = \"m\"\n"
        ));
        assert!(
            message.contains("spheres[0]") && message.contains("-1"),
            "{message}"
        );
        let message = scene_file_error(&format!(
            "{CAMERA}[materials.m]\n[[planes]]\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\nmaterial = \"m\"\n"
        ));
        assert!(message.contains("planes[0]"), "{message}");
        let message = scene_file_error(&format!(
            "{CAMERA}[[meshes]]\nfile = \"x.obj\"\nscale = \"big\"\n"
        ));
        assert!(
            message.contains("a number or an array of three numbers"),
            "{message}"
        );
        let message = scene_file_error(
            "background = [nan, 0, 0]\n[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1.0\n",
        );
        assert!(message.contains("background"), "{message}");
    }

    #[test]
    fn value_errors_name_the_line_of_their_entry() {
        // CAMERA is lines 1-6; the sphere's table starts on line 9.
        let message = scene_file_error(&format!(
            "{CAMERA}[materials.m]\n\n[[spheres]]\ncenter = [0, 0, 0]\nradius = -1\nmaterial = \"m\"\n"
        ));
        assert!(
            message.starts_with("bad.toml: line 9, column 1: spheres[0]: "),
            "{message}"
        );
        let message = scene_file_error(&format!(
            "{CAMERA}[[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = [1, 1, 1]\n\
             [[lights]]\ntype = \"directional\"\ndirection = [0, 0, 0]\nemission = [1, 1, 1]\n"
        ));
        assert!(
            message.contains("line 11") && message.contains("lights[1]"),
            "{message}"
        );
        let message = scene_file_error(&format!("{CAMERA}[materials.m]\nior = 0\n"));
        assert!(
            message.contains("line 7") && message.contains("materials.m"),
            "{message}"
        );
        let message = scene_file_error("x = 1\n[camera]\neye = [0, 1, [2]]\n");
        assert!(message.starts_with("bad.toml: line "), "{message}");
        assert!(!message.contains('\n'), "{message}");
    }

    #[test]
    fn scene_wide_errors_name_the_file_without_debug_dumps() {
        let message = scene_file_error(
            "\n[camera]\neye = [0, 0, 0]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1.0\n",
        );
        assert_eq!(
            message,
            "bad.toml: line 2, column 1: camera eye and look_at are the same point"
        );
        let message = scene_file_error(
            "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nfocal_distance = 1.0\n",
        );
        assert!(
            message.contains("bad.toml") && message.contains("parallel"),
            "{message}"
        );
        assert!(
            !message.contains("CameraSetup") && !message.contains('{'),
            "{message}"
        );
    }

    #[test]
    fn texture_errors_name_the_material_and_its_line() {
        let dir = temp_dir("bad-texture");
        std::fs::write(dir.join("tex.png"), b"not a PNG").unwrap();
        let scene = dir.join("scene.toml");
        std::fs::write(
            &scene,
            format!("{CAMERA}\n[materials.floor]\ntexture = \"tex.png\"\n"),
        )
        .unwrap();
        match load_scene_file(&scene) {
            Err(e @ Error::Texture { .. }) => {
                let message = e.to_string();
                assert!(
                    message.contains("tex.png: cannot read the texture of materials.floor at ")
                        && message.contains("scene.toml, line 8, column 1: "),
                    "{message}"
                );
            }
            other => panic!("expected a texture error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A texture that is not there names the file, the entry that named it and that entry's
    /// line; one named by the MTL file of a mesh names the MTL line and the mesh's entry.
    #[test]
    fn a_missing_texture_names_the_file_and_what_named_it() {
        let dir = temp_dir("missing-texture");
        let scene = dir.join("scene.toml");
        std::fs::write(
            &scene,
            format!("{CAMERA}\n[materials.floor]\ntexture = \"nothere.png\"\n"),
        )
        .unwrap();
        let message = load_scene_file(&scene).unwrap_err().to_string();
        assert_eq!(
            message,
            format!(
                "{}: cannot read the texture of materials.floor at {}, line 8, column 1: No such file or directory (os error 2)",
                dir.join("nothere.png").display(),
                scene.display()
            )
        );
        std::fs::write(dir.join("m.mtl"), "newmtl a\nKd 1 1 1\nmap_Kd gone.png\n").unwrap();
        std::fs::write(
            dir.join("tri.obj"),
            "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
        )
        .unwrap();
        std::fs::write(&scene, format!("{CAMERA}[[meshes]]\nfile = \"tri.obj\"\n")).unwrap();
        let message = load_scene_file(&scene).unwrap_err().to_string();
        assert_eq!(
            message,
            format!(
                "{}: cannot read the texture map_Kd of material 'a' at {}:3, in the OBJ file of meshes[0] at {}, line 7, column 1: No such file or directory (os error 2)",
                dir.join("gone.png").display(),
                dir.join("m.mtl").display(),
                scene.display()
            )
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn meshes_are_transformed_and_take_their_materials() {
        let dir = temp_dir("mesh");
        std::fs::write(
            dir.join("tri.obj"),
            "mtllib tri.mtl\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 2 0 0\nusemtl lamp\nf 1//1 2//1 3//1\n",
        )
        .unwrap();
        std::fs::write(dir.join("tri.mtl"), "newmtl lamp\nKe 1 1 1\n").unwrap();
        let scene_path = dir.join("scene.toml");
        std::fs::write(
            &scene_path,
            format!(
                "{CAMERA}[materials.grey]\n\
                 [[meshes]]\nfile = \"tri.obj\"\nscale = [2, 1, 1]\nrotate_y_degrees = 90\ntranslate = [0, 10, 0]\n\
                 [[meshes]]\nfile = \"tri.obj\"\nscale = -1\nmaterial = \"grey\"\n"
            ),
        )
        .unwrap();
        let scene = load_scene_file(&scene_path).unwrap();
        assert_eq!(scene.name, "scene");
        let mesh = &scene.mesh;
        assert_eq!(mesh.faces.len(), 2);
        // Scale (2,1,1), rotate 90° about y (x → -z), translate (0,10,0).
        let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
        assert!(
            close(mesh.positions[0], Vec3::new(0.0, 10.0, -2.0)),
            "{}",
            mesh.positions[0]
        );
        assert!(close(mesh.positions[1], Vec3::new(0.0, 11.0, 0.0)));
        assert!(close(mesh.positions[2], Vec3::new(1.0, 10.0, 0.0)));
        assert!(close(mesh.normals[0], -Vec3::Z), "{}", mesh.normals[0]);
        // The mirrored copy: normal flipped, winding swapped to match.
        assert!(close(mesh.normals[3], -Vec3::X), "{}", mesh.normals[3]);
        let [a, b, c] = mesh.triangle(1);
        assert!((b - a).cross(c - a).dot(mesh.normals[3]) > 0.0);
        // The first copy keeps the OBJ's material (appended after the scene's), the second is
        // overridden; the emissive triangle becomes an area light.
        let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        assert_eq!(names, ["grey", "lamp"]);
        assert_eq!(mesh.face_materials, [MaterialId(1), MaterialId(0)]);
        assert!(matches!(&scene.lights[..], [Light::Area(a)] if a.faces == [0]));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn mesh_errors_name_the_files() {
        let dir = temp_dir("mesh-errors");
        let scene_path = dir.join("scene.toml");
        std::fs::write(
            &scene_path,
            format!("{CAMERA}[[meshes]]\nfile = \"nothere.obj\"\n"),
        )
        .unwrap();
        match load_scene_file(&scene_path) {
            Err(e @ Error::SceneFile { .. }) => {
                let message = e.to_string();
                assert!(
                    message.contains("scene.toml") && message.contains("nothere.obj"),
                    "{message}"
                );
            }
            other => panic!("expected a scene file error, got {other:?}"),
        }
        std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 0 0\n").unwrap();
        std::fs::write(
            &scene_path,
            format!("{CAMERA}[[meshes]]\nfile = \"bad.obj\"\n"),
        )
        .unwrap();
        match load_scene_file(&scene_path) {
            Err(Error::Parse { path, line, .. }) => {
                assert_eq!((path, line), (dir.join("bad.obj"), 2));
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn missing_scene_file_is_an_io_error() {
        match load_scene_file(Path::new("/nonexistent/raylab/scene.toml")) {
            Err(e @ Error::Io { .. }) => assert!(e.to_string().contains("scene.toml")),
            other => panic!("expected an I/O error, got {other:?}"),
        }
    }

    #[test]
    fn textures_load_relative_to_the_scene_file() {
        let dir = temp_dir("texture");
        image::RgbImage::new(3, 1).save(dir.join("ok.png")).unwrap();
        std::fs::write(dir.join("garbage.png"), [0u8, 1, 2, 3, 4, 5, 6, 7]).unwrap();
        let text = format!("{CAMERA}[materials.m]\ntexture = \"ok.png\"\n");
        let scene = parse_scene_str("t.toml", &text, &dir).unwrap();
        let texture = scene.materials[0].diffuse_texture.as_ref().unwrap();
        assert_eq!((texture.width, texture.height), (3, 1));
        let text = format!("{CAMERA}[materials.m]\ntexture = \"garbage.png\"\n");
        match parse_scene_str("t.toml", &text, &dir) {
            Err(e @ Error::Texture { .. }) => assert!(e.to_string().contains("garbage.png")),
            other => panic!("expected a texture error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

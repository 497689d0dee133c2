//! Scenes: geometry (planes, spheres, triangle meshes), materials, lights and the camera, loaded
//! from OBJ/MTL files, from a scene file, or from the embedded scenes; the scene-level ray
//! queries `trace_to_closest` / `trace_to_any` of the DTU `RayTracer`, and the [`Hit`] they
//! return.

mod builtin;
mod environment;
mod file;
mod obj;
mod texture_file;
mod trace;

pub use builtin::{BUILTIN_SCENES, builtin_scene};
pub use environment::{EnvironmentMap, ProbeMapping, ProceduralProbe};
pub use file::{load_scene_file, parse_scene_str};
pub use obj::{ObjData, load_obj, load_obj_str};
pub use raylab_types::scene::*;
pub use texture_file::TextureFile;
pub use trace::{PrimitiveHit, PrimitiveTests};

use glam::Vec3;

use crate::Error;
use crate::accel::{Bvh, TriangleBvh};

/// A scene ready to render: geometry with its acceleration structures, materials, lights and
/// camera. Build it with [`Scene::new`], [`load_scene_file`] or [`builtin_scene`].
#[derive(Debug)]
pub struct Scene {
    /// Name shown in reports (file name or built-in scene name).
    pub name: String,
    /// The camera.
    pub camera: CameraSetup,
    /// Colour of rays that hit nothing.
    pub background: Vec3,
    /// The light probe around the scene, if any: from lab 11 on the radiance of rays that hit
    /// nothing, and the light of ambient occlusion.
    pub environment: Option<EnvironmentMap>,
    /// All materials; geometry refers to them by [`MaterialId`].
    pub materials: Vec<Material>,
    /// Light sources, including one [`AreaLight`] for all emissive triangles.
    pub lights: Vec<Light>,
    /// Infinite planes (tested one by one: they have no bounds).
    pub planes: Vec<Plane>,
    /// Spheres (in their own BVH).
    pub spheres: Vec<Sphere>,
    /// All triangles of all meshes, merged into one mesh (in a BVH).
    pub mesh: Mesh,
    pub(crate) triangle_bvh: TriangleBvh,
    pub(crate) sphere_bvh: Bvh,
}

/// The parts of a scene before it is checked and its BVHs are built.
#[derive(Clone, Debug, Default)]
pub struct SceneDescription {
    /// Name shown in reports.
    pub name: String,
    /// The camera; a scene without one is rejected.
    pub camera: Option<CameraSetup>,
    /// Colour of rays that hit nothing.
    pub background: Vec3,
    /// The light probe around the scene, if any (lab 11).
    pub environment: Option<EnvironmentMap>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Point and directional lights (area lights are found from emissive materials).
    pub lights: Vec<Light>,
    /// Planes.
    pub planes: Vec<Plane>,
    /// Spheres.
    pub spheres: Vec<Sphere>,
    /// Triangles.
    pub mesh: Mesh,
}

impl Scene {
    /// Checks a description (finite numbers, valid material references, a camera) and builds
    /// the acceleration structures.
    pub fn new(desc: SceneDescription) -> Result<Self, Error> {
        let SceneDescription {
            name,
            camera,
            background,
            environment,
            materials,
            mut lights,
            planes,
            spheres,
            mesh,
        } = desc;
        let camera = camera.ok_or_else(|| Error::Scene {
            scene: name.clone(),
            reason: "the scene has no camera; expected a [camera] table with eye, look_at, up and focal_distance".into(),
        })?;
        validate(
            &name, &camera, &materials, &lights, &planes, &spheres, &mesh,
        )?;
        let triangle_bvh = TriangleBvh::build(
            &(0..mesh.faces.len())
                .map(|f| mesh.triangle(f))
                .collect::<Vec<_>>(),
        );
        let sphere_bvh = Bvh::build(&spheres.iter().map(Sphere::bounds).collect::<Vec<_>>());
        let emissive: Vec<u32> = (0..mesh.faces.len() as u32)
            .filter(|&f| materials[mesh.face_materials[f as usize].0 as usize].is_emissive())
            .collect();
        if !emissive.is_empty() {
            let areas: Vec<f32> = emissive
                .iter()
                .map(|&f| {
                    let [a, b, c] = mesh.triangle(f as usize);
                    0.5 * (b - a).cross(c - a).length()
                })
                .collect();
            lights.push(Light::Area(AreaLight::new(emissive, &areas)));
        }
        Ok(Self {
            name,
            camera,
            background,
            environment,
            materials,
            lights,
            planes,
            spheres,
            mesh,
            triangle_bvh,
            sphere_bvh,
        })
    }

    /// The material with the given id.
    #[inline]
    pub fn material(&self, id: crate::scene::MaterialId) -> &Material {
        &self.materials[id.0 as usize]
    }

    /// The box around the scene's finite geometry (spheres and triangles; a plane has no
    /// bounds), `None` without any.
    pub fn bounds(&self) -> Option<crate::math::Aabb> {
        let spheres = self.spheres.iter().map(Sphere::bounds);
        let triangles = (0..self.mesh.faces.len())
            .map(|f| crate::math::Aabb::from_points(self.mesh.triangle(f)));
        let bounds = spheres
            .chain(triangles)
            .fold(crate::math::Aabb::EMPTY, crate::math::Aabb::union);
        (!bounds.is_empty()).then_some(bounds)
    }
}

fn validate(
    name: &str,
    camera: &CameraSetup,
    materials: &[Material],
    lights: &[Light],
    planes: &[Plane],
    spheres: &[Sphere],
    mesh: &Mesh,
) -> Result<(), Error> {
    let bad = |reason: String| Error::Scene {
        scene: name.to_string(),
        reason,
    };
    let finite = |v: Vec3| v.is_finite();
    if !(finite(camera.eye) && finite(camera.look_at) && finite(camera.up)) {
        return Err(bad(format!(
            "camera has a non-finite vector: eye {}, look_at {}, up {}; expected finite numbers",
            camera.eye, camera.look_at, camera.up
        )));
    }
    if !(camera.focal_distance.is_finite() && camera.focal_distance > 0.0) {
        return Err(bad(format!(
            "camera focal_distance is {}; expected a positive number",
            camera.focal_distance
        )));
    }
    let view = camera.look_at - camera.eye;
    if view.length_squared() == 0.0 {
        return Err(bad("camera eye and look_at are the same point".into()));
    }
    if view.cross(camera.up).length_squared()
        <= 1e-12 * view.length_squared() * camera.up.length_squared()
    {
        return Err(bad(format!(
            "camera up {} is zero or parallel to the view direction {}",
            camera.up, view
        )));
    }
    let check_material = |what: String, id: MaterialId| {
        if (id.0 as usize) < materials.len() {
            Ok(())
        } else {
            Err(bad(format!(
                "{what} refers to material #{} but the scene has {}",
                id.0,
                materials.len()
            )))
        }
    };
    for (i, p) in planes.iter().enumerate() {
        if !(p.normal.is_finite() && p.d.is_finite()) || p.normal.length_squared() == 0.0 {
            return Err(bad(format!(
                "plane #{i} has a non-finite or zero normal/offset"
            )));
        }
        check_material(format!("plane #{i}"), p.material)?;
    }
    for (i, s) in spheres.iter().enumerate() {
        if !(s.center.is_finite() && s.radius.is_finite() && s.radius > 0.0) {
            return Err(bad(format!(
                "sphere #{i} has centre {} and radius {}; expected finite numbers and a positive radius",
                s.center, s.radius
            )));
        }
        check_material(format!("sphere #{i}"), s.material)?;
    }
    for (i, p) in mesh.positions.iter().enumerate() {
        if !p.is_finite() {
            return Err(bad(format!(
                "vertex #{i} is {p}; expected finite coordinates"
            )));
        }
    }
    for (f, face) in mesh.faces.iter().enumerate() {
        if face.iter().any(|&i| i as usize >= mesh.positions.len()) {
            return Err(bad(format!(
                "triangle #{f} refers to vertices {}, {} and {} but the mesh has {}",
                face[0],
                face[1],
                face[2],
                mesh.positions.len()
            )));
        }
        check_material(format!("triangle #{f}"), mesh.face_materials[f])?;
    }
    for (i, l) in lights.iter().enumerate() {
        let ok = match l {
            Light::Point(p) => p.position.is_finite() && p.intensity.is_finite(),
            Light::Directional(d) => {
                d.direction.is_finite()
                    && d.direction.length_squared() > 0.0
                    && d.emission.is_finite()
            }
            Light::Area(_) => true,
        };
        if !ok {
            let what = match l {
                Light::Point(p) => format!(
                    "point light at {} with intensity {}",
                    p.position, p.intensity
                ),
                Light::Directional(d) => format!(
                    "directional light with direction {} and emission {}",
                    d.direction, d.emission
                ),
                Light::Area(_) => "area light".to_string(),
            };
            return Err(bad(format!(
                "light #{i} ({what}) has a non-finite or zero vector; expected finite numbers and a non-zero direction"
            )));
        }
    }
    Ok(())
}

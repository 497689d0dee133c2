//! Whether two engines find the same hits on the same rays.

use raylab_core::math::Ray;

use super::engine::{Engine, EngineHit};

/// Relative tolerance on the hit distance: two hits agree when their `t` differ by at most
/// `T_TOLERANCE · max(1, t)`.
pub const T_TOLERANCE: f32 = 1e-4;

/// How the answers of an engine compare with a reference engine's over one ray set.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Agreement {
    /// Rays compared.
    pub rays: usize,
    /// Rays on which both hit at the same distance (within [`T_TOLERANCE`]) or both missed.
    pub closest_agree: usize,
    /// Rays on which both hit, at the same distance, the same triangle (where both name it).
    pub same_triangle: usize,
    /// Rays that one engine hit and the other missed.
    pub hit_miss: usize,
    /// Rays that both hit, at distances further apart than the tolerance.
    pub distance: usize,
    /// Rays on which the engine's any-hit answer equals the reference's closest-hit hit/miss.
    pub any_agree: usize,
}

impl Agreement {
    /// Fraction of rays whose closest hits agree.
    pub fn closest_rate(&self) -> f64 {
        self.closest_agree as f64 / self.rays.max(1) as f64
    }

    /// Fraction of rays whose any-hit answers agree.
    pub fn any_rate(&self) -> f64 {
        self.any_agree as f64 / self.rays.max(1) as f64
    }
}

/// Whether two closest hits agree: both miss, or both hit within the distance tolerance.
pub fn same_hit(a: Option<EngineHit>, b: Option<EngineHit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => (a.t - b.t).abs() <= T_TOLERANCE * a.t.abs().max(1.0),
        _ => false,
    }
}

/// Compares `engine` with the answers `reference` (closest hits of the reference engine on
/// `rays`, in order).
pub fn compare(engine: &dyn Engine, rays: &[Ray], reference: &[Option<EngineHit>]) -> Agreement {
    let mut a = Agreement {
        rays: rays.len(),
        ..Agreement::default()
    };
    for (ray, &expected) in rays.iter().zip(reference) {
        let got = engine.closest(ray);
        if same_hit(expected, got) {
            a.closest_agree += 1;
            if let (Some(e), Some(g)) = (expected, got) {
                if e.prim.is_none() || g.prim.is_none() || e.prim == g.prim {
                    a.same_triangle += 1;
                }
            }
        } else if expected.is_some() != got.is_some() {
            a.hit_miss += 1;
        } else {
            a.distance += 1;
        }
        if engine.any(ray) == expected.is_some() {
            a.any_agree += 1;
        }
    }
    a
}

#[cfg(test)]
mod tests {
    use raylab_core::glam::Vec3;
    use raylab_core::scene::builtin_scene;

    use super::super::engine::{Core, SceneQuery};
    #[cfg(feature = "obvhs")]
    use super::super::peer_obvhs::{Kernel, Obvhs};
    use super::super::scenes::{bumpy_sphere, camera_rays, diffuse_rays, mesh_scene, triangles};
    use super::*;

    #[test]
    fn tolerance_is_relative_beyond_one() {
        let hit = |t| Some(EngineHit { t, prim: None });
        assert!(same_hit(None, None));
        assert!(!same_hit(hit(1.0), None));
        assert!(same_hit(hit(0.5), hit(0.5 + 0.5e-4)));
        assert!(!same_hit(hit(0.5), hit(0.5 + 2e-4)));
        assert!(same_hit(hit(100.0), hit(100.005)));
        assert!(!same_hit(hit(100.0), hit(100.02)));
    }

    /// The core's BVH, the scene's own queries and, with the `obvhs` feature, obvhs (with both
    /// triangle tests) agree on camera and diffuse rays through the Cornell box and a small
    /// bumpy sphere.
    #[test]
    fn core_and_peers_agree() {
        let cornell = builtin_scene("cornell").unwrap();
        let sphere = mesh_scene("sphere", bumpy_sphere(30, 40)).unwrap();
        for scene in [&cornell, &sphere] {
            let core = Core::build(&triangles(scene));
            #[cfg(feature = "obvhs")]
            let tris = triangles(scene);
            let primary = camera_rays(scene, 48);
            let diffuse = diffuse_rays(scene, &primary);
            assert!(diffuse.len() > 500, "{}", diffuse.len());
            for rays in [&primary, &diffuse] {
                let reference: Vec<_> = rays.iter().map(|r| core.closest(r)).collect();
                assert!(reference.iter().any(Option::is_some));
                assert_eq!(compare(&core, rays, &reference).closest_agree, rays.len());
                let query = compare(&SceneQuery(scene), rays, &reference);
                assert!(
                    query.closest_rate() > 0.999 && query.any_rate() > 0.999,
                    "{}: {query:?}",
                    scene.name
                );
                #[cfg(feature = "obvhs")]
                for kernel in [Kernel::Obvhs, Kernel::Framework] {
                    let a = compare(&Obvhs::build(&tris, kernel), rays, &reference);
                    assert!(
                        a.closest_rate() > 0.999 && a.any_rate() > 0.999,
                        "{}: {kernel:?} {a:?}",
                        scene.name
                    );
                    if kernel == Kernel::Framework {
                        assert_eq!(a.closest_agree, a.rays, "same kernel, same hits: {a:?}");
                    }
                }
            }
        }
        // A ray that misses everything agrees too.
        let away = Ray::unbounded(Vec3::splat(100.0), Vec3::X, 0.0);
        let core = Core::build(&triangles(&cornell));
        assert_eq!(compare(&core, &[away], &[None]).closest_agree, 1);
    }
}

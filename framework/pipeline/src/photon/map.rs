//! The photon map: photons stored at surfaces, in a k-d tree for the queries of the radiance
//! estimate (the `k` nearest within a maximum radius, and all within a radius).
//!
//! The tree is the framework's own balanced 3-d tree ([`KdTree`], `kdtree.rs`), built once from
//! the photons in the order the tracer stored them. Its answers depend on the photons alone
//! (ranked by squared distance, then by order of storage), so the same photons give the same
//! answers on any number of threads.

use glam::Vec3;

use super::kdtree::KdTree;
use contracts::lab08::NearbyPhoton;

/// A photon stored at a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    /// Where it was stored.
    pub position: Vec3,
    /// The unit direction it travelled in when it arrived.
    pub direction: Vec3,
    /// The power it carries.
    pub power: Vec3,
}

/// How many photons to emit, and the radiance estimate's `k` and maximum radius.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PhotonSettings {
    /// Photons emitted by all the lights together (shared among them by power).
    pub emitted: u32,
    /// The estimate gathers the `k` photons nearest to the shading point …
    pub k: u32,
    /// … within this distance (scene units).
    pub max_radius: f32,
    /// Seed of the photons' random numbers (photon `i` draws from stream `i`).
    pub seed: u64,
}

impl PhotonSettings {
    /// A good caustic of the built-in Cornell box with the glass sphere in about two seconds
    /// on two cores: two million photons, `k = 200` within 5 cm. The mirror sphere spreads a
    /// dim caustic glow over the walls and the ceiling, some twenty photons to a 2.5 cm disc of
    /// a million: `k = 50` there shows their noise as blotches; two hundred photons make it
    /// smooth (a relative noise of 7 %), while the glass sphere's caustic, hundreds of times
    /// denser, finds them within a few millimetres and stays sharp (docs/lab08.md).
    pub const DEFAULT: PhotonSettings = PhotonSettings {
        emitted: 2_000_000,
        k: 200,
        max_radius: 0.05,
        seed: 0,
    };

    /// The default radius as a share of the diagonal of the scene's bounds: the 5 cm of
    /// [`PhotonSettings::DEFAULT`] in the built-in Cornell box (0.963 m across).
    pub const RADIUS_PER_DIAGONAL: f32 = 0.052;

    /// The default radius for `scene`: [`PhotonSettings::RADIUS_PER_DIAGONAL`] of the diagonal
    /// of its finite geometry (the default's 2.5 cm without any), so that a scene of metres
    /// and one of millimetres gather over the same share of themselves.
    pub fn radius_for(scene: &raylab_core::scene::Scene) -> f32 {
        scene
            .bounds()
            .map(|b| Self::RADIUS_PER_DIAGONAL * b.diagonal().length())
            .filter(|r| r.is_finite() && *r > 0.0)
            .unwrap_or(Self::DEFAULT.max_radius)
    }

    /// Checks the settings, naming the offending value.
    pub fn validate(&self) -> Result<(), raylab_core::Error> {
        if self.emitted == 0 || self.emitted > 1 << 26 {
            return Err(raylab_core::Error::Invalid {
                what: format!("photon count {}", self.emitted),
                reason: "expected a whole number from 1 to 2^26".into(),
            });
        }
        if self.k == 0 || self.k > 10_000 {
            return Err(raylab_core::Error::Invalid {
                what: format!("photon k {}", self.k),
                reason: "expected a whole number of photons from 1 to 10000".into(),
            });
        }
        if !(self.max_radius.is_finite() && self.max_radius > 0.0) {
            return Err(raylab_core::Error::Invalid {
                what: format!("photon radius {}", self.max_radius),
                reason: "expected a positive, finite distance".into(),
            });
        }
        Ok(())
    }
}

impl Default for PhotonSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Photons in a k-d tree.
pub struct PhotonMap {
    photons: Vec<Photon>,
    tree: KdTree,
}

impl std::fmt::Debug for PhotonMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PhotonMap")
            .field("photons", &self.photons.len())
            .finish()
    }
}

impl PhotonMap {
    /// The map of `photons` (non-finite positions are dropped).
    pub fn new(mut photons: Vec<Photon>) -> Self {
        photons.retain(|p| p.position.is_finite());
        let points: Vec<Vec3> = photons.iter().map(|p| p.position).collect();
        let tree = KdTree::new(&points);
        Self { photons, tree }
    }

    /// The stored photons, in the order they were stored.
    pub fn photons(&self) -> &[Photon] {
        &self.photons
    }

    /// How many photons the map holds.
    pub fn len(&self) -> usize {
        self.photons.len()
    }

    /// Whether the map holds no photon.
    pub fn is_empty(&self) -> bool {
        self.photons.is_empty()
    }

    /// The total power of the stored photons.
    pub fn total_power(&self) -> Vec3 {
        self.photons
            .iter()
            .map(|p| p.power.as_dvec3())
            .sum::<glam::DVec3>()
            .as_vec3()
    }

    /// The at most `k` photons nearest to `point` within `max_radius`, nearest first (ties in
    /// the order of storage). Nothing for a non-finite `point`.
    pub fn nearest(&self, point: Vec3, k: usize, max_radius: f32) -> Vec<NearbyPhoton> {
        self.tree
            .nearest_within(point, k, max_radius * max_radius)
            .into_iter()
            .map(|n| {
                let p = &self.photons[n.index as usize];
                NearbyPhoton {
                    power: p.power,
                    direction: p.direction,
                    distance_squared: n.distance_squared,
                }
            })
            .collect()
    }

    /// Every photon within `radius` of `point`, in the order of storage.
    pub fn within(&self, point: Vec3, radius: f32) -> Vec<&Photon> {
        self.tree
            .within(point, radius * radius)
            .into_iter()
            .map(|i| &self.photons[i as usize])
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use raylab_core::sampling::Rng;

    fn random_photons(n: usize, seed: u64) -> Vec<Photon> {
        let mut rng = Rng::new(seed, 0);
        (0..n)
            .map(|_| Photon {
                position: Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()),
                direction: Vec3::NEG_Y,
                power: Vec3::splat(rng.next_f32()),
            })
            .collect()
    }

    #[test]
    fn nearest_and_within_agree_with_a_linear_search() {
        let photons = random_photons(5000, 3);
        let map = PhotonMap::new(photons.clone());
        let mut rng = Rng::new(4, 0);
        for _ in 0..200 {
            let q = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let (k, r) = (1 + rng.next_below(60) as usize, 0.02 + 0.1 * rng.next_f32());
            let mut brute: Vec<f32> = photons
                .iter()
                .map(|p| p.position.distance_squared(q))
                .filter(|&d| d <= r * r)
                .collect();
            brute.sort_by(f32::total_cmp);
            let found = map.nearest(q, k, r);
            assert_eq!(found.len(), brute.len().min(k));
            for (f, b) in found.iter().zip(&brute) {
                assert!((f.distance_squared - b).abs() <= 1e-6, "{f:?} {b}");
            }
            assert_eq!(map.within(q, r).len(), brute.len());
        }
    }

    #[test]
    fn an_empty_map_finds_nothing() {
        let map = PhotonMap::new(Vec::new());
        assert!(map.nearest(Vec3::ZERO, 10, 1.0).is_empty());
        assert!(map.within(Vec3::ZERO, 1.0).is_empty());
        assert!(map.is_empty());
    }

    #[test]
    fn settings_name_the_bad_value() {
        let bad = PhotonSettings {
            max_radius: f32::NAN,
            ..PhotonSettings::DEFAULT
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("radius NaN")
        );
        assert!(PhotonSettings::DEFAULT.validate().is_ok());
    }
}

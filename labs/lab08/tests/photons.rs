//! Lab 08's photon tracer on the reference: the same map on one and two threads, power
//! conservation (stored ≤ emitted, equal in a closed scene of mirrors), and the caustic of the
//! Cornell box's glass sphere where it belongs, in the map and in the render.

use lab08_checks::checks::{
    CAUSTIC_CENTRE, MIRROR_BOX, caustic_counts, check_scene, glass_caustic,
};
use pipeline::photon::{PhotonSettings, StoreRule, trace_photons, with_caustics};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::render::RenderSettings;
use raylab_core::scene::{IllumModel, builtin_scene};

fn lab8() -> Pipeline {
    reference::pipeline(8)
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn one_and_two_threads_give_the_same_photon_map() {
    let one = on_threads(1, || glass_caustic(&lab8(), 5).unwrap());
    let two = on_threads(2, || glass_caustic(&lab8(), 5).unwrap());
    assert!(one.map.len() > 1000, "{} photons stored", one.map.len());
    assert_eq!(one.map.photons(), two.map.photons());
    assert_eq!(one.stored_power, two.stored_power);
    let other = glass_caustic(&lab8(), 6).unwrap();
    assert_ne!(
        one.map.photons(),
        other.map.photons(),
        "another seed, other photons"
    );
}

#[test]
fn stored_power_never_exceeds_the_emitted_power() {
    let trace = glass_caustic(&lab8(), 7).unwrap();
    let accounted =
        trace.stored_power + trace.direct_power + trace.escaped_power + trace.truncated_power;
    for c in 0..3 {
        assert!(trace.stored_power[c] <= trace.emitted_power[c], "{trace:?}");
        let e = trace.emitted_power[c];
        assert!(
            (accounted[c] - e).abs() <= 1e-6 * e,
            "{accounted} vs {}",
            trace.emitted_power
        );
    }
    // The map holds the photons of the caustic, not the direct light.
    assert!(
        trace.stored_power.x < 0.2 * trace.emitted_power.x,
        "{trace:?}"
    );
}

#[test]
fn a_closed_scene_of_mirrors_stores_all_the_emitted_power() {
    let scene = check_scene("mirror-box", MIRROR_BOX).unwrap();
    let settings = PhotonSettings {
        emitted: 50_000,
        ..PhotonSettings::DEFAULT
    };
    let trace = trace_photons(&lab8(), &scene, &settings, StoreRule::Caustic);
    assert_eq!(trace.escaped_power, raylab_core::glam::DVec3::ZERO);
    assert_eq!(trace.direct_power, raylab_core::glam::DVec3::ZERO);
    for c in 0..3 {
        let (stored, emitted) = (trace.stored_power[c], trace.emitted_power[c]);
        assert!((stored - emitted).abs() <= 1e-3 * emitted, "{trace:?}");
    }
    // The emitted power is the light's 4πI (I = (1, 2, 3)).
    let four_pi = 4.0 * std::f64::consts::PI;
    for (c, i) in [1.0, 2.0, 3.0].into_iter().enumerate() {
        assert!(
            (trace.emitted_power[c] - four_pi * i).abs() <= 1e-4 * four_pi * i,
            "{trace:?}"
        );
    }
}

#[test]
fn the_caustic_is_a_bright_spot_under_the_glass_sphere() {
    let trace = glass_caustic(&lab8(), 9).unwrap();
    let [disc, ring, all] = caustic_counts(&trace);
    // A disc of 3 cm holds a third of all caustic photons; the ring around it (an area five
    // times larger) far fewer per area.
    assert!(disc as f64 > 0.2 * all as f64, "{disc} {ring} {all}");
    assert!(
        (ring as f64 / 5.0) < 0.2 * disc as f64,
        "{disc} {ring} {all}"
    );
    // In the render, the caustic-only view is brightest there.
    let scene = builtin_scene("cornell-spheres").unwrap();
    let pipeline = {
        let mut pipeline = lab8();
        pipeline.view = View::Caustics;
        pipeline.photons = PhotonSettings {
            emitted: 200_000,
            ..PhotonSettings::DEFAULT
        };
        pipeline
    };
    let pipeline = with_caustics(&pipeline, &scene).unwrap();
    let settings = RenderSettings {
        width: 80,
        height: 80,
        ..RenderSettings::default()
    };
    let film = render(&scene, &pipeline, &settings).unwrap();
    // The brightest pixel of a diffuse, non-emitting surface seen directly.
    let camera = pipeline.prepare_camera(&scene, raylab_core::glam::UVec2::new(80, 80));
    let mut best: Option<(f32, raylab_core::glam::Vec3)> = None;
    for (i, p) in film.pixels.iter().enumerate() {
        let (x, y) = ((i % 80) as f32 + 0.5, (i / 80) as f32 + 0.5);
        let ray = pipeline.camera_ray(&camera, raylab_core::glam::Vec2::new(x, y));
        let Some(hit) = pipeline.trace_to_closest(&scene, &ray) else {
            continue;
        };
        let m = scene.material(hit.material);
        if m.illum != IllumModel::Lambertian || m.emission != raylab_core::glam::Vec3::ZERO {
            continue;
        }
        if best.is_none_or(|(b, _)| p.y > b) {
            best = Some((p.y, hit.position));
        }
    }
    let (_, at) = best.unwrap();
    assert!(
        (at - CAUSTIC_CENTRE).length() < 0.05,
        "the brightest caustic on a diffuse surface is at {at}, expected near {CAUSTIC_CENTRE}"
    );
}

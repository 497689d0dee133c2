//! The answer key: one module per lab implementing that lab's contract from
//! `contracts` — every lab in the course's repository, the released ones in a
//! handout — and [`pipeline`], the reference [`Pipeline`] every check and render starts from.
//!
//! Which labs' solutions the crate holds is its `key-labNN` features (all on by default); the
//! slot of a lab whose solution it does not hold is a [`contracts::Waiting`] one, so that no
//! lab's tests need another lab's student crate (a lab's harness puts its own student's code
//! in its own slot).

#[cfg(feature = "key-lab01")]
pub mod lab01;
#[cfg(feature = "key-lab02")]
pub mod lab02;
#[cfg(feature = "key-lab03")]
pub mod lab03;
#[cfg(feature = "key-lab04")]
pub mod lab04;
#[cfg(feature = "key-lab05")]
pub mod lab05;
#[cfg(feature = "key-lab06")]
pub mod lab06;
#[cfg(feature = "key-lab07")]
pub mod lab07;
#[cfg(feature = "key-lab08")]
pub mod lab08;

use std::sync::Arc;

use pipeline::photon::PhotonSettings;
#[cfg(feature = "key-lab09")]
pub mod lab09;
#[cfg(feature = "key-lab10")]
pub mod lab10;

use contracts::lab09::{Addressing, TextureFilter};
#[cfg(feature = "key-lab11")]
pub mod lab11;

use contracts::lab11::HemisphereSampler;
use pipeline::{Pipeline, View};

include!(concat!(env!("OUT_DIR"), "/keys.rs"));

/// Lab `$n`'s slot: the answer key's `$key` where this crate holds it (feature `$feature`),
/// otherwise a [`contracts::Waiting`] slot that names the lab.
macro_rules! slot {
    ($feature:literal, $n:literal, $module:ident :: $key:ident, $contract:ty) => {{
        #[cfg(feature = $feature)]
        let slot: Arc<$contract> = Arc::new($module::$key);
        #[cfg(not(feature = $feature))]
        let slot: Arc<$contract> = Arc::new(contracts::Waiting::<$contract>::new($n));
        slot
    }};
}

/// The reference pipeline with every lab enabled up to `lab`.
pub fn pipeline(lab: u32) -> Pipeline {
    Pipeline {
        camera: slot!(
            "key-lab01",
            1,
            lab01::Lab01,
            dyn contracts::lab01::CameraRays
        ),
        intersection: None,
        shading: slot!("key-lab02", 2, lab02::Lab02, dyn contracts::lab02::Shading),
        shadows: slot!("key-lab03", 3, lab03::Lab03, dyn contracts::lab03::Shadows),
        reflection: slot!(
            "key-lab04",
            4,
            lab04::Lab04,
            dyn contracts::lab04::Reflection
        ),
        radiometry: slot!(
            "key-lab05",
            5,
            lab05::Lab05,
            dyn contracts::lab05::Radiometry
        ),
        radiosity: slot!(
            "key-lab06",
            6,
            lab06::Lab06,
            dyn contracts::lab06::Radiosity
        ),
        antialiasing: slot!(
            "key-lab07",
            7,
            lab07::Lab07,
            dyn contracts::lab07::Antialiasing
        ),
        photon_mapping: slot!(
            "key-lab08",
            8,
            lab08::Lab08,
            dyn contracts::lab08::PhotonMapping
        ),
        caustics: None,
        photons: PhotonSettings::DEFAULT,
        texturing: slot!(
            "key-lab09",
            9,
            lab09::Lab09,
            dyn contracts::lab09::Texturing
        ),
        fresnel: slot!("key-lab10", 10, lab10::Lab10, dyn contracts::lab10::Fresnel),
        ambient_occlusion: slot!(
            "key-lab11",
            11,
            lab11::Lab11,
            dyn contracts::lab11::AmbientOcclusion
        ),
        lab,
        view: View::Shaded,
        area_light_samples: 4,
        max_depth: 10,
        texture_filter: TextureFilter::Bilinear,
        texture_addressing: Addressing::Repeat,
        occlusion_rays: (64, HemisphereSampler::Cosine),
    }
}

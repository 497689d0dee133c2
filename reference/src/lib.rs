//! The answer key: one module per lab implementing that lab's contract from
//! `contracts` — every lab in the course's repository, the released ones in a
//! handout — and [`pipeline`], the reference [`Pipeline`] every check and render starts from.
//!
//! Which labs' solutions the crate holds is its `key-labNN` features (all on by default); a lab
//! whose solution it does not hold has the student's own code (`labs/labNN`'s `Student`) in
//! its slot of [`pipeline`].

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

/// The code in each lab's slot of [`pipeline`]: the answer key's where this crate holds it,
/// the student's otherwise.
mod slots {
    #[cfg(feature = "key-lab01")]
    pub use super::lab01::Lab01;
    #[cfg(feature = "key-lab02")]
    pub use super::lab02::Lab02;
    #[cfg(feature = "key-lab03")]
    pub use super::lab03::Lab03;
    #[cfg(feature = "key-lab04")]
    pub use super::lab04::Lab04;
    #[cfg(feature = "key-lab05")]
    pub use super::lab05::Lab05;
    #[cfg(feature = "key-lab06")]
    pub use super::lab06::Lab06;
    #[cfg(feature = "key-lab07")]
    pub use super::lab07::Lab07;
    #[cfg(feature = "key-lab08")]
    pub use super::lab08::Lab08;
    #[cfg(feature = "key-lab09")]
    pub use super::lab09::Lab09;
    #[cfg(feature = "key-lab10")]
    pub use super::lab10::Lab10;
    #[cfg(feature = "key-lab11")]
    pub use super::lab11::Lab11;
    #[cfg(not(feature = "key-lab01"))]
    pub use ::lab01::Student as Lab01;
    #[cfg(not(feature = "key-lab02"))]
    pub use ::lab02::Student as Lab02;
    #[cfg(not(feature = "key-lab03"))]
    pub use ::lab03::Student as Lab03;
    #[cfg(not(feature = "key-lab04"))]
    pub use ::lab04::Student as Lab04;
    #[cfg(not(feature = "key-lab05"))]
    pub use ::lab05::Student as Lab05;
    #[cfg(not(feature = "key-lab06"))]
    pub use ::lab06::Student as Lab06;
    #[cfg(not(feature = "key-lab07"))]
    pub use ::lab07::Student as Lab07;
    #[cfg(not(feature = "key-lab08"))]
    pub use ::lab08::Student as Lab08;
    #[cfg(not(feature = "key-lab09"))]
    pub use ::lab09::Student as Lab09;
    #[cfg(not(feature = "key-lab10"))]
    pub use ::lab10::Student as Lab10;
    #[cfg(not(feature = "key-lab11"))]
    pub use ::lab11::Student as Lab11;
}

/// The reference pipeline with every lab enabled up to `lab`.
pub fn pipeline(lab: u32) -> Pipeline {
    Pipeline {
        camera: Arc::new(slots::Lab01),
        intersection: None,
        shading: Arc::new(slots::Lab02),
        shadows: Arc::new(slots::Lab03),
        reflection: Arc::new(slots::Lab04),
        radiometry: Arc::new(slots::Lab05),
        radiosity: Arc::new(slots::Lab06),
        antialiasing: Arc::new(slots::Lab07),
        photon_mapping: Arc::new(slots::Lab08),
        caustics: None,
        photons: PhotonSettings::DEFAULT,
        texturing: Arc::new(slots::Lab09),
        fresnel: Arc::new(slots::Lab10),
        ambient_occlusion: Arc::new(slots::Lab11),
        lab,
        view: View::Shaded,
        area_light_samples: 4,
        max_depth: 10,
        texture_filter: TextureFilter::Bilinear,
        texture_addressing: Addressing::Repeat,
        occlusion_rays: (64, HemisphereSampler::Cosine),
    }
}

//! The lab contracts: one module per lab with the traits a student implements, the lab's
//! checks, and the generator of its golden data. The renderer reaches student code only
//! through these traits, composed in a [`Pipeline`](crate::pipeline::Pipeline).

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab07;
pub mod strategies;

/// Every lab the framework knows, with its title.
pub const LABS: &[(u32, &str)] = &[
    (1, "Camera rays and the image loop"),
    (2, "Intersections and Lambertian shading"),
    (3, "Shadows and area lights"),
    (4, "Reflection, refraction and Phong"),
    (7, "Anti-aliasing"),
];

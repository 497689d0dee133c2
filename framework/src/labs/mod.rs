//! The lab contracts: one module per lab with the traits a student implements, the lab's
//! checks, and the generator of its golden data. The renderer reaches student code only
//! through these traits, composed in a [`Pipeline`](crate::pipeline::Pipeline).

pub mod lab01;
pub mod lab02;
pub mod strategies;

/// Every lab the framework knows, with its title.
pub const LABS: &[(u32, &str)] = &[
    (1, "Camera rays and the image loop"),
    (2, "Intersections and Lambertian shading"),
];

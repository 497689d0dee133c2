//! The wire between the checks and a student's code that runs apart from them (compiled to
//! WebAssembly, in `raylab grade`): a contract's calls as bytes.
//!
//! `#[contract]` derives both ends from the trait: `Remote<dyn Trait>` implements the trait on
//! the checking side by encoding each call's arguments, handing them to a [`Transport`] and
//! decoding the result (and writing back what a `&mut` argument became); `dyn Trait:
//! Serve` runs an encoded call on an implementation on the student's side. Closure arguments
//! stay on the checking side: the student's side calls them back through [`Host`] by their
//! index among the method's closures. Values are encoded with postcard (serde's data model, in
//! order, without field names).

use std::marker::PhantomData;
use std::sync::Arc;

use serde::Serialize;
use serde::de::DeserializeOwned;

mod run;

pub use run::{OUT_OF_WORK, begin_run, current_run};

/// The encoding of a call's values, one after another.
#[derive(Default)]
pub struct Writer(Vec<u8>);

impl Writer {
    /// An empty encoding.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends `value`.
    pub fn put<T: Serialize + ?Sized>(&mut self, value: &T) {
        let mut bytes = std::mem::take(&mut self.0);
        bytes = postcard::to_extend(value, bytes).unwrap_or_else(|e| {
            panic!("a value of a contract call cannot be encoded: {e}");
        });
        self.0 = bytes;
    }

    /// The bytes.
    pub fn finish(self) -> Vec<u8> {
        self.0
    }
}

/// The decoding of a call's values, in the order they were put.
pub struct Reader<'a>(&'a [u8]);

impl<'a> Reader<'a> {
    /// The values encoded in `bytes`.
    pub fn new(bytes: &'a [u8]) -> Self {
        Self(bytes)
    }

    /// The next value. Bytes that do not hold one are a panic: the far side broke the wire.
    pub fn take<T: DeserializeOwned>(&mut self) -> T {
        match postcard::take_from_bytes(self.0) {
            Ok((value, rest)) => {
                self.0 = rest;
                value
            }
            Err(e) => panic!(
                "the other side of a contract call sent bytes that are not a {}: {e}",
                std::any::type_name::<T>()
            ),
        }
    }
}

/// A closure argument on the checking side, answering the encoded arguments of a call back
/// with the encoded result (and what its `&mut` arguments became).
pub type Callback<'a> = &'a mut dyn FnMut(&[u8]) -> Vec<u8>;

/// What carries a contract's calls to the student's code and back.
pub trait Transport: Send + Sync {
    /// Runs the method named `method` on the student's code with the encoded `args`; the student's code calls `callbacks[i]` for the method's closure
    /// argument `i`. Returns the encoded result. A panic of the student's code is resumed here
    /// as a panic, with its message.
    fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8>;
}

/// Contract `T` implemented by code on the far side of a [`Transport`].
pub struct Remote<T: ?Sized> {
    transport: Arc<dyn Transport>,
    contract: PhantomData<fn() -> Box<T>>,
}

impl<T: ?Sized> Remote<T> {
    /// The contract served over `transport`.
    pub fn new(transport: Arc<dyn Transport>) -> Self {
        Self {
            transport,
            contract: PhantomData,
        }
    }

    /// Runs a call (see [`Transport::call`]).
    #[doc(hidden)]
    pub fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8> {
        self.transport.call(method, args, callbacks)
    }
}

/// The checking side, as the student's code sees it: the closures it was given.
pub trait Host {
    /// Calls closure number `index` of the running call with encoded arguments.
    fn call_back(&self, index: u32, args: Vec<u8>) -> Vec<u8>;
}

/// Running encoded calls of a lab's contract on an implementation (the student's side).
pub trait Serve {
    /// Runs the method named `method` with the encoded `args`; returns the encoded result.
    fn serve(&self, method: &str, args: &[u8], host: &dyn Host) -> Vec<u8>;
}

/// Running encoded calls of the contract trait `C` (one of a lab's traits) on an
/// implementation: `None` for a method `C` does not have.
pub trait Serves<C: ?Sized> {
    /// Runs the method named `method` with the encoded `args`, if `C` has it.
    fn serve_part(&self, method: &str, args: &[u8], host: &dyn Host) -> Option<Vec<u8>>;
}

/// The answer to a method the contract does not have.
#[doc(hidden)]
pub fn unknown_method(method: &str) -> Vec<u8> {
    panic!("the contract has no method `{method}`")
}

/// A transport that serves the calls in this process: the wire's encoding and decoding, with
/// nothing apart (what the tests of every contract's wire code run on).
pub struct Loopback<T: ?Sized>(pub Arc<T>);

impl<T: ?Sized + Serve + Send + Sync> Transport for Loopback<T> {
    fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8> {
        let host = LoopbackHost(std::cell::RefCell::new(callbacks));
        self.0.serve(method, &args, &host)
    }
}

struct LoopbackHost<'a, 'b>(std::cell::RefCell<&'a mut [Callback<'b>]>);

impl Host for LoopbackHost<'_, '_> {
    fn call_back(&self, index: u32, args: Vec<u8>) -> Vec<u8> {
        let mut callbacks = self.0.borrow_mut();
        let callback = callbacks
            .get_mut(index as usize)
            .unwrap_or_else(|| panic!("the call has no closure number {index}"));
        callback(&args)
    }
}

//! The slot of one exercise: the student's code for one function of a contract, the base's
//! for the rest.

use std::sync::Arc;

/// One slot of a pipeline that a check of one exercise fills: the student's implementation
/// answers for one function of the contract (the exercise's), the base's for every other, so
/// that an unfinished exercise never fails another.
///
/// Every contract implements itself for `PartSlot<dyn Contract>`, method by method, through
/// [`#[contract]`](crate::contract); a check puts [`PartSlot::shared`] into the pipeline.
pub struct PartSlot<T: ?Sized> {
    /// The function the student's code answers for (a method of the contract).
    pub function: &'static str,
    /// The student's implementation.
    pub student: Arc<T>,
    /// The base's implementation (the reference, usually).
    pub base: Arc<T>,
}

impl<T: ?Sized> PartSlot<T> {
    /// The slot with `student` for `function` and `base` for the rest, shared as a pipeline
    /// holds its slots.
    pub fn shared(function: &'static str, student: &Arc<T>, base: &Arc<T>) -> Arc<Self> {
        Arc::new(PartSlot {
            function,
            student: student.clone(),
            base: base.clone(),
        })
    }

    /// The implementation that answers for `method`: the student's for the slot's function,
    /// the base's for the others.
    #[inline]
    pub fn pick(&self, method: &str) -> &T {
        if method == self.function {
            &self.student
        } else {
            &self.base
        }
    }
}

/// The methods of a contract, as [`#[contract]`](crate::contract) lists them for `dyn Trait`.
pub trait ContractMethods {
    /// The names of its methods, in the order of the trait.
    const METHODS: &'static [&'static str];
}

/// The slot of a lab whose answer key this tree does not hold (a handout before the lab's
/// solution is released): every method panics with a message naming the lab. A check that
/// reaches it fails as "waiting for lab N's solution" (`grading::FailureKind::Waiting`), and a
/// lab's tests never need another lab's student crate.
pub struct Waiting<T: ?Sized> {
    lab: u32,
    contract: std::marker::PhantomData<fn(&T)>,
}

impl<T: ?Sized> Waiting<T> {
    /// The waiting slot of lab `lab`'s contract `T`.
    pub fn new(lab: u32) -> Self {
        Self {
            lab,
            contract: std::marker::PhantomData,
        }
    }

    /// Panics: `method` is lab `lab`'s, whose solution is not here.
    #[cold]
    pub fn unavailable(&self, method: &str) -> ! {
        panic!(
            "{WAITING_FOR_LAB}{}'s solution: `{method}` is that lab's, and its answer key is not released yet",
            self.lab
        )
    }
}

/// The start of a [`Waiting`] slot's panic message, before the lab's number.
pub const WAITING_FOR_LAB: &str = "waiting for lab ";

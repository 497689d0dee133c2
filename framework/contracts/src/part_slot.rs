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

//! The slot of a check: the student's code for some functions of a contract, the base's for
//! the rest.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// A slot that a check fills: the student's implementation answers for some functions of the
/// contract, the base's (the answer key's, usually) for the others, so that an unfinished or
/// wrong exercise never fails another.
///
/// Every contract implements itself for `PartSlot<C>` whatever `C` implements it, method by
/// method, through [`#[contract]`](crate::contract): a check of one function puts
/// [`PartSlot::shared`] into the pipeline; the grader puts [`Mix::mix`] in the place of the
/// whole student code, to learn which of the student's functions a check called and to
/// replace those whose own exercises fail.
pub struct PartSlot<T: ?Sized> {
    /// The functions the student's code answers for.
    pub student_for: StudentFor,
    /// The student's implementation.
    pub student: Arc<T>,
    /// The base's implementation (the reference, usually).
    pub base: Arc<T>,
    /// The student's functions called through this slot.
    pub calls: Arc<CallLog>,
}

/// Which functions of a contract a [`PartSlot`] sends to the student's code.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StudentFor {
    /// This one (a method of the contract); the base answers for the rest.
    Only(&'static str),
    /// Every function but these, which the base answers for.
    AllBut(Vec<&'static str>),
}

impl StudentFor {
    /// Whether the student's code answers for `method`.
    #[inline]
    pub fn includes(&self, method: &str) -> bool {
        match self {
            Self::Only(function) => *function == method,
            Self::AllBut(functions) => !functions.contains(&method),
        }
    }
}

impl<T: ?Sized> PartSlot<T> {
    /// The slot with `student` for `function` and `base` for the rest, shared as a pipeline
    /// holds its slots.
    pub fn shared(function: &'static str, student: &Arc<T>, base: &Arc<T>) -> Arc<Self> {
        Arc::new(PartSlot {
            student_for: StudentFor::Only(function),
            student: student.clone(),
            base: base.clone(),
            calls: Arc::default(),
        })
    }

    /// The slot with `student` for every function but those of `key_for`, which `key` answers
    /// for, noting the student's functions called in `calls` (for [`Mix::mix`]).
    pub fn mixed(
        student: &Arc<T>,
        key: &Arc<T>,
        key_for: Vec<&'static str>,
        calls: &Arc<CallLog>,
    ) -> Arc<Self> {
        Arc::new(PartSlot {
            student_for: StudentFor::AllBut(key_for),
            student: student.clone(),
            base: key.clone(),
            calls: calls.clone(),
        })
    }

    /// The implementation that answers for `method` (whose [`method_bit`] is `bit`): the
    /// student's for the slot's functions, noted in its [`CallLog`], the base's for the others.
    #[inline]
    pub fn pick(&self, method: &str, bit: u64) -> &T {
        if self.student_for.includes(method) {
            self.calls.note(bit);
            &self.student
        } else {
            &self.base
        }
    }
}

/// The student's functions a [`PartSlot`] sent calls to, each as its [`method_bit`].
#[derive(Debug, Default)]
pub struct CallLog(AtomicU64);

impl CallLog {
    /// Notes a call of the method whose bit is `bit`.
    #[inline]
    pub fn note(&self, bit: u64) {
        // A load first: the calls of a render note the same few bits millions of times.
        if self.0.load(Ordering::Relaxed) & bit == 0 {
            self.0.fetch_or(bit, Ordering::Relaxed);
        }
    }

    /// Whether no call was noted.
    pub fn is_empty(&self) -> bool {
        self.0.load(Ordering::Relaxed) == 0
    }

    /// Whether `method` may have been called: its bit is set (two methods may share a bit, so a
    /// method never called can answer `true`, one called never `false`).
    pub fn may_have_called(&self, method: &str) -> bool {
        self.0.load(Ordering::Relaxed) & method_bit(method) != 0
    }
}

/// The bit of a [`CallLog`] that stands for the method `name`: one of 64, by the FNV-1a hash of
/// the name, computed when the contract is compiled for its forwarding code.
pub const fn method_bit(name: &str) -> u64 {
    let bytes = name.as_bytes();
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut i = 0;
    while i < bytes.len() {
        hash ^= bytes[i] as u64;
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
        i += 1;
    }
    1 << (hash % 64)
}

/// Contracts a grader can mix: the student's code with the answer key's in place of some of
/// its functions. [`#[contract]`](crate::contract) implements it for `dyn Trait`.
pub trait Mix: Send + Sync {
    /// `student` for every function of the contract but those of `key_for`, which `key`
    /// answers for; the student's functions called are noted in `calls`.
    fn mix(
        student: &Arc<Self>,
        key: &Arc<Self>,
        key_for: Vec<&'static str>,
        calls: &Arc<CallLog>,
    ) -> Arc<Self>;

    /// `student` for the method `function`, `base` for the rest: [`PartSlot::shared`] as the
    /// contract's code.
    fn only(function: &'static str, student: &Arc<Self>, base: &Arc<Self>) -> Arc<Self>;
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

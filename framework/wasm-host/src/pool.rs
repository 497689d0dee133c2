//! The instances of a student's module, at most [`POOL_SIZE`] at once whatever the number of
//! threads that call it, each made in one run of checks and never used in another; and the
//! fuel of the run under way (`budget`).

use std::sync::{Condvar, Mutex, MutexGuard, PoisonError};

use crate::budget::{CALL_FUEL, Limit, RUN_FUEL, Work};
use crate::guest::Guest;

/// The most instances of one module at once. Each reserves [`crate::MEMORY_LIMIT`] of address
/// space (256 MiB), so 4 take 1 GiB of the 4 GiB an exercise's process may address, whatever
/// the number of threads that render: calls beyond wait for an instance. A call nested in
/// another through a callback runs in the instance of the call it is nested in, so it never
/// waits.
pub const POOL_SIZE: usize = 4;

/// The instances and the run's fuel.
pub(crate) struct Pool {
    state: Mutex<State>,
    freed: Condvar,
}

struct State {
    /// The run of checks the instances and the fuel below are of.
    run: u64,
    idle: Vec<Guest>,
    /// Instances made and not dropped: idle, or running a call.
    live: usize,
    /// The run's fuel given to calls so far (what a running call was given, until it ends).
    fuel: u64,
    /// The run's fuel the ended calls used.
    used: u64,
    /// Why the run is over: a call of it ran past its budget.
    stopped: Option<String>,
    work: Work,
}

/// An instance taken for one call, and the fuel that call may use.
pub(crate) struct Lease {
    pub guest: Guest,
    pub fuel: u64,
    pub limit: Limit,
}

impl Pool {
    pub fn new() -> Self {
        Self {
            state: Mutex::new(State {
                run: 0,
                idle: Vec::new(),
                live: 0,
                fuel: 0,
                used: 0,
                stopped: None,
                work: Work::default(),
            }),
            freed: Condvar::new(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// An instance of run `run` (idle, or made by `make` while fewer than [`POOL_SIZE`] live)
    /// with the fuel of one call, taken from the run's once the instance is there; waits while
    /// all are busy. `Err`: why the call cannot run (the run is over, or no instance can be
    /// made).
    pub fn take(
        &self,
        run: u64,
        make: impl FnOnce(u64) -> Result<Guest, String>,
    ) -> Result<Lease, String> {
        let mut state = self.lock();
        if state.run < run {
            // A new run: nothing of the student's code made before it is used again.
            state.run = run;
            state.fuel = 0;
            state.used = 0;
            state.stopped = None;
            let retired = std::mem::take(&mut state.idle);
            state.live -= retired.len();
            drop(state);
            drop(retired);
            state = self.lock();
        }
        while state.idle.is_empty() && state.live >= POOL_SIZE {
            state = self
                .freed
                .wait(state)
                .unwrap_or_else(PoisonError::into_inner);
        }
        let (fuel, limit) = state.grant()?;
        if let Some(guest) = state.idle.pop() {
            return Ok(Lease { guest, fuel, limit });
        }
        state.live += 1;
        drop(state);
        match make(fuel) {
            Ok(guest) => Ok(Lease { guest, fuel, limit }),
            Err(why) => {
                self.give_back(None, run, fuel, 0);
                Err(why)
            }
        }
    }

    /// Ends a call of run `run` given `fuel` that used `used`: its instance back to the idle
    /// ones when it is of the run under way (`None`: the instance is dropped).
    pub fn give_back(&self, guest: Option<Guest>, run: u64, fuel: u64, used: u64) {
        let mut state = self.lock();
        let mut dropped = None;
        if state.run == run {
            state.fuel -= fuel - used.min(fuel);
            state.work.most_in_one_call = state.work.most_in_one_call.max(used);
            state.used += used;
            state.work.most_in_one_run = state.work.most_in_one_run.max(state.used);
            state.work.calls += 1;
        }
        match guest {
            Some(guest) if guest.run == state.run => state.idle.push(guest),
            other => {
                dropped = other;
                state.live -= 1;
            }
        }
        drop(state);
        self.freed.notify_one();
        drop(dropped);
    }

    /// Ends run `run`: every later call of it fails with `why` at once.
    pub fn stop_run(&self, run: u64, why: &str) {
        let mut state = self.lock();
        if state.run == run && state.stopped.is_none() {
            state.stopped = Some(why.to_string());
        }
    }

    /// Counts a call nested in another.
    pub fn nested_call(&self) {
        self.lock().work.nested_calls += 1;
    }

    /// The most work the student's code did so far.
    pub fn work(&self) -> Work {
        self.lock().work
    }
}

impl State {
    /// The fuel of the next call, taken from the run's: the call's own budget while the run has
    /// that much left, else what the run has left; `Err` once the run is over.
    fn grant(&mut self) -> Result<(u64, Limit), String> {
        if let Some(why) = &self.stopped {
            return Err(why.clone());
        }
        let left = RUN_FUEL.saturating_sub(self.fuel);
        if left == 0 {
            let why = Limit::Run.message();
            self.stopped = Some(why.clone());
            return Err(why);
        }
        let grant = if left >= CALL_FUEL {
            (CALL_FUEL, Limit::Call)
        } else {
            (left, Limit::Run)
        };
        self.fuel += grant.0;
        Ok(grant)
    }
}

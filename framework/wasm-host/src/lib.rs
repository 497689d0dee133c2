//! Where graded code runs: a student's lab compiled to WebAssembly (`raylab_guest::serve!`),
//! instantiated here and called by the checks through its contract's wire
//! (`contracts::wire::Remote`).
//!
//! The student's code reaches nothing but its own linear memory: not the checks, not the
//! answer keys, not the verdict secret, which live in this process's native memory. Whatever it
//! does with a soundness hole of the compiler stays inside that memory; what it returns is
//! decoded as the contract's data types and judged by the checks. Each module instance may grow
//! its memory to [`MEMORY_LIMIT`]; a panic of the student's code (its message and location sent
//! by the module's panic hook), a trap or an exhausted memory is resumed in the caller as a
//! panic, which the checks report against the exercise that ran.
//!
//! Calls may come from many threads (a parallel render): each takes an idle instance of the
//! module or makes one, at most [`POOL_SIZE`] at once (calls beyond wait); an instance that
//! trapped is dropped. Each instance serves one run of checks (`contracts::wire::begin_run`):
//! the student's code starts each run afresh, its statics included. Its work is counted in
//! fuel, per call and per run ([`CALL_FUEL`], [`RUN_FUEL`]): an endless loop is stopped, as a
//! time-out, after the same work on every machine.

mod budget;
mod guest;
mod pool;

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use contracts::wire::{Callback, Transport};
use wasmtime::{Config, Engine, Linker, Module};

pub use budget::{CALL_FUEL, RUN_FUEL, Work};
pub use pool::POOL_SIZE;

use guest::{Guest, State, Stop};
use pool::Pool;

/// The most linear memory one instance of a student's module may have: 256 MiB (a lab's
/// functions take small inputs; the largest, a texture, is copied into it).
pub const MEMORY_LIMIT: usize = 256 << 20;

/// The extension of [`StudentModule::precompile`]'s output, which [`ModuleFromEnv`] loads as
/// machine code.
pub const PRECOMPILED_EXTENSION: &str = "cwasm";

/// A student's lab compiled to WebAssembly, ready to be called.
pub struct StudentModule {
    /// Its number among the modules of this process (for calls nested through callbacks).
    id: u64,
    engine: Engine,
    linker: Linker<State>,
    module: Module,
    pool: Pool,
}

/// The engine every student module is compiled and precompiled with.
fn engine() -> Result<Engine, String> {
    let mut config = Config::new();
    // Bounds-checked memories that reserve the address space of their limit and no more (an
    // exercise's process runs under an address-space limit), so that growing up to the limit
    // never moves one.
    config.memory_reservation(MEMORY_LIMIT as u64);
    config.memory_guard_size(0);
    config.memory_reservation_for_growth(0);
    config.max_wasm_stack(1 << 20);
    // The work of every call is counted (`budget`).
    config.consume_fuel(true);
    Engine::new(&config).map_err(|e| format!("{e:#}"))
}

impl StudentModule {
    /// Compiles the module at `path`. The error says why it cannot run: not a module, or one
    /// that imports what the checking side does not give or lacks an export of
    /// `raylab_guest::serve!`.
    pub fn load(path: &Path) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::from_bytes(&bytes).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// Compiles a module from its bytes (see [`StudentModule::load`]).
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        let engine = engine()?;
        let module = Module::new(&engine, bytes).map_err(|e| format!("not a module: {e:#}"))?;
        Self::with_module(engine, module)
    }

    /// Compiles the module at `wasm` once and writes the machine code to `out`, for
    /// [`StudentModule::load_precompiled`] (which then takes a millisecond where compiling
    /// takes a tenth of a second, in every exercise's process).
    pub fn precompile(wasm: &Path, out: &Path) -> Result<(), String> {
        let bytes = std::fs::read(wasm).map_err(|e| format!("{}: {e}", wasm.display()))?;
        let module = Module::new(&engine()?, &bytes).map_err(|e| format!("not a module: {e:#}"))?;
        let code = module.serialize().map_err(|e| format!("{e:#}"))?;
        std::fs::write(out, code).map_err(|e| format!("{}: {e}", out.display()))
    }

    /// Loads what [`StudentModule::precompile`] wrote.
    ///
    /// # Safety
    /// `path` must hold the output of [`StudentModule::precompile`] of this build, untouched:
    /// its machine code is run as it is. (The grader writes it from the student's module with
    /// this program, before any student code runs, and the student's code has no files.)
    pub unsafe fn load_precompiled(path: &Path) -> Result<Self, String> {
        let engine = engine()?;
        // SAFETY: as the caller promises.
        let module = unsafe { Module::deserialize_file(&engine, path) }
            .map_err(|e| format!("{}: {e:#}", path.display()))?;
        Self::with_module(engine, module)
    }

    fn with_module(engine: Engine, module: Module) -> Result<Self, String> {
        static MODULES: AtomicU64 = AtomicU64::new(0);
        let loaded = Self {
            id: MODULES.fetch_add(1, Ordering::Relaxed),
            linker: guest::linker(&engine)?,
            engine,
            module,
            pool: Pool::new(),
        };
        // One instance now, so that a module without the exports fails here, saying why.
        loaded.instance(0, CALL_FUEL)?;
        Ok(loaded)
    }

    fn instance(&self, run: u64, fuel: u64) -> Result<Guest, String> {
        Guest::new(&self.engine, &self.linker, &self.module, self.id, run, fuel)
    }

    /// The most work the module's code did so far (calls, and the fuel of one call and of one
    /// run), for measuring the budgets.
    pub fn work(&self) -> Work {
        self.pool.work()
    }

    /// Fails the call of run `run` that stopped with `stop`: as a time-out that ends the run
    /// when it used up its fuel.
    fn fail(&self, stop: Stop, run: u64) -> ! {
        if stop.out_of_fuel.is_some() {
            self.pool.stop_run(run, &stop.message);
        }
        raylab_core::resume_panic(stop.message, stop.location)
    }
}

/// A call that holds an instance of the pool: gives it back however the call ends (an
/// unwinding callback included, which drops the instance).
struct Running<'a> {
    module: &'a StudentModule,
    guest: Option<Guest>,
    run: u64,
    fuel: u64,
}

impl Running<'_> {
    /// Ends the call, which used `used` fuel; its instance is kept when `keep`.
    fn finish(mut self, keep: bool, used: u64) {
        let guest = self.guest.take().filter(|_| keep);
        self.module.pool.give_back(guest, self.run, self.fuel, used);
    }
}

impl Drop for Running<'_> {
    fn drop(&mut self) {
        if let Some(guest) = self.guest.take() {
            let used = guest.fuel_used(self.fuel);
            drop(guest);
            self.module.pool.give_back(None, self.run, self.fuel, used);
        }
    }
}

impl Transport for StudentModule {
    fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8> {
        let run = contracts::wire::current_run();
        if let Some(result) = guest::nested(self.id, method, &args, callbacks) {
            self.pool.nested_call();
            return result.unwrap_or_else(|stop| self.fail(stop, run));
        }
        let lease = self
            .pool
            .take(run, |fuel| self.instance(run, fuel))
            .unwrap_or_else(|why| raylab_core::resume_panic(why, None));
        let mut running = Running {
            module: self,
            guest: Some(lease.guest),
            run,
            fuel: lease.fuel,
        };
        let guest = running.guest.as_mut().expect("just put there");
        let (result, used) = guest.call((lease.fuel, lease.limit), method, &args, callbacks);
        running.finish(result.is_ok(), used);
        result.unwrap_or_else(|stop| self.fail(stop, run))
    }
}

/// The student's module named by an environment variable, loaded at the first call: a graded
/// program lists its tests without one, and a module that does not load fails each exercise
/// that calls it, saying why.
pub struct ModuleFromEnv {
    var: &'static str,
    module: std::sync::OnceLock<Result<StudentModule, String>>,
}

impl ModuleFromEnv {
    /// The module the variable `var` names.
    pub fn new(var: &'static str) -> Self {
        Self {
            var,
            module: std::sync::OnceLock::new(),
        }
    }
}

impl Transport for ModuleFromEnv {
    fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8> {
        let module = self.module.get_or_init(|| {
            let path = std::env::var_os(self.var)
                .ok_or_else(|| format!("{} names no student module", self.var))?;
            let path = Path::new(&path);
            if path.extension().is_some_and(|e| e == PRECOMPILED_EXTENSION) {
                // SAFETY: a `.cwasm` file is the grader's output of `precompile` (see there).
                unsafe { StudentModule::load_precompiled(path) }
            } else {
                StudentModule::load(path)
            }
        });
        match module {
            Ok(module) => module.call(method, args, callbacks),
            Err(e) => {
                raylab_core::resume_panic(format!("the student's code cannot run: {e}"), None)
            }
        }
    }
}

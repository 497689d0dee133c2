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
//! module or makes one, so calls never wait for each other; an instance that trapped is dropped.

use std::path::Path;
use std::sync::{Mutex, PoisonError};

use contracts::wire::{Callback, Transport};
use wasmtime::{
    Caller, Config, Engine, Extern, Linker, Memory, Module, ResourceLimiter, Store, Trap, TypedFunc,
};

/// The most linear memory one instance of a student's module may have: 256 MiB (a lab's
/// functions take small inputs; the largest, a texture, is copied into it).
pub const MEMORY_LIMIT: usize = 256 << 20;

/// The extension of [`StudentModule::precompile`]'s output, which [`ModuleFromEnv`] loads as
/// machine code.
pub const PRECOMPILED_EXTENSION: &str = "cwasm";

/// The longest panic message kept, in bytes.
const PANIC_TEXT_LIMIT: u32 = 64 << 10;

/// A student's lab compiled to WebAssembly, ready to be called.
pub struct StudentModule {
    engine: Engine,
    linker: Linker<State>,
    module: Module,
    idle: Mutex<Vec<Guest>>,
}

/// The closures of the call an instance is running, for `raylab.call_back`.
struct Callbacks(*mut [Callback<'static>]);

// SAFETY: the pointer is set and used only on the thread that runs the call, for its duration.
unsafe impl Send for Callbacks {}

/// What the host functions of one instance share.
#[derive(Default)]
struct State {
    callbacks: Option<Callbacks>,
    panic: Option<String>,
    memory_refused: Option<usize>,
}

impl ResourceLimiter for State {
    fn memory_growing(
        &mut self,
        _current: usize,
        desired: usize,
        _maximum: Option<usize>,
    ) -> wasmtime::Result<bool> {
        if desired > MEMORY_LIMIT {
            self.memory_refused = Some(desired);
            return Ok(false);
        }
        Ok(true)
    }

    fn table_growing(
        &mut self,
        _current: usize,
        desired: usize,
        _maximum: Option<usize>,
    ) -> wasmtime::Result<bool> {
        Ok(desired <= 1 << 16)
    }
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
    Engine::new(&config).map_err(|e| format!("{e:#}"))
}

/// One instance of the module and its exports.
struct Guest {
    store: Store<State>,
    memory: Memory,
    alloc: TypedFunc<u32, u32>,
    free: TypedFunc<(u32, u32), ()>,
    call: TypedFunc<(u32, u32, u32), u64>,
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
        let mut linker = Linker::new(&engine);
        linker
            .func_wrap("raylab", "call_back", call_back)
            .and_then(|l| l.func_wrap("raylab", "panic", panic_text))
            .map_err(|e| format!("{e:#}"))?;
        let loaded = Self {
            engine,
            linker,
            module,
            idle: Mutex::new(Vec::new()),
        };
        let first = loaded.instantiate()?;
        loaded.idle(first);
        Ok(loaded)
    }

    fn instantiate(&self) -> Result<Guest, String> {
        let mut store = Store::new(&self.engine, State::default());
        store.limiter(|state| state as &mut dyn ResourceLimiter);
        let instance = self
            .linker
            .instantiate(&mut store, &self.module)
            .map_err(|e| format!("the module cannot be instantiated: {e:#}"))?;
        let missing = |name: &str, e: wasmtime::Error| {
            format!("the module has no export `{name}` of `raylab_guest::serve!`: {e:#}")
        };
        let memory = instance
            .get_memory(&mut store, "memory")
            .ok_or_else(|| "the module exports no memory".to_string())?;
        let alloc = instance
            .get_typed_func(&mut store, "raylab_alloc")
            .map_err(|e| missing("raylab_alloc", e))?;
        let free = instance
            .get_typed_func(&mut store, "raylab_free")
            .map_err(|e| missing("raylab_free", e))?;
        let call = instance
            .get_typed_func(&mut store, "raylab_call")
            .map_err(|e| missing("raylab_call", e))?;
        Ok(Guest {
            store,
            memory,
            alloc,
            free,
            call,
        })
    }

    fn idle(&self, guest: Guest) {
        self.idle
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(guest);
    }
}

impl Transport for StudentModule {
    fn call(&self, method: &str, args: Vec<u8>, callbacks: &mut [Callback<'_>]) -> Vec<u8> {
        let idle = self
            .idle
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .pop();
        let mut guest = match idle {
            Some(guest) => guest,
            None => self
                .instantiate()
                .unwrap_or_else(|e| raylab_core::resume_panic(e, None)),
        };
        match guest.call(method, &args, callbacks) {
            Ok(result) => {
                self.idle(guest);
                result
            }
            Err((message, location)) => raylab_core::resume_panic(message, location),
        }
    }
}

impl Guest {
    /// Runs one call; a failure is the message and location of the student's panic, or what
    /// stopped the module.
    fn call(
        &mut self,
        method: &str,
        args: &[u8],
        callbacks: &mut [Callback<'_>],
    ) -> Result<Vec<u8>, (String, Option<String>)> {
        let len = method.len() + args.len();
        let len = u32::try_from(len).map_err(|_| (format!("a call of {len} bytes"), None))?;
        let at = self
            .alloc
            .call(&mut self.store, len)
            .map_err(|e| self.failure(e))?;
        let written = self
            .memory
            .write(&mut self.store, at as usize, method.as_bytes())
            .and_then(|()| {
                self.memory
                    .write(&mut self.store, at as usize + method.len(), args)
            });
        written.map_err(|_| outside_memory())?;
        let callbacks: *mut [Callback<'_>] = callbacks;
        // SAFETY: the lifetime is erased only while the call runs (`call_back` uses the pointer
        // then); it is cleared below, and an unwinding callback drops this instance.
        let callbacks = unsafe {
            std::mem::transmute::<*mut [Callback<'_>], *mut [Callback<'static>]>(callbacks)
        };
        self.store.data_mut().callbacks = Some(Callbacks(callbacks));
        let result = self.call.call(
            &mut self.store,
            (at, method.len() as u32, args.len() as u32),
        );
        self.store.data_mut().callbacks = None;
        let packed = result.map_err(|e| self.failure(e))?;
        let (at, len) = ((packed >> 32) as u32, packed as u32);
        let mut out = vec![0; len as usize];
        self.memory
            .read(&self.store, at as usize, &mut out)
            .map_err(|_| outside_memory())?;
        self.free
            .call(&mut self.store, (at, len))
            .map_err(|e| self.failure(e))?;
        Ok(out)
    }

    /// What stopped the module, as the student should read it.
    fn failure(&mut self, error: wasmtime::Error) -> (String, Option<String>) {
        let state = self.store.data_mut();
        if let Some(text) = state.panic.take() {
            let (message, at) = text.split_once('\n').unwrap_or((&text, ""));
            return (
                message.to_string(),
                (!at.is_empty()).then(|| at.to_string()),
            );
        }
        if let Some(bytes) = state.memory_refused.take() {
            return (
                format!(
                    "the code ran out of memory: it asked for {} MiB; it may have {} MiB",
                    bytes >> 20,
                    MEMORY_LIMIT >> 20
                ),
                None,
            );
        }
        let message = match error.downcast_ref::<Trap>() {
            Some(Trap::StackOverflow) => {
                "the code overflowed its stack (a recursion without end?)".to_string()
            }
            Some(Trap::UnreachableCodeReached) => {
                "the code aborted (`std::process::exit` and `abort` end only the student's code \
                 here, which counts as a crash)"
                    .to_string()
            }
            Some(trap) => format!("the code stopped: {trap}"),
            None => format!("{error:#}"),
        };
        (message, None)
    }
}

fn outside_memory() -> (String, Option<String>) {
    (
        "the code answered with a buffer outside its memory".to_string(),
        None,
    )
}

/// `raylab.call_back(index, ptr, len)`: calls closure `index` of the running call with the
/// encoded arguments at `ptr`; answers with a buffer of the module's `raylab_alloc`.
fn call_back(
    mut caller: Caller<'_, State>,
    index: u32,
    at: u32,
    len: u32,
) -> wasmtime::Result<u64> {
    let memory = export(&mut caller, "memory")?
        .into_memory()
        .ok_or_else(|| wasmtime::format_err!("`memory` is not a memory"))?;
    let mut args = vec![0; len as usize];
    memory.read(&caller, at as usize, &mut args)?;
    let Some(Callbacks(callbacks)) = caller.data().callbacks else {
        wasmtime::bail!("the code called back outside a call");
    };
    // SAFETY: `Guest::call` set the pointer for the call that is running on this thread, and
    // nothing else uses the closures while it runs.
    let callbacks = unsafe { &mut *callbacks };
    let callback = callbacks
        .get_mut(index as usize)
        .ok_or_else(|| wasmtime::format_err!("the call has no closure number {index}"))?;
    let result = callback(&args);
    let alloc = export(&mut caller, "raylab_alloc")?
        .into_func()
        .ok_or_else(|| wasmtime::format_err!("`raylab_alloc` is not a function"))?
        .typed::<u32, u32>(&caller)?;
    let len = u32::try_from(result.len())?;
    let at = alloc.call(&mut caller, len)?;
    memory.write(&mut caller, at as usize, &result)?;
    Ok((u64::from(at) << 32) | u64::from(len))
}

/// `raylab.panic(ptr, len)`: the text of the student's panic, kept until the trap that follows.
fn panic_text(mut caller: Caller<'_, State>, at: u32, len: u32) -> wasmtime::Result<()> {
    let memory = export(&mut caller, "memory")?
        .into_memory()
        .ok_or_else(|| wasmtime::format_err!("`memory` is not a memory"))?;
    let mut text = vec![0; len.min(PANIC_TEXT_LIMIT) as usize];
    memory.read(&caller, at as usize, &mut text)?;
    caller.data_mut().panic = Some(String::from_utf8_lossy(&text).into_owned());
    Ok(())
}

fn export(caller: &mut Caller<'_, State>, name: &str) -> wasmtime::Result<Extern> {
    caller
        .get_export(name)
        .ok_or_else(|| wasmtime::format_err!("the module exports no `{name}`"))
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

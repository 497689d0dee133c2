//! One instance of a student's module: its store, its exports, and a call run in it — the
//! outermost call of a thread, or a call nested in it through a callback (see [`nested`]).

use std::cell::RefCell;

use contracts::wire::Callback;
use wasmtime::{
    AsContextMut, Caller, Engine, Extern, Linker, Memory, Module, ResourceLimiter, Store, Trap,
    TypedFunc,
};

use crate::MEMORY_LIMIT;
use crate::budget::Limit;

/// The longest panic message kept, in bytes.
const PANIC_TEXT_LIMIT: u32 = 64 << 10;

/// The closures of the call an instance is running, for `raylab.call_back`.
struct Callbacks(*mut [Callback<'static>]);

// SAFETY: the pointer is set and used only on the thread that runs the call, for its duration.
unsafe impl Send for Callbacks {}

/// The exports of `raylab_guest::serve!`.
#[derive(Clone)]
struct Exports {
    memory: Memory,
    alloc: TypedFunc<u32, u32>,
    free: TypedFunc<(u32, u32), ()>,
    call: TypedFunc<(u32, u32, u32), u64>,
}

/// What the host functions of one instance share.
pub(crate) struct State {
    /// The [`crate::StudentModule`] the instance is of (its number).
    module: u64,
    exports: Option<Exports>,
    callbacks: Option<Callbacks>,
    panic: Option<String>,
    memory_refused: Option<usize>,
    /// The budget of the fuel of the outermost call running.
    limit: Limit,
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

/// Why a call did not answer.
pub(crate) struct Stop {
    /// The student's panic message, or what stopped the module.
    pub message: String,
    /// Where the student's code panicked, when it says.
    pub location: Option<String>,
    /// The budget the call used up, if it ran out of fuel.
    pub out_of_fuel: Option<Limit>,
}

/// One instance of the module.
pub(crate) struct Guest {
    store: Store<State>,
    /// The run of checks it was made in (`contracts::wire::current_run`).
    pub run: u64,
}

/// The host functions every instance imports.
pub(crate) fn linker(engine: &Engine) -> Result<Linker<State>, String> {
    let mut linker = Linker::new(engine);
    linker
        .func_wrap("raylab", "call_back", call_back)
        .and_then(|l| l.func_wrap("raylab", "panic", panic_text))
        .map_err(|e| format!("{e:#}"))?;
    Ok(linker)
}

impl Guest {
    /// A new instance of `module` (number `id`), made in run `run`, with `fuel` for whatever
    /// its instantiation runs.
    pub fn new(
        engine: &Engine,
        linker: &Linker<State>,
        module: &Module,
        id: u64,
        run: u64,
        fuel: u64,
    ) -> Result<Self, String> {
        let state = State {
            module: id,
            exports: None,
            callbacks: None,
            panic: None,
            memory_refused: None,
            limit: Limit::Call,
        };
        let mut store = Store::new(engine, state);
        store.limiter(|state| state as &mut dyn ResourceLimiter);
        store.set_fuel(fuel).map_err(|e| format!("{e:#}"))?;
        let instance = linker
            .instantiate(&mut store, module)
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
        store.data_mut().exports = Some(Exports {
            memory,
            alloc,
            free,
            call,
        });
        Ok(Self { store, run })
    }

    /// Runs one call with `fuel` of budget `limit` to use: its answer or why it stopped, and
    /// the fuel it used.
    pub fn call(
        &mut self,
        (fuel, limit): (u64, Limit),
        method: &str,
        args: &[u8],
        callbacks: &mut [Callback<'_>],
    ) -> (Result<Vec<u8>, Stop>, u64) {
        self.store.data_mut().limit = limit;
        if let Err(e) = self.store.set_fuel(fuel) {
            return (Err(stop(&mut self.store, e)), 0);
        }
        let result = invoke(&mut self.store, method, args, callbacks);
        let used = self.fuel_used(fuel);
        (result.map_err(|e| stop(&mut self.store, e)), used)
    }

    /// The fuel used of `fuel` given to the last call.
    pub fn fuel_used(&self, fuel: u64) -> u64 {
        fuel.saturating_sub(self.store.get_fuel().unwrap_or(0))
    }
}

/// Runs one call in the instance of `cx` (its store, or the caller of a host function).
fn invoke(
    cx: &mut impl AsContextMut<Data = State>,
    method: &str,
    args: &[u8],
    callbacks: &mut [Callback<'_>],
) -> wasmtime::Result<Vec<u8>> {
    let mut cx = cx.as_context_mut();
    let Some(exports) = cx.data().exports.clone() else {
        wasmtime::bail!("the instance has no exports");
    };
    let len = method.len() + args.len();
    let len = u32::try_from(len).map_err(|_| wasmtime::format_err!("a call of {len} bytes"))?;
    let at = exports.alloc.call(&mut cx, len)?;
    exports
        .memory
        .write(&mut cx, at as usize, method.as_bytes())
        .and_then(|()| {
            exports
                .memory
                .write(&mut cx, at as usize + method.len(), args)
        })
        .map_err(|_| outside_memory())?;
    let callbacks: *mut [Callback<'_>] = callbacks;
    // SAFETY: the lifetime is erased only while the call runs (`call_back` uses the pointer
    // then); the outer call's closures are put back below, and an unwinding callback drops
    // this instance.
    let callbacks =
        unsafe { std::mem::transmute::<*mut [Callback<'_>], *mut [Callback<'static>]>(callbacks) };
    let outer = cx.data_mut().callbacks.replace(Callbacks(callbacks));
    let result = exports
        .call
        .call(&mut cx, (at, method.len() as u32, args.len() as u32));
    cx.data_mut().callbacks = outer;
    let packed = result?;
    let (at, len) = ((packed >> 32) as u32, packed as u32);
    let mut out = vec![0; len as usize];
    exports
        .memory
        .read(&cx, at as usize, &mut out)
        .map_err(|_| outside_memory())?;
    exports.free.call(&mut cx, (at, len))?;
    Ok(out)
}

/// What stopped the module, as the student should read it.
fn stop(cx: &mut impl AsContextMut<Data = State>, error: wasmtime::Error) -> Stop {
    let mut cx = cx.as_context_mut();
    let state = cx.data_mut();
    let plain = |message: String| Stop {
        message,
        location: None,
        out_of_fuel: None,
    };
    if let Some(text) = state.panic.take() {
        let (message, at) = text.split_once('\n').unwrap_or((&text, ""));
        return Stop {
            message: message.to_string(),
            location: (!at.is_empty()).then(|| at.to_string()),
            out_of_fuel: None,
        };
    }
    if let Some(bytes) = state.memory_refused.take() {
        return plain(format!(
            "the code ran out of memory: it asked for {} MiB; it may have {} MiB",
            bytes >> 20,
            MEMORY_LIMIT >> 20
        ));
    }
    match error.downcast_ref::<Trap>() {
        Some(Trap::OutOfFuel) => Stop {
            message: state.limit.message(),
            location: None,
            out_of_fuel: Some(state.limit),
        },
        Some(Trap::StackOverflow) => {
            plain("the code overflowed its stack (a recursion without end?)".into())
        }
        Some(Trap::UnreachableCodeReached) => plain(
            "the code aborted (`std::process::exit` and `abort` end only the student's code \
             here, which counts as a crash)"
                .into(),
        ),
        Some(trap) => plain(format!("the code stopped: {trap}")),
        None => plain(format!("{error:#}")),
    }
}

fn outside_memory() -> wasmtime::Error {
    wasmtime::format_err!("the code answered with a buffer outside its memory")
}

/// The host functions running a callback on this thread, innermost last: for each, the number
/// of its module and its caller, through which a call of the same module made by the callback
/// runs in the same instance ([`nested`]).
type Active = RefCell<Vec<(u64, *mut Caller<'static, State>)>>;

thread_local! {
    static ACTIVE: Active = const { RefCell::new(Vec::new()) };
}

/// Keeps a callback's caller in [`ACTIVE`] while the callback runs (and unwinds).
struct Running;

impl Running {
    fn enter(module: u64, caller: &mut Caller<'_, State>) -> Self {
        let caller = std::ptr::from_mut(caller).cast::<Caller<'static, State>>();
        ACTIVE.with(|active| active.borrow_mut().push((module, caller)));
        Running
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        ACTIVE.with(|active| active.borrow_mut().pop());
    }
}

/// Runs a call of module `id` in the instance whose callback this thread is running, if it is
/// running one: a call nested in another through a closure argument uses the instance (and
/// the fuel) of the call it is nested in, so it never waits for an instance of the pool. `None`
/// when the thread runs no callback of that module.
pub(crate) fn nested(
    id: u64,
    method: &str,
    args: &[u8],
    callbacks: &mut [Callback<'_>],
) -> Option<Result<Vec<u8>, Stop>> {
    let caller = ACTIVE.with(|active| {
        active
            .borrow()
            .iter()
            .rev()
            .find(|(module, _)| *module == id)
            .map(|&(_, caller)| caller)
    })?;
    // SAFETY: `call_back` put the pointer there while it runs the callback this call comes
    // from, on this thread, and takes it out before it uses its caller again: for the length
    // of this call nothing else uses the caller.
    let caller = unsafe { &mut *caller };
    Some(invoke(caller, method, args, callbacks).map_err(|e| stop(caller, e)))
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
    // SAFETY: `invoke` set the pointer for the call that is running on this thread, and
    // nothing else uses the closures while it runs.
    let callbacks = unsafe { &mut *callbacks };
    let callback = callbacks
        .get_mut(index as usize)
        .ok_or_else(|| wasmtime::format_err!("the call has no closure number {index}"))?;
    let module = caller.data().module;
    let result = {
        let _running = Running::enter(module, &mut caller);
        callback(&args)
    };
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

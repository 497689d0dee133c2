//! The student's side of a lab graded in WebAssembly (docs/architecture.md, "Where graded code
//! runs"): `raylab grade` compiles a submission's lab crate to `wasm32-unknown-unknown` with a
//! one-line crate around it, `raylab_guest::serve!(lab03::Student as contracts::lab03::Contract);`,
//! and the checks call it through the module's exports:
//!
//! - `raylab_alloc(len) -> ptr` and `raylab_free(ptr, len)`: byte buffers in the module's memory;
//! - `raylab_call(ptr, method_len, args_len) -> (ptr << 32) | len`: the buffer at `ptr` holds a
//!   method's name and its encoded arguments (`contracts::wire`); the result is a new buffer the
//!   checking side reads and frees.
//!
//! The module imports `raylab.call_back(index, ptr, len) -> (ptr << 32) | len` (a closure
//! argument of the running call, answered in a buffer the checking side allocates) and
//! `raylab.panic(ptr, len)` (the text of a panic, `message\nlocation`, sent before the module
//! traps).

use contracts::wire::{Host, Serve};

/// The exports of a student's lab: `serve!(labNN::Student as contracts::labNN::Contract)`.
#[macro_export]
macro_rules! serve {
    ($student:path as $contract:ty) => {
        /// A buffer of `len` bytes in this module's memory.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_alloc(len: u32) -> u32 {
            $crate::alloc(len)
        }

        /// Frees a buffer of [`raylab_alloc`] or of a result.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_free(ptr: u32, len: u32) {
            // SAFETY: the checking side frees each buffer it was given once.
            drop(unsafe { $crate::take(ptr, len) });
        }

        /// Runs one call of the contract on the student's code.
        #[unsafe(no_mangle)]
        pub extern "C" fn raylab_call(ptr: u32, method_len: u32, args_len: u32) -> u64 {
            let student: &$contract = &$student;
            // SAFETY: `ptr` is a buffer of `raylab_alloc` of `method_len + args_len` bytes.
            unsafe { $crate::call(student, ptr, method_len, args_len) }
        }
    };
}

/// A zeroed buffer of `len` bytes, left for the checking side to fill: its address.
pub fn alloc(len: u32) -> u32 {
    let buffer = vec![0u8; len as usize].into_boxed_slice();
    Box::into_raw(buffer) as *mut u8 as usize as u32
}

/// The buffer of `len` bytes at `ptr`, taken back.
///
/// # Safety
/// `ptr` and `len` are those of a buffer [`alloc`] or [`leak`] made and nothing has taken yet.
pub unsafe fn take(ptr: u32, len: u32) -> Box<[u8]> {
    let slice = std::ptr::slice_from_raw_parts_mut(ptr as usize as *mut u8, len as usize);
    // SAFETY: as the caller promises, the buffer was a leaked `Box<[u8]>` of this length.
    unsafe { Box::from_raw(slice) }
}

/// `bytes` left in memory for the checking side: `(address << 32) | length`.
pub fn leak(bytes: Vec<u8>) -> u64 {
    let len = bytes.len() as u64;
    let ptr = Box::into_raw(bytes.into_boxed_slice()) as *mut u8 as usize as u64;
    (ptr << 32) | len
}

/// Runs the call in the buffer at `ptr` on `student`; the result, as [`leak`] leaves it.
///
/// # Safety
/// `ptr` is a buffer of [`alloc`] of `method_len + args_len` bytes.
pub unsafe fn call<C: ?Sized + Serve>(
    student: &C,
    ptr: u32,
    method_len: u32,
    args_len: u32,
) -> u64 {
    install_panic_hook();
    // SAFETY: as the caller promises.
    let input = unsafe { take(ptr, method_len + args_len) };
    let (method, args) = input.split_at(method_len as usize);
    let method = std::str::from_utf8(method).expect("a method's name is text");
    leak(student.serve(method, args, &Checks))
}

/// The checking side, through the module's imports.
struct Checks;

impl Host for Checks {
    fn call_back(&self, index: u32, args: Vec<u8>) -> Vec<u8> {
        let packed = imports::call_back(index, &args);
        // SAFETY: the checking side answers with a buffer of `raylab_alloc` it filled.
        unsafe { take((packed >> 32) as u32, packed as u32) }.into_vec()
    }
}

fn install_panic_hook() {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        std::panic::set_hook(Box::new(|info| {
            let payload = info.payload();
            let message = payload
                .downcast_ref::<&str>()
                .copied()
                .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
                .unwrap_or("a panic with a non-text payload");
            let at = info
                .location()
                .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()))
                .unwrap_or_default();
            imports::panic(&format!("{message}\n{at}"));
        }));
    });
}

#[cfg(target_arch = "wasm32")]
mod imports {
    #[link(wasm_import_module = "raylab")]
    unsafe extern "C" {
        #[link_name = "call_back"]
        fn raylab_call_back(index: u32, ptr: u32, len: u32) -> u64;
        #[link_name = "panic"]
        fn raylab_panic(ptr: u32, len: u32);
    }

    pub fn call_back(index: u32, args: &[u8]) -> u64 {
        // SAFETY: the checking side only reads the `args` buffer during the call.
        unsafe { raylab_call_back(index, args.as_ptr() as usize as u32, args.len() as u32) }
    }

    pub fn panic(text: &str) {
        // SAFETY: as above.
        unsafe { raylab_panic(text.as_ptr() as usize as u32, text.len() as u32) }
    }
}

/// Natively there is no checking side to call (the crate is built for wasm32 only).
#[cfg(not(target_arch = "wasm32"))]
mod imports {
    pub fn call_back(_index: u32, _args: &[u8]) -> u64 {
        unreachable!("the student's side of a graded lab runs in WebAssembly")
    }

    pub fn panic(text: &str) {
        eprintln!("{text}");
    }
}

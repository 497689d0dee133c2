#!/**/[allow(unused)] #[path = "@REPO@/reference/src/lab02.rs"] mod key;
// Hostile submission `shebang_path_to_key`: the answer key as the module `key`, by its
// absolute path, on a first line that the compiler reads as an inner attribute and a module
// (`#!` then a comment then `[`) and a scan that skips any `#!` line would not read;
// `Student` is the key's `Lab02`.
//
// The build sees the submission's sources and nothing else of the machine: the module's file
// does not exist there, so the lab does not compile (0 of 14), with the scan switched off too.
// Not a line of the key may reach any report.

pub use key::Lab02 as Student;

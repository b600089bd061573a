//! The `psh` command line as a user runs it: every command's outputs and errors
//! (`cli`), hostile inputs (`hardening`, `bounded`) and the fuzzer over the command line and the
//! file readers (`fuzz`). One test binary (`cargo test --release --test command_line`).

mod bounded;
mod cli;
mod fuzz;
mod hardening;
#[path = "../support/mat.rs"]
mod mat;
mod pbrdf;

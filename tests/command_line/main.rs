//! The `psh` command line as a user runs it: every command's outputs and errors
//! (`cli`), hostile inputs (`hardening`) and the fuzzer over the command line and the
//! file readers (`fuzz`). One test binary (`cargo test --release --test command_line`).

mod cli;
mod fuzz;
mod hardening;

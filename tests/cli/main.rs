//! Integration tests of the `vito` binary (one test crate, a module per feature).
//!
//! Solving tests need a release build to stay quick: `cargo test --release --test cli`.

mod util;

mod check;
mod errors;
mod init;
mod regression;
mod solve;

//! Tests of the `vito` binary, a module per command or feature.

pub mod util;

mod check;
mod errors;
mod init;
mod output_dirs;
mod regression;
mod simulate;
mod solve;

//! The `vito` command: parse arguments, run, exit with the command's code (see `cli`).

use std::process::ExitCode;

use clap::Parser;

mod cli;

fn main() -> ExitCode {
    vito::ipopt::blas_kernels::pin();
    cli::run(cli::Args::parse())
}

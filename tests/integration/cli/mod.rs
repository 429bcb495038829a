//! Tests of the `vito` binary, a module per command or feature.

pub mod util;

mod bench;
mod check;
pub mod errors;
mod gaits;
mod hostile;
mod incline;
mod init;
mod inputs;
mod levels;
mod mode_blocks;
mod output_dirs;
mod passive;
mod penalty;
mod regression;
mod simulate;
mod solve;
mod sphere_contacts;
mod study;
pub mod sweep;
mod sweep_slurm;
mod terrain;
mod trust;
mod view_files;

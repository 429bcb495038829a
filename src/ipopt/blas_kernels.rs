//! One set of BLAS kernels, on one thread, on every machine.
//!
//! The same holds for OpenBLAS's thread count: with `OPENBLAS_NUM_THREADS` unset OpenBLAS
//! takes every core, splits MUMPS's larger BLAS calls and sums in another order, and
//! LittleDog's step ends at 62.92 instead of 50.59. The re-execution below also sets
//! `OPENBLAS_NUM_THREADS=1` and `OMP_NUM_THREADS=1` (read at load time too).
//!
//! OpenBLAS picks its kernels by CPU when it loads, before `main`, unless `OPENBLAS_CORETYPE`
//! names them; the robots' nonconvex solves round their way to different local optima with
//! different kernels (Spring Flamingo: 106.9 with Haswell's, 80.2 with SkylakeX's, 62.1 with
//! Prescott's, from one binary on one machine). So `vito` sets `OPENBLAS_CORETYPE` to
//! the pinned core type for itself: if its environment holds another value, or none, it re-executes
//! its own binary (same PID, same arguments) with the pinned value before doing anything else.
//! The variable must be set before the dynamic loader initialises OpenBLAS, which a
//! constructor inside `vito` would be too late for (libraries initialise first).
//!
//! The pinned set is Haswell's (AVX2 + FMA) on every CPU that has those instructions (Intel
//! since 2013, AMD since 2015; glibc's libm picks its FMA variants on exactly these CPUs too),
//! and Prescott's (SSE3, which every x86-64 CPU runs) on older ones, whose results may then
//! differ from the rest. Prescott's kernels everywhere would cost 1.5-1.7x Ipopt's time per
//! iteration on the brick (BENCHMARKS.md). `summary.json` records the core type a solve used.
//! Other architectures keep their BLAS's choice.

use std::ffi::OsStr;

/// The environment variable OpenBLAS reads its core type from.
pub const VARIABLE: &str = "OPENBLAS_CORETYPE";

/// The pinned OpenBLAS core type for this CPU, if vito pins one.
#[cfg(target_arch = "x86_64")]
pub fn coretype() -> Option<&'static str> {
    if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
        Some("Haswell")
    } else {
        Some("Prescott")
    }
}

/// The pinned OpenBLAS core type for this CPU, if vito pins one.
#[cfg(not(target_arch = "x86_64"))]
pub fn coretype() -> Option<&'static str> {
    None
}

/// The variables OpenBLAS and OpenMP runtimes read their thread counts from when they load:
/// one thread per solve (parallel work uses processes, as sweeps do). The library also sets
/// them at run time before every solve (`ipopt::pin_one_thread`); set here too, they hold
/// from the start, for whichever BLAS Debian's alternatives chose.
const THREADS: [(&str, &str); 2] = [("OPENBLAS_NUM_THREADS", "1"), ("OMP_NUM_THREADS", "1")];

/// Re-executes this binary with `OPENBLAS_CORETYPE` set to the pinned core type and
/// [`THREADS`] set unless they already hold them; returns only when no re-execution is
/// needed or it failed (then with a warning on stderr).
pub fn pin() {
    let mut pinned: Vec<(&str, &str)> = THREADS.to_vec();
    if let Some(coretype) = coretype() {
        pinned.push((VARIABLE, coretype));
    }
    if !cfg!(target_os = "linux")
        || pinned
            .iter()
            .all(|(name, value)| std::env::var_os(name).as_deref() == Some(OsStr::new(value)))
    {
        return;
    }
    reexec(&pinned);
}

#[cfg(unix)]
fn reexec(pinned: &[(&str, &str)]) {
    use std::os::unix::process::CommandExt;
    let exe = match std::env::current_exe() {
        Ok(exe) => exe,
        Err(e) => return warn(pinned, &e.to_string()),
    };
    let mut args = std::env::args_os();
    let mut command = std::process::Command::new(exe);
    if let Some(arg0) = args.next() {
        command.arg0(arg0);
    }
    // `exec` returns only on failure.
    let error = command.args(args).envs(pinned.iter().copied()).exec();
    warn(pinned, &error.to_string());
}

#[cfg(not(unix))]
fn reexec(_pinned: &[(&str, &str)]) {}

fn warn(pinned: &[(&str, &str)], why: &str) {
    let settings: Vec<String> = pinned.iter().map(|(n, v)| format!("{n}={v}")).collect();
    eprintln!(
        "warning: could not restart vito with {} ({why}); BLAS kernels are this CPU's choice, so results may differ from other machines'",
        settings.join(" ")
    );
}

//! One thread for the linear algebra under every solve, whatever the environment says.
//!
//! MUMPS calls BLAS (Debian's `libblas.so.3` alternative: OpenBLAS by default), and OpenBLAS
//! splits its larger calls over `OPENBLAS_NUM_THREADS` threads (by default the machine's
//! cores), summing in another order: the same binary then reaches another local optimum
//! (LittleDog's step: 50.59 with one thread, 62.92 with two). OpenBLAS reads the variable when
//! it loads, before `main`, so the `vito` binary also re-executes itself with it set (see its
//! `blas_kernels`); this module makes it hold for the library too (tests, other programs):
//! before each solve it calls the thread setters the loaded libraries export, found by name at
//! run time (`dlsym`), since which BLAS is loaded is the system's choice:
//! `openblas_set_num_threads` (OpenBLAS, pthread or OpenMP build), `bli_thread_set_num_threads`
//! (BLIS), `omp_set_num_threads` (an OpenMP runtime, e.g. Debian 13's MUMPS or OpenBLAS's
//! OpenMP build). A library that exports none of them is a single-threaded one (reference
//! BLAS) or one vito cannot steer; [`BlasThreads`] says which.

use std::ffi::{CStr, c_char, c_int, c_void};

unsafe extern "C" {
    /// glibc's `dlsym` (in libc.so.6 since glibc 2.34; Debian 12 has 2.36).
    fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
}

/// glibc's `RTLD_DEFAULT`: search the global scope (the executable and the libraries it
/// loaded, in load order).
const RTLD_DEFAULT: *mut c_void = std::ptr::null_mut();

/// The address of `symbol` in the loaded libraries, if one exports it.
fn lookup(symbol: &CStr) -> Option<*mut c_void> {
    // SAFETY: `dlsym` with RTLD_DEFAULT and a NUL-terminated name only reads the name and the
    // loader's tables; it returns null when no loaded object exports the name.
    let address = unsafe { dlsym(RTLD_DEFAULT, symbol.as_ptr()) };
    (!address.is_null()).then_some(address)
}

/// Calls `void f(int)` named `symbol` with `n`, if loaded; whether it was.
fn set(symbol: &CStr, n: c_int) -> bool {
    let Some(address) = lookup(symbol) else {
        return false;
    };
    // SAFETY: OpenBLAS's `openblas_set_num_threads`, BLIS's `bli_thread_set_num_threads`
    // and OpenMP's `omp_set_num_threads` all have the C signature `void (int)`; the address
    // is that function's, as the loader resolved it.
    let f = unsafe { std::mem::transmute::<*mut c_void, extern "C" fn(c_int)>(address) };
    f(n);
    true
}

/// Calls `int f(void)` named `symbol`, if loaded.
fn get(symbol: &CStr) -> Option<i64> {
    let address = lookup(symbol)?;
    // SAFETY: `openblas_get_num_threads` and `omp_get_max_threads` have the C signature
    // `int (void)`.
    let f = unsafe { std::mem::transmute::<*mut c_void, extern "C" fn() -> c_int>(address) };
    Some(i64::from(f()))
}

/// Calls `char *f(void)` named `symbol` (a static string), if loaded.
fn text(symbol: &CStr) -> Option<String> {
    let address = lookup(symbol)?;
    // SAFETY: `openblas_get_config` and `openblas_get_corename` have the C signature
    // `char *(void)` and return a pointer to a static NUL-terminated string (or null).
    let f =
        unsafe { std::mem::transmute::<*mut c_void, extern "C" fn() -> *const c_char>(address) };
    let p = f();
    if p.is_null() {
        return None;
    }
    // SAFETY: non-null, NUL-terminated and static (OpenBLAS's own buffers).
    Some(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}

/// The threads the linear algebra of a solve runs on, after [`pin_one_thread`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlasThreads {
    /// OpenBLAS's `openblas_get_config()` (version, build, kernels), when OpenBLAS is loaded.
    pub openblas_config: Option<String>,
    /// OpenBLAS's kernels (`openblas_get_corename()`).
    pub openblas_core: Option<String>,
    /// OpenBLAS's thread count (`openblas_get_num_threads()`).
    pub openblas_threads: Option<i64>,
    /// Whether BLIS is loaded (its thread count set to 1).
    pub blis: bool,
    /// An OpenMP runtime's thread count for the next parallel region
    /// (`omp_get_max_threads()`), when one is loaded.
    pub omp_threads: Option<i64>,
}

/// Sets every loaded BLAS and OpenMP runtime to one thread and returns what it found.
pub fn pin_one_thread() -> BlasThreads {
    set(c"openblas_set_num_threads", 1);
    let blis = set(c"bli_thread_set_num_threads", 1);
    set(c"omp_set_num_threads", 1);
    BlasThreads {
        openblas_config: text(c"openblas_get_config").map(|s| s.trim().to_owned()),
        openblas_core: text(c"openblas_get_corename"),
        openblas_threads: get(c"openblas_get_num_threads"),
        blis,
        omp_threads: get(c"omp_get_max_threads"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The build links Debian's OpenBLAS (`libopenblas0-pthread`, see
    /// vendor-config/debian-packages.txt): it is found and left at one thread.
    #[test]
    fn openblas_is_found_and_pinned() {
        let threads = pin_one_thread();
        assert_eq!(threads.openblas_threads, Some(1), "{threads:?}");
        assert!(
            threads
                .openblas_config
                .as_deref()
                .is_some_and(|c| c.starts_with("OpenBLAS")),
            "{threads:?}"
        );
        if let Some(omp) = threads.omp_threads {
            assert_eq!(omp, 1);
        }
    }
}

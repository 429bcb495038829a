//! The one place that knows how Ipopt's C interface differs between the versions vito builds
//! against (3.11 to 3.14). `build.rs` reads the version of the `IpStdCInterface.h` it generates
//! the bindings from and sets `cfg(ipopt_3_14)` for 3.14 and later; the rest of the wrapper
//! uses the names defined here and never looks at `sys`'s version-dependent types itself.
//!
//! | | 3.11-3.13 (`coin/`) | 3.14 (`coin-or/`) |
//! | --- | --- | --- |
//! | truth values | `Bool` = `int`, `TRUE` 1 | C `bool` |
//! | indices, integer options | `Index`, `Int` = `int` | `ipindex` (`int`; `int64_t` in an `IPOPT_INT64` build) |
//! | numbers | `Number` = `double` | `ipnumber` (`double`) |
//! | return codes | up to `Maximum_CpuTime_Exceeded` = -4 | also `Maximum_WallTime_Exceeded` = -5 |

#[cfg(not(ipopt_3_14))]
mod types {
    use super::super::sys;

    /// Ipopt's index type (sizes, sparsity triplets, iteration counts).
    pub type Index = sys::Index;
    /// Ipopt's floating-point type.
    pub type Number = sys::Number;
    /// The value type of `AddIpoptIntOption`.
    pub type Int = sys::Int;
    /// The callbacks' and option setters' truth value: an `int` before 3.14.
    pub type Bool = sys::Bool;
    /// Ipopt's true.
    pub const TRUE: Bool = 1;
    /// Ipopt's false.
    pub const FALSE: Bool = 0;

    /// A truth value from Ipopt as a Rust `bool`.
    pub fn is_true(value: Bool) -> bool {
        value != 0
    }

    /// 3.11 has no wall-time limit; the code is kept (never returned) so that every version
    /// has the same status table.
    pub const MAXIMUM_WALL_TIME_EXCEEDED: sys::ApplicationReturnStatus =
        sys::ApplicationReturnStatus(-5);
}

#[cfg(ipopt_3_14)]
mod types {
    use super::super::sys;

    /// Ipopt's index type (sizes, sparsity triplets, iteration counts).
    pub type Index = sys::ipindex;
    /// Ipopt's floating-point type.
    pub type Number = sys::ipnumber;
    /// The value type of `AddIpoptIntOption` (an `ipindex` since 3.14).
    pub type Int = sys::ipindex;
    /// The callbacks' and option setters' truth value: C `bool` since 3.14.
    pub type Bool = bool;
    /// Ipopt's true.
    pub const TRUE: Bool = true;
    /// Ipopt's false.
    pub const FALSE: Bool = false;

    /// A truth value from Ipopt as a Rust `bool`.
    pub fn is_true(value: Bool) -> bool {
        value
    }

    /// `max_wall_time` reached (option and code new in 3.14).
    pub const MAXIMUM_WALL_TIME_EXCEEDED: sys::ApplicationReturnStatus =
        sys::ApplicationReturnStatus::Maximum_WallTime_Exceeded;
}

pub(super) use types::*;

/// The Ipopt release vito was built against, from its `IpoptConfig.h`, e.g. `"3.14.17"`.
pub const VERSION: &str = env!("VITO_IPOPT_VERSION");

/// `vito <version> (Ipopt <version>)`'s version part, for `--version`.
pub const LONG_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (Ipopt ",
    env!("VITO_IPOPT_VERSION"),
    ")"
);

/// Whether the process has MPI, and its state, as far as Ipopt's MUMPS is concerned.
///
/// Debian 13's Ipopt 3.14 links the MPI build of MUMPS 5.7 (OpenMPI), and its `libipopt`
/// calls `MPI_Init` when the library is loaded, before `main`, and `MPI_Finalize` at exit:
/// vito never initialises MPI itself, and no MPI call may follow process exit handlers.
/// Debian 12's Ipopt 3.11 links the sequential MUMPS, which has no MPI at all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MpiState {
    /// No `MPI_Initialized` symbol in the process: sequential MUMPS.
    Absent,
    /// MPI is linked; `initialized` once `MPI_Init` ran, `finalized` once `MPI_Finalize` ran
    /// (after which no MPI call, so no MUMPS factorisation, may happen in this process).
    Linked {
        /// `MPI_Initialized`'s answer.
        initialized: bool,
        /// `MPI_Finalized`'s answer.
        finalized: bool,
    },
}

/// An MPI query function (`MPI_Initialized`, `MPI_Finalized`): `int f(int *flag)`.
type MpiFlagQuery = unsafe extern "C" fn(*mut std::ffi::c_int) -> std::ffi::c_int;

unsafe extern "C" {
    /// glibc's symbol lookup (in libc itself since glibc 2.34).
    fn dlsym(
        handle: *mut std::ffi::c_void,
        symbol: *const std::ffi::c_char,
    ) -> *mut std::ffi::c_void;
}

/// Looks `name` up among the symbols of the program and the libraries it loaded.
fn mpi_query(name: &std::ffi::CStr) -> Option<MpiFlagQuery> {
    // SAFETY: a null handle is glibc's RTLD_DEFAULT (search the global scope); `name` is a
    // NUL-terminated string that dlsym only reads.
    let address = unsafe { dlsym(std::ptr::null_mut(), name.as_ptr()) };
    if address.is_null() {
        return None;
    }
    // SAFETY: MPI_Initialized and MPI_Finalized are declared `int f(int *flag)` by every MPI
    // standard; a non-null address for those names is that function.
    Some(unsafe { std::mem::transmute::<*mut std::ffi::c_void, MpiFlagQuery>(address) })
}

/// The process's MPI state (see [`MpiState`]). Both queries may be called at any time, also
/// before `MPI_Init` and after `MPI_Finalize` (MPI standard, section "Startup").
pub fn mpi_state() -> MpiState {
    let (Some(initialized), Some(finalized)) =
        (mpi_query(c"MPI_Initialized"), mpi_query(c"MPI_Finalized"))
    else {
        return MpiState::Absent;
    };
    let ask = |query: MpiFlagQuery| {
        let mut flag: std::ffi::c_int = 0;
        // SAFETY: `flag` is a live int the function writes its answer to.
        let code = unsafe { query(&mut flag) };
        code == 0 && flag != 0
    };
    MpiState::Linked {
        initialized: ask(initialized),
        finalized: ask(finalized),
    }
}

//! Build script: finds Ipopt (Debian's `coinor-libipopt-dev` through pkg-config, or a prefix
//! named by `VITO_IPOPT_DIR`), links `-lipopt` only, and generates the raw bindings of
//! `coin/IpStdCInterface.h` with bindgen into `$OUT_DIR/ipopt_sys.rs`.
//!
//! Debian's `ipopt.pc` lists `-lblas -llapack` although the packages that ship the unversioned
//! `libblas.so`/`liblapack.so` are not its dependencies, so its full link line can fail; the
//! shared `libipopt.so` resolves its own dependencies, so `-lipopt` is all we pass.

use std::env;
use std::path::{Path, PathBuf};

/// Environment variable naming an Ipopt install prefix (with `include/coin/` and `lib/`) that
/// replaces the pkg-config probe.
const DIR_ENV: &str = "VITO_IPOPT_DIR";

/// Oldest Ipopt whose C interface matches the bindings' use (Debian bookworm ships 3.11.9).
const MIN_VERSION: &str = "3.11";
/// Ipopt 3.14 changed the C interface (types, header location `coin-or/`).
const MAX_VERSION_EXCLUSIVE: &str = "3.14";

/// Where the headers and the library are.
struct IpoptInstall {
    /// Directories for `-I`; `coin/IpStdCInterface.h` must be found under one of them.
    include_dirs: Vec<PathBuf>,
    /// Directory holding `libipopt.so`.
    lib_dir: PathBuf,
    /// Whether the library lies outside the loader's default paths (then an rpath is added).
    needs_rpath: bool,
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed=src/ipopt/wrapper.h");
    println!("cargo:rerun-if-env-changed={DIR_ENV}");

    let install = find_ipopt().unwrap_or_else(|reason| fail(&reason));

    println!(
        "cargo:rustc-link-search=native={}",
        install.lib_dir.display()
    );
    println!("cargo:rustc-link-lib=dylib=ipopt");
    if install.needs_rpath {
        println!(
            "cargo:rustc-link-arg=-Wl,-rpath,{}",
            install.lib_dir.display()
        );
    }

    let out_dir = PathBuf::from(env::var_os("OUT_DIR").unwrap_or_else(|| fail("OUT_DIR unset")));
    generate_bindings(&install, &out_dir.join("ipopt_sys.rs"))
        .unwrap_or_else(|reason| fail(&reason));
}

/// The prefix from `VITO_IPOPT_DIR` if set, otherwise pkg-config's `ipopt`.
fn find_ipopt() -> Result<IpoptInstall, String> {
    if let Some(dir) = env::var_os(DIR_ENV) {
        return from_prefix(Path::new(&dir));
    }
    from_pkg_config()
}

/// Ipopt installed under `prefix` (`prefix/include/coin/IpStdCInterface.h`, `prefix/lib`).
fn from_prefix(prefix: &Path) -> Result<IpoptInstall, String> {
    let include = prefix.join("include");
    let header = include.join("coin").join("IpStdCInterface.h");
    if !header.is_file() {
        return Err(format!(
            "{DIR_ENV}={} has no {}",
            prefix.display(),
            header.display()
        ));
    }
    let lib_dir = ["lib", "lib64"]
        .iter()
        .map(|sub| prefix.join(sub))
        .find(|dir| dir.join("libipopt.so").exists() || dir.join("libipopt.a").exists())
        .ok_or_else(|| {
            format!(
                "{DIR_ENV}={} has no lib/libipopt.so (nor lib64/)",
                prefix.display()
            )
        })?;
    Ok(IpoptInstall {
        include_dirs: vec![include],
        lib_dir,
        needs_rpath: true,
    })
}

/// Ipopt as pkg-config reports it; only its include and library directories are used.
fn from_pkg_config() -> Result<IpoptInstall, String> {
    let library = pkg_config::Config::new()
        .range_version(MIN_VERSION..MAX_VERSION_EXCLUSIVE)
        .cargo_metadata(false)
        .env_metadata(true)
        .probe("ipopt")
        .map_err(|e| {
            format!(
                "pkg-config could not find ipopt >= {MIN_VERSION}, < {MAX_VERSION_EXCLUSIVE}: {e}"
            )
        })?;
    let lib_dir = pkg_config::get_variable("ipopt", "libdir")
        .map_err(|e| format!("pkg-config has no libdir for ipopt: {e}"))?;
    // The .pc file gives `.../include/coin`; the wrapper includes `coin/IpStdCInterface.h`, so
    // the parent goes on the path too.
    let mut include_dirs = Vec::new();
    for dir in &library.include_paths {
        include_dirs.push(dir.clone());
        if dir.ends_with("coin")
            && let Some(parent) = dir.parent()
        {
            include_dirs.push(parent.to_path_buf());
        }
    }
    Ok(IpoptInstall {
        include_dirs,
        lib_dir: PathBuf::from(lib_dir),
        needs_rpath: false,
    })
}

/// Runs bindgen on `src/ipopt/wrapper.h`, keeping only the C interface's functions and types.
fn generate_bindings(install: &IpoptInstall, out: &Path) -> Result<(), String> {
    let mut builder = bindgen::Builder::default()
        .header("src/ipopt/wrapper.h")
        .allowlist_function(
            "CreateIpoptProblem|FreeIpoptProblem|AddIpopt(Str|Num|Int)Option|\
             OpenIpoptOutputFile|SetIpoptProblemScaling|SetIntermediateCallback|IpoptSolve",
        )
        .allowlist_type("ApplicationReturnStatus|Eval_(F|Grad_F|G|Jac_G|H)_CB|Intermediate_CB")
        // A newtype, not a Rust enum: a status code outside the list must not be undefined
        // behaviour; `status.rs` maps the known ones.
        .newtype_enum("ApplicationReturnStatus")
        .generate_comments(false)
        .rust_edition(bindgen::RustEdition::Edition2024)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    for dir in &install.include_dirs {
        builder = builder.clang_arg(format!("-I{}", dir.display()));
    }
    // bindgen panics when libclang cannot be loaded; turn that into our message.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let generated =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    std::panic::set_hook(default_hook);
    let bindings = match generated {
        Ok(Ok(bindings)) => bindings,
        Ok(Err(e)) => return Err(format!("bindgen failed on coin/IpStdCInterface.h: {e}")),
        Err(payload) => {
            let message = payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".to_string());
            return Err(format!(
                "bindgen could not run (libclang missing?): {message}"
            ));
        }
    };
    bindings
        .write_to_file(out)
        .map_err(|e| format!("cannot write {}: {e}", out.display()))
}

/// Stops the build with one message that says what is missing and how to install it (an exit,
/// not a panic, so that no backtrace buries it).
fn fail(reason: &str) -> ! {
    eprintln!(
        "\n\nvito cannot build against Ipopt: {reason}\n\n\
         vito needs Ipopt {MIN_VERSION}.x-3.13.x with its C headers, libclang (for bindgen) and \
         pkg-config.\nOn Debian/Ubuntu install them with\n\n    \
         sudo bash vendor-config/install-deps.sh\n\n\
         (it installs what is missing of: coinor-libipopt-dev libclang-dev pkg-config \
         libopenblas0-pthread),\nor point {DIR_ENV} at an Ipopt prefix holding \
         include/coin/IpStdCInterface.h and lib/libipopt.so.\n\n"
    );
    std::process::exit(1)
}

//! Build script: finds Ipopt 3.11-3.14 (Debian's `coinor-libipopt-dev` through pkg-config, or a
//! prefix named by `VITO_IPOPT_DIR`), links `-lipopt` only, and generates the raw bindings of
//! `IpStdCInterface.h` (under `coin/` up to 3.13, `coin-or/` from 3.14) with bindgen into
//! `$OUT_DIR/ipopt_sys.rs`.
//!
//! The version comes from the `IPOPT_VERSION` of the `IpoptConfig.h` beside that header (what
//! the bindings are made from), pkg-config's when that file is missing. It is passed on as the
//! environment variable `VITO_IPOPT_VERSION` and, for 3.14 and later, as `cfg(ipopt_3_14)`,
//! which `src/ipopt/compat.rs` alone reads (3.14's C interface uses `bool`, `ipindex` and
//! `ipnumber` where 3.11 has `Bool` = int, `Index` and `Number`).
//!
//! Debian's `ipopt.pc` lists `-lblas -llapack` although the packages that ship the unversioned
//! `libblas.so`/`liblapack.so` are not its dependencies, so its full link line can fail; the
//! shared `libipopt.so` resolves its own dependencies, so `-lipopt` is all we pass.

use std::env;
use std::path::{Path, PathBuf};

/// Environment variable naming an Ipopt install prefix (with `include/coin-or/` or
/// `include/coin/`, and `lib/`) that
/// replaces the pkg-config probe.
const DIR_ENV: &str = "VITO_IPOPT_DIR";

/// Oldest Ipopt whose C interface matches the bindings' use (Debian bookworm ships 3.11.9).
const MIN_VERSION: &str = "3.11";
/// First Ipopt release not known to work (Debian trixie ships 3.14.17, Ubuntu 3.14.19).
const MAX_VERSION_EXCLUSIVE: &str = "3.15";
/// The C header, found directly in an include directory or under one of these subdirectories
/// (`coin-or/` from 3.14 on, `coin/` before).
const HEADER: &str = "IpStdCInterface.h";
const HEADER_SUBDIRS: [&str; 3] = ["", "coin-or", "coin"];

/// Where the headers and the library are.
struct IpoptInstall {
    /// Directories for `-I`.
    include_dirs: Vec<PathBuf>,
    /// `-D` definitions from pkg-config's Cflags (3.14's `ipopt.pc` has `-DHAVE_CSTDDEF`).
    defines: Vec<String>,
    /// The `IpStdCInterface.h` bindgen reads.
    header: PathBuf,
    /// Version as `(major, minor, release)`.
    version: (u32, u32, u32),
    /// Directory holding `libipopt.so`.
    lib_dir: PathBuf,
    /// Whether the library lies outside the loader's default paths (then an rpath is added).
    needs_rpath: bool,
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed={DIR_ENV}");
    println!("cargo::rustc-check-cfg=cfg(ipopt_3_14)");

    let install = find_ipopt().unwrap_or_else(|reason| fail(&reason));
    println!("cargo:rerun-if-changed={}", install.header.display());
    let (major, minor, release) = install.version;
    println!("cargo:rustc-env=VITO_IPOPT_VERSION={major}.{minor}.{release}");
    if (major, minor) >= (3, 14) {
        println!("cargo:rustc-cfg=ipopt_3_14");
    }

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

/// Ipopt installed under `prefix` (`prefix/include/coin-or/` or `prefix/include/coin/`, and
/// `prefix/lib` or `prefix/lib64`).
fn from_prefix(prefix: &Path) -> Result<IpoptInstall, String> {
    let include = prefix.join("include");
    let header = find_header(std::slice::from_ref(&include)).ok_or_else(|| {
        format!(
            "{DIR_ENV}={} has no include/coin-or/{HEADER} nor include/coin/{HEADER}",
            prefix.display()
        )
    })?;
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
    let version = header_version(&header)?.ok_or_else(|| {
        format!(
            "{DIR_ENV}={}: no IPOPT_VERSION in IpoptConfig.h beside {}",
            prefix.display(),
            header.display()
        )
    })?;
    check_version(version)?;
    Ok(IpoptInstall {
        include_dirs: vec![include],
        defines: Vec::new(),
        header,
        version,
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
    let header = find_header(&library.include_paths).ok_or_else(|| {
        format!(
            "pkg-config's ipopt {} names no directory holding {HEADER} (include paths: {:?})",
            library.version, library.include_paths
        )
    })?;
    // The header's own IpoptConfig.h is what the bindings are made from; pkg-config's
    // version stands in only where that file lacks IPOPT_VERSION.
    let version = match header_version(&header)? {
        Some(version) => version,
        None => parse_version(&library.version).ok_or_else(|| {
            format!(
                "cannot read pkg-config's ipopt version {:?}",
                library.version
            )
        })?,
    };
    check_version(version)?;
    let defines = library
        .defines
        .iter()
        .map(|(name, value)| match value {
            Some(value) => format!("-D{name}={value}"),
            None => format!("-D{name}"),
        })
        .collect();
    Ok(IpoptInstall {
        include_dirs: library.include_paths,
        defines,
        header,
        version,
        lib_dir: PathBuf::from(lib_dir),
        needs_rpath: false,
    })
}

/// The first `IpStdCInterface.h` in `dirs`, directly or under `coin-or/` or `coin/`.
fn find_header(dirs: &[PathBuf]) -> Option<PathBuf> {
    dirs.iter().find_map(|dir| {
        HEADER_SUBDIRS
            .iter()
            .map(|sub| dir.join(sub).join(HEADER))
            .find(|path| path.is_file())
    })
}

/// `IPOPT_VERSION` from the `IpoptConfig.h` beside `header`, if that file defines it.
fn header_version(header: &Path) -> Result<Option<(u32, u32, u32)>, String> {
    let Some(config) = header.parent().map(|dir| dir.join("IpoptConfig.h")) else {
        return Ok(None);
    };
    if !config.is_file() {
        return Ok(None);
    }
    println!("cargo:rerun-if-changed={}", config.display());
    let text = std::fs::read_to_string(&config)
        .map_err(|e| format!("cannot read {}: {e}", config.display()))?;
    for line in text.lines() {
        let mut words = line.split_whitespace();
        if let (Some("#define"), Some("IPOPT_VERSION"), Some(value)) =
            (words.next(), words.next(), words.next())
        {
            return parse_version(value.trim_matches('"'))
                .map(Some)
                .ok_or_else(|| format!("{}: cannot read IPOPT_VERSION {value}", config.display()));
        }
    }
    Ok(None)
}

/// `"3.14.17"` as `(3, 14, 17)`; a missing release is 0 (`"3.14"`), a suffix after the
/// release (`"3.14.17-rc1"`) is ignored.
fn parse_version(text: &str) -> Option<(u32, u32, u32)> {
    let mut parts = text.trim().splitn(3, '.');
    let major = parts.next()?.parse().ok()?;
    let minor = parts.next()?.parse().ok()?;
    let release = match parts.next() {
        None => 0,
        Some(rest) => {
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            digits.parse().ok()?
        }
    };
    Some((major, minor, release))
}

/// Refuses a version outside [`MIN_VERSION`, `MAX_VERSION_EXCLUSIVE`).
fn check_version(version: (u32, u32, u32)) -> Result<(), String> {
    let bound = |text: &str| parse_version(text).unwrap_or((0, 0, 0));
    if version < bound(MIN_VERSION) || version >= bound(MAX_VERSION_EXCLUSIVE) {
        let (major, minor, release) = version;
        return Err(format!(
            "found Ipopt {major}.{minor}.{release}, need >= {MIN_VERSION}, < {MAX_VERSION_EXCLUSIVE}"
        ));
    }
    Ok(())
}

/// Runs bindgen on the found `IpStdCInterface.h`, keeping only the C interface's functions and
/// types (`Bool`, `Index`, `Number` up to 3.13; `ipindex`, `ipnumber` from 3.14).
fn generate_bindings(install: &IpoptInstall, out: &Path) -> Result<(), String> {
    let header = install
        .header
        .to_str()
        .ok_or_else(|| format!("{} is not UTF-8", install.header.display()))?;
    let mut builder = bindgen::Builder::default()
        .header(header)
        .allowlist_function(
            "CreateIpoptProblem|FreeIpoptProblem|AddIpopt(Str|Num|Int)Option|\
             OpenIpoptOutputFile|SetIpoptProblemScaling|SetIntermediateCallback|IpoptSolve",
        )
        .allowlist_type(
            "ApplicationReturnStatus|Eval_(F|Grad_F|G|Jac_G|H)_CB|Intermediate_CB|UserDataPtr|\
             Bool|Index|Int|Number|ipindex|ipnumber",
        )
        // A newtype, not a Rust enum: a status code outside the list must not be undefined
        // behaviour; `status.rs` maps the known ones.
        .newtype_enum("ApplicationReturnStatus")
        .generate_comments(false)
        .rust_edition(bindgen::RustEdition::Edition2024)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    for dir in &install.include_dirs {
        builder = builder.clang_arg(format!("-I{}", dir.display()));
    }
    builder = builder.clang_args(&install.defines);
    // bindgen panics when libclang cannot be loaded; turn that into our message.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let generated =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || builder.generate()));
    std::panic::set_hook(default_hook);
    let bindings = match generated {
        Ok(Ok(bindings)) => bindings,
        Ok(Err(e)) => return Err(format!("bindgen failed on {header}: {e}")),
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
         vito needs Ipopt {MIN_VERSION}.x-3.14.x with its C headers, libclang (for bindgen) and \
         pkg-config.\nOn Debian/Ubuntu install them with\n\n    \
         sudo bash vendor-config/install-deps.sh\n\n\
         (it installs what is missing of: coinor-libipopt-dev libclang-dev pkg-config \
         libopenblas0-pthread),\nor point {DIR_ENV} at an Ipopt prefix holding \
         include/coin-or/{HEADER} (3.14) or include/coin/{HEADER} (3.11-3.13) and \
         lib/libipopt.so.\n\n"
    );
    std::process::exit(1)
}

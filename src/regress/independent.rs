//! The independent CasADi implementation of the reference problems
//! (`tools/independent/spec_casadi.py`), run for timing beside vito's own solves.
//!
//! It shares no code with vito; `vito bench` runs its `--bench` mode, one problem per
//! process, and reads the JSON line it prints. Python and its `casadi` package are optional:
//! [`Independent::locate`] says why the column is missing when they are.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde::Deserialize;

/// The script, relative to the repository root.
pub const SCRIPT: &str = "tools/independent/spec_casadi.py";

/// One timed CasADi solve: the solver call only (building the expressions is not counted,
/// as vito's wall time does not count transcription), split into CasADi's function
/// evaluations and the rest (Ipopt).
#[derive(Debug, Clone, Deserialize)]
pub struct IndependentRow {
    pub problem: String,
    pub implementation: String,
    pub variables: usize,
    pub constraints: usize,
    pub status: String,
    pub iterations: usize,
    pub objective: f64,
    pub max_slack: f64,
    pub wall_s: f64,
    pub functions_s: f64,
    pub ipopt_s: f64,
}

/// A Python interpreter that imports `casadi`, and the script.
#[derive(Debug, Clone)]
pub struct Independent {
    python: PathBuf,
    script: PathBuf,
}

impl Independent {
    /// The interpreter is `$VITO_PYTHON` or `python3`; the script `$VITO_CASADI_SCRIPT`, else
    /// [`SCRIPT`] in the repository vito was built from (never the working directory: a
    /// dataset's `tools/` or `casadi.py` is not run). Python runs isolated (`-I`: neither the
    /// working directory, nor the script's, nor `PYTHON*` variables reach `sys.path`).
    /// `Err` says what is missing and how to get it.
    pub fn locate() -> Result<Independent, String> {
        let python =
            std::env::var_os("VITO_PYTHON").map_or_else(|| "python3".into(), PathBuf::from);
        let script = match std::env::var_os("VITO_CASADI_SCRIPT") {
            Some(s) => PathBuf::from(s),
            None => Path::new(env!("CARGO_MANIFEST_DIR")).join(SCRIPT),
        };
        if !script.is_absolute() || !script.is_file() {
            return Err(format!(
                "{} is not a file given by an absolute path (a vito built outside its repository \
                 has no CasADi script: set VITO_CASADI_SCRIPT)",
                script.display()
            ));
        }
        let imports = Self::isolated(&python)
            .args(["-c", "import casadi"])
            .output()
            .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
        if !imports.status.success() {
            return Err(format!(
                "{} cannot import casadi (pip install casadi==3.8.2, or `make bench-casadi`)",
                python.display()
            ));
        }
        Ok(Independent { python, script })
    }

    /// `python -I`: the working directory never reaches `sys.path`.
    fn isolated(python: &Path) -> Command {
        let mut command = Command::new(python);
        command.arg("-I");
        command
    }

    /// Solves `problem` (one of [`super::reference::NAMES`], which the script implements) once with the CasADi implementation.
    pub fn bench(&self, problem: &str) -> Result<IndependentRow, String> {
        let out = Self::isolated(&self.python)
            .arg(&self.script)
            .args(["--bench", problem])
            .output()
            .map_err(|e| format!("cannot run {}: {e}", self.python.display()))?;
        if !out.status.success() {
            return Err(format!(
                "{} --bench {problem} failed: {}",
                self.script.display(),
                String::from_utf8_lossy(&out.stderr).trim()
            ));
        }
        let stdout = String::from_utf8_lossy(&out.stdout);
        // CasADi's Ipopt prints its banner on stdout; the row is the last JSON line.
        let line = stdout
            .lines()
            .rev()
            .find(|l| l.starts_with('{'))
            .ok_or_else(|| format!("{} printed no result for {problem}", self.script.display()))?;
        serde_json::from_str(line).map_err(|e| format!("unreadable result for {problem}: {e}"))
    }
}

//! Conversions between Python values and the library's: `set={...}` values as the text of a
//! `--set` value (bounded in depth and size, as the command line bounds an argument), the
//! overrides back as Python literals (for `repr`), JSON as Python objects, rows as arrays,
//! the columns of a trajectory CSV, and path arguments (str, bytes or os.PathLike).

use std::ffi::OsString;
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::path::{Path, PathBuf};

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use vito::problem::Override;
use vito::report;

use crate::errors::VitoError;

/// How deep lists may nest in a `set=` value (as deep as an expression may nest).
pub(crate) const MAX_SET_DEPTH: usize = vito::problem::family::MAX_NESTING;
/// The longest `set=` value, as text (the longest single argument Linux passes to a command).
pub(crate) const MAX_SET_BYTES: usize = 128 * 1024;

/// The text of one `set=` value being built, with its budget.
struct SetText {
    key: String,
    text: String,
}

impl SetText {
    fn too_large(&self) -> PyErr {
        PyValueError::new_err(format!(
            "set={{{:?}: ...}}: the value is larger than {MAX_SET_BYTES} bytes as TOML, more \
             than a --set argument can hold; give it in the problem file",
            self.key
        ))
    }

    fn push(&mut self, s: &str) -> PyResult<()> {
        if self.text.len() + s.len() > MAX_SET_BYTES {
            return Err(self.too_large());
        }
        self.text.push_str(s);
        Ok(())
    }

    /// Appends `value` as TOML: strings as given at the top (like the command line), quoted
    /// inside lists; booleans, ints, floats, lists and tuples as TOML.
    fn value(&mut self, value: &Bound<'_, PyAny>, depth: usize) -> PyResult<()> {
        if value.is_instance_of::<PyString>() {
            let s = value.extract::<String>()?;
            return if depth == 0 {
                self.push(&s)
            } else {
                self.push(&toml::Value::String(s).to_string())
            };
        }
        if value.is_instance_of::<PyBool>() {
            return self.push(if value.extract::<bool>()? {
                "true"
            } else {
                "false"
            });
        }
        if value.is_instance_of::<PyInt>() {
            let i = value.extract::<i64>().map_err(|_| {
                PyValueError::new_err(format!(
                    "set={{{:?}: {}}}: the int does not fit in 64 bits (TOML's integers)",
                    self.key,
                    value.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
            return self.push(&i.to_string());
        }
        if value.is_instance_of::<PyFloat>() {
            let x = value.extract::<f64>()?;
            // TOML spells the non-finite values inf and nan; Rust's `{:?}` keeps a `.0`.
            let text = if x.is_nan() {
                "nan".to_owned()
            } else if x.is_infinite() {
                if x > 0.0 { "inf" } else { "-inf" }.to_owned()
            } else {
                format!("{x:?}")
            };
            return self.push(&text);
        }
        if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
            if depth >= MAX_SET_DEPTH {
                return Err(PyValueError::new_err(format!(
                    "set={{{:?}: [...]}}: the list nests more than {MAX_SET_DEPTH} deep (or \
                     contains itself)",
                    self.key
                )));
            }
            // Two bytes per item at least ("x,"): refused before walking a huge list.
            if value.len()?.saturating_mul(2) > MAX_SET_BYTES {
                return Err(self.too_large());
            }
            self.push("[")?;
            for (i, item) in value.try_iter()?.enumerate() {
                if i > 0 {
                    self.push(", ")?;
                }
                self.value(&item?, depth + 1)?;
            }
            return self.push("]");
        }
        // numpy's scalars and other numbers.
        if let Ok(x) = value.extract::<f64>()
            && value.hasattr("__float__")?
            && !value.hasattr("__index__")?
        {
            return self.value(PyFloat::new(value.py(), x).as_any(), depth);
        }
        if value.hasattr("__index__")? {
            let i: i64 = value.call_method0("__index__")?.extract()?;
            return self.push(&i.to_string());
        }
        Err(PyTypeError::new_err(format!(
            "set={{{:?}: ...}}: a value of type {} cannot be set; give a str, bool, int, float \
             or a list of them",
            self.key,
            value.get_type().name()?
        )))
    }
}

/// One value of `key` as the text of a `--set` value (a str as given).
pub(crate) fn value_text(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    let mut text = SetText {
        key: key.to_owned(),
        text: String::new(),
    };
    text.value(value, 0)?;
    Ok(text.text)
}

/// `set={key: value}` as `--set key=value` arguments (in the dict's order).
pub(crate) fn set_args(set: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    if set.is_none() {
        return Ok(Vec::new());
    }
    let set = set.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "set= takes a dict {{\"key.path\": value}}, not {}",
            set.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    set.iter()
        .map(|(k, v)| {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "set= keys are str (\"contacts.friction\"), not {}",
                    k.get_type()
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default()
                ))
            })?;
            Ok(format!("{key}={}", value_text(&key, &v)?))
        })
        .collect()
}

/// A TOML value as the Python literal that `set=` turns back into it.
fn python_literal(value: &toml::Value, top: bool) -> String {
    match value {
        toml::Value::String(s) => {
            // At the top a str is read as the command line reads it: one that would read as
            // something else is given quoted (TOML), so it stays a string.
            let reads_back = Override::parse(&format!("k={s}"))
                .is_ok_and(|o| o.value == toml::Value::String(s.clone()));
            if top && !reads_back {
                python_str(&toml::Value::String(s.clone()).to_string())
            } else {
                python_str(s)
            }
        }
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(x) if x.is_nan() => "float('nan')".into(),
        toml::Value::Float(x) if x.is_infinite() => if *x > 0.0 {
            "float('inf')"
        } else {
            "float('-inf')"
        }
        .into(),
        toml::Value::Float(x) => format!("{x:?}"),
        toml::Value::Boolean(b) => if *b { "True" } else { "False" }.into(),
        toml::Value::Array(items) => format!(
            "[{}]",
            items
                .iter()
                .map(|v| python_literal(v, false))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        other => python_str(&other.to_string()),
    }
}

/// A Python string literal (single quotes, backslash escapes).
pub(crate) fn python_str(s: &str) -> String {
    let mut out = String::from("'");
    for c in s.chars() {
        match c {
            '\\' => out.push_str("\\\\"),
            '\'' => out.push_str("\\'"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('\'');
    out
}

/// `--set` arguments as the `set={...}` dict literal that gives them again.
pub(crate) fn set_literal(sets: &[String]) -> String {
    let items: Vec<String> = sets
        .iter()
        .map(|s| match Override::parse(s) {
            Ok(o) => format!(
                "{}: {}",
                python_str(&o.path),
                python_literal(&o.value, true)
            ),
            Err(_) => python_str(s),
        })
        .collect();
    format!("{{{}}}", items.join(", "))
}

/// A `serde_json` value as Python objects (through Python's `json`).
pub(crate) fn json_to_py<'py>(
    py: Python<'py>,
    value: &serde_json::Value,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(|e| VitoError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Rows of equal length as a 2-D array of shape (rows, width).
pub(crate) fn matrix<'py>(py: Python<'py>, rows: &[Vec<f64>], width: usize) -> Bound<'py, PyAny> {
    let flat: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
    match Array2::from_shape_vec((rows.len(), width), flat) {
        Ok(a) => a.into_pyarray(py).into_any(),
        Err(_) => PyArray1::<f64>::zeros(py, 0, false).into_any(),
    }
}

/// A vector as a 1-D array.
pub(crate) fn vector<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyAny> {
    Array1::from(values.to_vec()).into_pyarray(py).into_any()
}

/// The columns of a trajectory CSV (the text vito writes) as `(header, values)`: the header
/// cells as written (`x [m]`), the values as the library reads them back (blank cells NaN).
pub(crate) fn csv_columns(csv: &str) -> PyResult<Vec<(String, Vec<f64>)>> {
    let headers: Vec<String> = csv
        .lines()
        .next()
        .unwrap_or_default()
        .split(',')
        .map(str::to_owned)
        .collect();
    let table = report::read_csv(csv).map_err(VitoError::new_err)?;
    Ok(headers.into_iter().zip(table.columns).collect())
}

/// A DataFrame of a trajectory CSV's columns, in its order, under its header.
pub(crate) fn csv_dataframe<'py>(py: Python<'py>, csv: &str) -> PyResult<Bound<'py, PyAny>> {
    let pandas = py.import("pandas")?;
    let data = PyDict::new(py);
    let mut order = Vec::new();
    for (header, values) in csv_columns(csv)? {
        data.set_item(&header, Array1::from(values).into_pyarray(py))?;
        order.push(header);
    }
    let kwargs = PyDict::new(py);
    kwargs.set_item("columns", order)?;
    pandas.call_method("DataFrame", (data,), Some(&kwargs))
}

/// `progress=`: None or a callable, checked before anything runs (a TypeError naming it).
/// A count argument (`starts=`, `jobs=`), checked as the command checks its option: 1 to
/// `max`.
pub(crate) fn count(name: &str, value: usize, max: usize) -> PyResult<usize> {
    vito::files::input::checked_count(value, max)
        .map_err(|m| PyValueError::new_err(format!("{name}={value}: {m}")))
}

pub(crate) fn check_progress(py: Python<'_>, progress: Option<&Py<PyAny>>) -> PyResult<()> {
    match progress {
        Some(p) if !p.bind(py).is_callable() => Err(PyTypeError::new_err(format!(
            "progress={}: give a callable (or None)",
            p.bind(py)
                .repr()
                .map_or_else(|_| "?".into(), |r| r.to_string())
        ))),
        _ => Ok(()),
    }
}

/// A path argument, taken as Python's own file functions take one: a str, bytes or
/// os.PathLike, through `os.fsencode` (a str with the file-system encoding and its error
/// handler, so a name that is not UTF-8, read from the OS as a str with surrogates, names
/// the same file; bytes as the name's bytes). Anything else is a TypeError.
pub(crate) struct PathArg(pub(crate) PathBuf);

impl<'a, 'py> FromPyObject<'a, 'py> for PathArg {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let encoded = obj.py().import("os")?.call_method1("fsencode", (obj,))?;
        let bytes = encoded.cast::<PyBytes>()?.as_bytes().to_vec();
        Ok(PathArg(PathBuf::from(OsString::from_vec(bytes))))
    }
}

/// A path as a Python literal that gives it again: a str, or bytes when the name is not
/// UTF-8.
pub(crate) fn python_path(path: &Path) -> String {
    match path.to_str() {
        Some(text) => python_str(text),
        None => {
            let mut out = String::from("b'");
            for &b in path.as_os_str().as_bytes() {
                match b {
                    b'\\' => out.push_str("\\\\"),
                    b'\'' => out.push_str("\\'"),
                    0x20..=0x7e => out.push(char::from(b)),
                    _ => out.push_str(&format!("\\x{b:02x}")),
                }
            }
            out.push('\'');
            out
        }
    }
}

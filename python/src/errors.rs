//! vito's errors as Python exceptions: `VitoError`, `ProblemError` (file, line, field,
//! message) and, for a problem file that does not exist, `ProblemFileNotFoundError`, which
//! is both a `ProblemError` and a `FileNotFoundError`. Messages speak of `set=` where the
//! command's speak of `--set`.

use pyo3::exceptions::{PyException, PyFileNotFoundError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};

use vito::problem::ProblemError as LibProblemError;

pyo3::create_exception!(
    vito,
    VitoError,
    PyException,
    "An error of vito: the message is the one the `vito` command prints."
);
pyo3::create_exception!(
    vito,
    ProblemError,
    VitoError,
    "A problem file (or an override, or a file it names) that vito cannot use, found before \
     any solving. Attributes: `file`, `line` (1-based, or None), `field` (the TOML path, or \
     ''), `message` (the explanation)."
);

/// `ProblemFileNotFoundError(ProblemError, FileNotFoundError)`, made once.
static NOT_FOUND: PyOnceLock<Py<PyType>> = PyOnceLock::new();

fn not_found_type(py: Python<'_>) -> PyResult<&Bound<'_, PyType>> {
    NOT_FOUND
        .get_or_try_init(py, || {
            let bases = PyTuple::new(
                py,
                [
                    py.get_type::<ProblemError>().into_any(),
                    py.get_type::<PyFileNotFoundError>().into_any(),
                ],
            )?;
            let namespace = PyDict::new(py);
            namespace.set_item("__module__", "vito")?;
            namespace.set_item(
                "__doc__",
                "A problem file (or a file it names) that does not exist: a `ProblemError` \
                 and a `FileNotFoundError` (`filename` is the path).",
            )?;
            let made =
                py.get_type::<PyType>()
                    .call1(("ProblemFileNotFoundError", bases, namespace))?;
            Ok(made.cast_into::<PyType>()?.unbind())
        })
        .map(|t| t.bind(py))
}

/// Adds the exception types to the module.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("VitoError", py.get_type::<VitoError>())?;
    m.add("ProblemError", py.get_type::<ProblemError>())?;
    m.add("ProblemFileNotFoundError", not_found_type(py)?)?;
    Ok(())
}

/// The library's words for its types, as Python names them (serde's `expected i64` is
/// `expected an int` from Python).
const TYPE_WORDS: [(&str, &str); 12] = [
    ("expected i64", "expected an int"),
    ("expected u64", "expected an int"),
    ("expected usize", "expected an int"),
    ("expected u32", "expected an int"),
    ("expected f64", "expected a float"),
    ("expected a string", "expected a str"),
    ("expected a boolean", "expected a bool"),
    ("expected a sequence", "expected a list"),
    ("expected an integer", "expected an int"),
    ("invalid type: integer", "invalid type: int"),
    ("invalid type: floating point", "invalid type: float"),
    ("invalid type: boolean", "invalid type: bool"),
];

/// A library message as Python's caller gave the input: `set=` for `--set`, Python's type
/// names for serde's.
pub(crate) fn python_words(message: &str) -> String {
    let mut m = message
        .replace(" (set with --set)", " (from set=)")
        .replace("--set ", "set= ");
    for (rust, python) in TYPE_WORDS {
        m = m.replace(rust, python);
    }
    m
}

/// A library problem error as a Python exception: a [`ProblemError`] with its location (a
/// `ProblemFileNotFoundError` for a missing file), the message in Python's words; an
/// unknown key from `set=` lists the family's `[parameters]`.
pub(crate) fn problem_error(py: Python<'_>, e: &LibProblemError) -> PyErr {
    let mut message = python_words(&e.to_string());
    let location = e.location();
    if let (LibProblemError::UnknownKey { at, .. }, Some(l)) = (e, location)
        && at.from_override
    {
        let parameters = vito::problem::family::declared_parameters(&l.file);
        if !parameters.is_empty() {
            let names: Vec<String> = parameters.iter().map(|p| format!("`{p}`")).collect();
            message.push_str(&format!(
                "; or a parameter of the family: {}",
                names.join(", ")
            ));
        }
    }
    let made = match e {
        LibProblemError::Io { path, source } if source.kind() == std::io::ErrorKind::NotFound => {
            not_found_type(py).and_then(|t| {
                let errno = source.raw_os_error().unwrap_or(2);
                let value = t.call1((errno, message.clone(), path.as_os_str()))?;
                Ok(PyErr::from_value(value))
            })
        }
        _ => Ok(ProblemError::new_err(message.clone())),
    };
    let err = match made {
        Ok(err) => err,
        Err(e) => return e,
    };
    // The file as Python names it (os.fsdecode's str, also for a name that is not UTF-8).
    let file = match (e, location) {
        (_, Some(l)) => Some(l.file.as_os_str()),
        (LibProblemError::Io { path, .. }, None) => Some(path.as_os_str()),
        _ => None,
    };
    let value = err.value(py);
    let result = (|| -> PyResult<()> {
        value.setattr("file", file)?;
        value.setattr("line", location.and_then(|l| l.line))?;
        value.setattr("field", location.map_or(String::new(), |l| l.field.clone()))?;
        value.setattr("message", message)
    })();
    match result {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// Any other library error, with its chain of causes as the command prints it.
pub(crate) fn vito_error(e: &dyn std::error::Error) -> PyErr {
    let mut message = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(&format!("\n  caused by: {text}"));
        }
        source = s.source();
    }
    VitoError::new_err(python_words(&message))
}

//! ARCHITECTURE.md against the tree: every path it names exists, every module of `src/` has
//! its row, and each module imports only from the modules listed above it.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn architecture() -> String {
    std::fs::read_to_string(root().join("ARCHITECTURE.md")).expect("ARCHITECTURE.md")
}

/// The text between backticks on `line`.
fn quoted(line: &str) -> Vec<&str> {
    line.split('`').skip(1).step_by(2).collect()
}

/// Whether a quoted name is a path: it holds a '/' or ends with a file extension the
/// repository uses; commands, options, TOML keys and Rust paths are not.
fn is_path(name: &str) -> bool {
    let simple = !name.contains([' ', '=', '[', '<', ':', '(', '"', '*']);
    let extension = [".rs", ".md", ".toml", ".py", ".html", ".opt"]
        .iter()
        .any(|e| name.ends_with(e));
    simple && (name.contains('/') || extension)
}

/// The rows of the module table: (module, the rest of the row).
fn module_rows(text: &str) -> Vec<(String, String)> {
    let mut rows = Vec::new();
    let mut inside = false;
    for line in text.lines() {
        if line.starts_with("## ") {
            inside = line.starts_with("## Modules");
            continue;
        }
        if !inside || !line.starts_with("| `") {
            continue;
        }
        let first = line.split('|').nth(1).unwrap_or_default();
        let module = quoted(first)
            .first()
            .copied()
            .unwrap_or_default()
            .to_string();
        rows.push((module, line.to_string()));
    }
    rows
}

/// The folder or file of module `m` in `src/`.
fn module_source(m: &str) -> Option<PathBuf> {
    let dir = root().join("src").join(m);
    let file = root().join("src").join(format!("{m}.rs"));
    [dir, file].into_iter().find(|p| p.exists())
}

#[test]
fn every_path_architecture_names_exists() {
    let text = architecture();
    let rows = module_rows(&text);
    let mut fenced = false;
    let mut missing = Vec::new();
    let mut checked = 0;
    for line in text.lines() {
        if line.starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // A file named in a module's row may be relative to that module's folder.
        let module = rows.iter().find(|(_, row)| row == line).map(|(m, _)| m);
        for name in quoted(line).into_iter().filter(|n| is_path(n)) {
            let mut bases = vec![root().to_path_buf(), root().join("src")];
            if let Some(m) = module {
                bases.insert(0, root().join("src").join(m));
            }
            checked += 1;
            if !bases.iter().any(|b| b.join(name).exists()) {
                missing.push(name.to_string());
            }
        }
    }
    assert!(
        checked > 100,
        "only {checked} paths found: is the page still parsed?"
    );
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md names paths that do not exist: {missing:?}"
    );
}

/// `crate::<module>` named on a line of code (comments left out) in the files under `path`.
fn imported_modules(path: &Path, found: &mut BTreeSet<String>) {
    if path.is_dir() {
        for entry in std::fs::read_dir(path).unwrap() {
            imported_modules(&entry.unwrap().path(), found);
        }
        return;
    }
    if path.extension().and_then(|e| e.to_str()) != Some("rs") {
        return;
    }
    let text = std::fs::read_to_string(path).unwrap();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or_default();
        for piece in code.split("crate::").skip(1) {
            let name: String = piece
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            found.insert(name);
        }
    }
}

#[test]
fn modules_import_only_from_the_modules_above_them() {
    let rows = module_rows(&architecture());
    let listed: Vec<&str> = rows.iter().map(|(m, _)| m.as_str()).collect();
    // Every module `src/lib.rs` declares has its row.
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).unwrap();
    for line in lib.lines() {
        if let Some(m) = line.trim().strip_prefix("pub mod ") {
            let m = m.trim_end_matches(';');
            assert!(
                listed.contains(&m),
                "module `{m}` has no row in ARCHITECTURE.md"
            );
        }
    }
    let mut upward = Vec::new();
    for (i, m) in listed.iter().enumerate() {
        let Some(source) = module_source(m) else {
            continue; // `cli` is the binary's, below `src/cli/`: checked by the path test
        };
        let mut found = BTreeSet::new();
        imported_modules(&source, &mut found);
        for other in found {
            if other != *m && listed[i + 1..].contains(&other.as_str()) {
                upward.push(format!("{m} -> {other}"));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports that run up the module order of ARCHITECTURE.md: {upward:?}"
    );
}

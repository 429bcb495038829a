//! Output directories that never cost a user a file.
//!
//! The rule: vito replaces only a directory it wrote itself (it holds the marker file
//! [`MARKER`], which lists every entry vito wrote there, and nothing else) or an empty one.
//! A file added to it later is never deleted: the directory is refused, naming the file. Anything else at the target — a file, a symbolic link, a
//! directory with other content — is refused, and so is a target that is the current
//! directory, an ancestor of it, or a directory holding one of the run's input files (the
//! problem file, its robot), before any solving ([`OutputTarget::check`]).
//!
//! Results are staged in a fresh sibling `.<name>.tmp-<pid>-<ns>` (marked at once), then
//! swapped with the target in one `renameat2(RENAME_EXCHANGE)`, and the previous results,
//! now at the staging path, are removed. A kill at any point leaves either the old or the
//! new results at the target; the staging sibling it may leave behind is removed by the
//! next run to the same target.

use std::io;
use std::path::{Component, Path, PathBuf};

use rustix::fs::{Access, CWD, RenameFlags};

/// The file that marks a directory as vito's own output (and so replaceable).
pub const MARKER: &str = ".vito-output";

/// Longest output directory name (bytes): the staging sibling adds about 40 to it, and
/// Linux allows 255 per component.
const MAX_NAME_BYTES: usize = 200;

/// Longest output directory path (bytes, made absolute): Linux allows 4,095 (`PATH_MAX`), and
/// the staging sibling and the files inside add about 60.
const MAX_PATH_BYTES: usize = 4000;

/// Why a directory cannot receive a run's results.
#[derive(Debug, thiserror::Error)]
pub enum OutputDirError {
    /// The target holds something vito did not write.
    #[error(
        "output directory {path} {what}; vito replaces only a directory it wrote itself \
         (one holding `{MARKER}`) or an empty one: choose another directory with --out, \
         or move that one away"
    )]
    NotOurs {
        /// The target.
        path: PathBuf,
        /// What is there ("is a file", "holds 3 entries vito did not write", …).
        what: String,
    },
    /// Replacing the target would delete the working directory or an input file.
    #[error(
        "output directory {path} is {relation}; replacing it would delete it: choose a \
         directory beside or below it with --out"
    )]
    Protected {
        /// The target.
        path: PathBuf,
        /// "the current directory", "an ancestor of the directory of the problem file …", …
        relation: String,
    },
    /// The path cannot name an output directory at all.
    #[error("output directory {path}: {message}")]
    Invalid {
        /// The path as given.
        path: PathBuf,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// The operating system refused an operation.
    #[error("output directory {path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating-system error.
        source: io::Error,
    },
}

fn io_error(path: &Path) -> impl FnOnce(io::Error) -> OutputDirError + '_ {
    move |source| OutputDirError::Io {
        path: path.to_owned(),
        source,
    }
}

/// A checked place for a run's results: an absolute path whose existing part is resolved
/// through symbolic links, whose parent can be created and written, and whose current
/// content (if any) vito may replace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputTarget {
    path: PathBuf,
}

impl OutputTarget {
    /// Checks `target` against the rule of this module; `inputs` are the files the run reads
    /// (the problem file, the URDF), whose directories must survive.
    pub fn check(target: &Path, inputs: &[&Path]) -> Result<OutputTarget, OutputDirError> {
        let invalid = |message: String| OutputDirError::Invalid {
            path: target.to_owned(),
            message,
        };
        let name = match target.components().next_back() {
            Some(Component::Normal(name)) => name.to_owned(),
            _ => {
                return Err(invalid(
                    "names no directory of its own (it ends in `.`, `..` or `/`): give a \
                     new directory's name, such as out/run1"
                        .into(),
                ));
            }
        };
        if name.len() > MAX_NAME_BYTES {
            return Err(invalid(format!(
                "its last component is {} bytes long; keep it under {MAX_NAME_BYTES}",
                name.len()
            )));
        }
        let cwd = std::env::current_dir().map_err(io_error(Path::new(".")))?;
        let absolute = cwd.join(target);
        if absolute.as_os_str().len() > MAX_PATH_BYTES {
            return Err(invalid(format!(
                "the path is {} bytes long (from the root); keep it under {MAX_PATH_BYTES} \
                 (Linux allows 4,095): choose a shorter path",
                absolute.as_os_str().len()
            )));
        }
        let path = resolve_existing_prefix(&absolute, target)?;
        let parent = path.parent().unwrap_or(Path::new("/"));
        check_parent(parent, target)?;

        let cwd = cwd.canonicalize().unwrap_or(cwd);
        if cwd.starts_with(&path) {
            let relation = if cwd == path {
                "the current directory".to_string()
            } else {
                format!("an ancestor of the current directory {}", cwd.display())
            };
            return Err(OutputDirError::Protected { path, relation });
        }
        for input in inputs {
            let Some(dir) = input
                .canonicalize()
                .ok()
                .and_then(|p| p.parent().map(Path::to_owned))
            else {
                continue;
            };
            if dir.starts_with(&path) {
                let relation = if dir == path {
                    format!("the directory holding the input {}", input.display())
                } else {
                    format!("an ancestor of the input {}", input.display())
                };
                return Err(OutputDirError::Protected { path, relation });
            }
        }
        replaceable(&path)?;
        Ok(OutputTarget { path })
    }

    /// The absolute target path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Creates the parent directories, removes staging siblings left by killed runs to the
    /// same target, and opens a fresh, marked staging directory.
    pub fn stage(&self) -> Result<StagedDir, OutputDirError> {
        let parent = self.path.parent().unwrap_or(Path::new("/"));
        std::fs::create_dir_all(parent).map_err(io_error(parent))?;
        remove_stale_siblings(&self.path);
        let staging = sibling(&self.path, "tmp");
        std::fs::create_dir(&staging).map_err(io_error(&staging))?;
        let staged = StagedDir {
            target: self.path.clone(),
            staging,
            committed: false,
        };
        let marker = staged.staging.join(MARKER);
        std::fs::write(&marker, format!("{MARKER_TEXT}\n")).map_err(io_error(&marker))?;
        Ok(staged)
    }
}

/// `absolute` with its longest existing prefix resolved through symbolic links; what
/// follows must be plain names (no `.`/`..` after a missing directory).
fn resolve_existing_prefix(absolute: &Path, given: &Path) -> Result<PathBuf, OutputDirError> {
    let mut existing = absolute.to_owned();
    let mut rest: Vec<std::ffi::OsString> = Vec::new();
    loop {
        // A target that is itself a link (dangling or not) is checked later, unresolved.
        let is_target = rest.is_empty();
        let meta = std::fs::symlink_metadata(&existing);
        let exists = match &meta {
            Ok(m) if is_target && m.file_type().is_symlink() => {
                return Err(OutputDirError::NotOurs {
                    path: given.to_owned(),
                    what: "is a symbolic link (vito does not write through links)".into(),
                });
            }
            Ok(_) => true,
            Err(_) => false,
        };
        if exists {
            break;
        }
        match (existing.file_name(), existing.parent()) {
            (Some(name), Some(parent)) => {
                rest.push(name.to_owned());
                existing = parent.to_owned();
            }
            (None, Some(_)) => {
                return Err(OutputDirError::Invalid {
                    path: given.to_owned(),
                    message: "has `.` or `..` after a directory that does not exist".into(),
                });
            }
            _ => break,
        }
    }
    let mut path = existing.canonicalize().map_err(io_error(&existing))?;
    for name in rest.iter().rev() {
        if name == ".." || name == "." {
            return Err(OutputDirError::Invalid {
                path: given.to_owned(),
                message: "has `.` or `..` after a directory that does not exist".into(),
            });
        }
        path.push(name);
    }
    Ok(path)
}

/// The nearest existing ancestor of `parent` must be a writable directory.
fn check_parent(parent: &Path, given: &Path) -> Result<(), OutputDirError> {
    let mut dir = parent;
    while !dir.exists() {
        match dir.parent() {
            Some(up) => dir = up,
            None => break,
        }
    }
    if !dir.is_dir() {
        return Err(OutputDirError::Invalid {
            path: given.to_owned(),
            message: format!(
                "{} is not a directory, so nothing can be created below it",
                dir.display()
            ),
        });
    }
    if rustix::fs::access(dir, Access::WRITE_OK).is_err() {
        return Err(OutputDirError::Invalid {
            path: given.to_owned(),
            message: format!("{} is not writable", dir.display()),
        });
    }
    Ok(())
}

/// Whether vito may replace what is at `path` now: nothing, an empty directory, or a
/// directory holding the marker.
fn replaceable(path: &Path) -> Result<(), OutputDirError> {
    let not_ours = |what: String| OutputDirError::NotOurs {
        path: path.to_owned(),
        what,
    };
    let meta = match std::fs::symlink_metadata(path) {
        Ok(meta) => meta,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_error(path)(e)),
    };
    if meta.file_type().is_symlink() {
        return Err(not_ours(
            "is a symbolic link (vito does not write through links)".into(),
        ));
    }
    if !meta.is_dir() {
        return Err(not_ours("is a file, not a directory".into()));
    }
    let entries = entries_besides_marker(path)?;
    let manifest = if is_marked(path) {
        read_manifest(path)
    } else {
        None
    };
    let foreign: Vec<&String> = entries
        .iter()
        .filter(|e| !manifest.as_ref().is_some_and(|m| m.contains(*e)))
        .collect();
    if foreign.is_empty() {
        return Ok(());
    }
    const SHOWN: usize = 8;
    let names = foreign
        .iter()
        .take(SHOWN)
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ");
    let more = if foreign.len() > SHOWN { ", …" } else { "" };
    Err(not_ours(match manifest {
        Some(_) => format!(
            "holds {} entr{} that vito did not write ({names}{more}; its own are listed in `{MARKER}`)",
            foreign.len(),
            if foreign.len() == 1 { "y" } else { "ies" }
        ),
        None if is_marked(path) => format!(
            "was written by a vito that did not list its files in `{MARKER}`, and holds {names}{more}"
        ),
        None => format!(
            "holds {} entr{} that vito did not write ({names}{more})",
            foreign.len(),
            if foreign.len() == 1 { "y" } else { "ies" }
        ),
    }))
}

/// The first line of [`MARKER`]; each entry vito wrote follows on a line of its own after
/// [`MANIFEST_PREFIX`].
const MARKER_TEXT: &str =
    "This directory was written by vito, which may replace it on the next run.";
/// The prefix of a manifest line of [`MARKER`].
const MANIFEST_PREFIX: &str = "wrote: ";

fn is_marked(dir: &Path) -> bool {
    std::fs::symlink_metadata(dir.join(MARKER)).is_ok_and(|m| m.is_file())
}

/// The entries [`MARKER`] lists as vito's (`None`: a marker without a list).
fn read_manifest(dir: &Path) -> Option<Vec<String>> {
    let text = crate::files::input::read_regular_text(
        &dir.join(MARKER),
        crate::files::input::MAX_TEXT_BYTES,
    )
    .ok()?;
    let names: Vec<String> = text
        .lines()
        .filter_map(|l| l.strip_prefix(MANIFEST_PREFIX))
        .map(str::to_owned)
        .collect();
    // A complete list ends with MANIFEST_END (the list of an empty result is empty).
    (text.lines().any(|l| l == MANIFEST_END) || !names.is_empty()).then_some(names)
}

/// Last line of a complete manifest.
const MANIFEST_END: &str = "end of list";

/// The names in `dir` other than [`MARKER`], sorted.
fn entries_besides_marker(dir: &Path) -> Result<Vec<String>, OutputDirError> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map_err(io_error(dir))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n != MARKER)
        .collect();
    names.sort();
    Ok(names)
}

/// Writes the [`MARKER`] of a staged directory with the list of everything in it.
fn write_manifest(dir: &Path) -> Result<(), OutputDirError> {
    let names = entries_besides_marker(dir)?;
    let mut text = format!("{MARKER_TEXT}\nIt replaces only the entries listed here.\n");
    for n in &names {
        text.push_str(&format!("{MANIFEST_PREFIX}{n}\n"));
    }
    text.push_str(MANIFEST_END);
    text.push('\n');
    let marker = dir.join(MARKER);
    crate::files::output::write_atomic(&marker, text.as_bytes()).map_err(io_error(&marker))
}

fn name_of(target: &Path) -> String {
    target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into())
}

fn sibling(target: &Path, tag: &str) -> PathBuf {
    let unique = format!(
        ".{}.{tag}-{}-{}",
        name_of(target),
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos())
    );
    target.with_file_name(unique)
}

/// Removes `.<name>.tmp-<pid>-*` siblings of `target` whose process is gone and which vito
/// marked (or which are empty): what a killed run left. Best effort: anything else stays.
fn remove_stale_siblings(target: &Path) {
    let (Some(parent), prefix) = (target.parent(), format!(".{}.tmp-", name_of(target))) else {
        return;
    };
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let Some(pid) = file_name
            .strip_prefix(&prefix)
            .and_then(|rest| rest.split('-').next())
            .and_then(|pid| pid.parse::<u32>().ok())
        else {
            continue;
        };
        let alive = pid == std::process::id() || Path::new(&format!("/proc/{pid}")).exists();
        let path = entry.path();
        let is_dir = std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir());
        let empty = std::fs::read_dir(&path).is_ok_and(|mut d| d.next().is_none());
        if !alive && is_dir && (is_marked(&path) || empty) {
            let _ = std::fs::remove_dir_all(&path);
        }
    }
}

/// A directory being written, to become the target on [`StagedDir::commit`]; dropped
/// uncommitted, it is removed.
#[derive(Debug)]
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Checks `target` (with no input files to protect besides the current directory) and
    /// stages it; see [`OutputTarget`].
    pub fn new(target: &Path) -> Result<StagedDir, OutputDirError> {
        OutputTarget::check(target, &[])?.stage()
    }

    /// Where files are written until the commit.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The final directory.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Swaps the staged directory into place in one atomic exchange, then removes the
    /// previous results. The target is checked again first, in case something else took
    /// its place while the run was solving.
    pub fn commit(mut self) -> Result<PathBuf, OutputDirError> {
        write_manifest(&self.staging)?;
        replaceable(&self.target)?;
        if self.target.exists() {
            rustix::fs::renameat_with(CWD, &self.staging, CWD, &self.target, RenameFlags::EXCHANGE)
                .map_err(|e| io_error(&self.target)(e.into()))?;
            self.committed = true;
            // The staging path now holds the previous results (marked, or empty).
            std::fs::remove_dir_all(&self.staging).map_err(io_error(&self.staging))?;
        } else {
            rustix::fs::renameat_with(
                CWD,
                &self.staging,
                CWD,
                &self.target,
                RenameFlags::NOREPLACE,
            )
            .map_err(|e| io_error(&self.target)(e.into()))?;
            self.committed = true;
        }
        Ok(self.target.clone())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// Creates the file `path` for writing, only if nothing is there: not a file, not a
/// directory, not a symbolic link (dangling or not, it is never followed; `O_CREAT | O_EXCL
/// | O_NOFOLLOW`). Every file vito writes outside a directory of its own is created so.
pub fn create_new_file(path: &Path) -> io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .custom_flags(rustix::fs::OFlags::NOFOLLOW.bits() as i32)
        .open(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn replaces_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out");
        {
            let staged = StagedDir::new(&target).unwrap();
            std::fs::write(staged.path().join("old.txt"), "old").unwrap();
            staged.commit().unwrap();
        }
        {
            let staged = StagedDir::new(&target).unwrap();
            std::fs::write(staged.path().join("new.txt"), "new").unwrap();
            // Dropped without commit: the old directory stays, the staging one goes.
        }
        assert_eq!(entries(&target), [MARKER, "old.txt"]);
        assert_eq!(entries(dir.path()), ["out"]);
        let staged = StagedDir::new(&target).unwrap();
        std::fs::write(staged.path().join("new.txt"), "new").unwrap();
        staged.commit().unwrap();
        assert_eq!(entries(&target), [MARKER, "new.txt"]);
        assert_eq!(entries(dir.path()), ["out"]);
    }

    /// Files and directories vito did not write are refused, and left as they were.
    #[test]
    fn refuses_what_vito_did_not_write() {
        let dir = tempfile::tempdir().unwrap();
        let notes = dir.path().join("notes.txt");
        std::fs::write(&notes, "mine").unwrap();
        let err = OutputTarget::check(&notes, &[]).unwrap_err();
        assert!(err.to_string().contains("is a file"), "{err}");

        let work = dir.path().join("work");
        std::fs::create_dir(&work).unwrap();
        std::fs::write(work.join("thesis.tex"), "mine").unwrap();
        let err = OutputTarget::check(&work, &[]).unwrap_err();
        assert!(err.to_string().contains("holds 1 entry"), "{err}");
        assert_eq!(entries(&work), ["thesis.tex"]);

        let link = dir.path().join("link");
        std::os::unix::fs::symlink(dir.path().join("nowhere"), &link).unwrap();
        let err = OutputTarget::check(&link, &[]).unwrap_err();
        assert!(err.to_string().contains("symbolic link"), "{err}");

        // Files that only look like vito's results (no marker) are not taken as vito's.
        let lookalike = dir.path().join("lookalike");
        std::fs::create_dir(&lookalike).unwrap();
        std::fs::write(
            lookalike.join("summary.json"),
            r#"{"vito_version": "0.1.0"}"#,
        )
        .unwrap();
        std::fs::write(lookalike.join("trajectory.csv"), "t\n").unwrap();
        let err = OutputTarget::check(&lookalike, &[]).unwrap_err();
        assert!(
            err.to_string().contains("`summary.json`, `trajectory.csv`"),
            "{err}"
        );

        // A marked directory: only the entries its marker lists are vito's.
        let marked = dir.path().join("marked");
        std::fs::create_dir(&marked).unwrap();
        std::fs::write(marked.join("summary.json"), "{}").unwrap();
        std::fs::write(
            marked.join(MARKER),
            format!("{MARKER_TEXT}\n{MANIFEST_PREFIX}summary.json\n{MANIFEST_END}\n"),
        )
        .unwrap();
        assert!(OutputTarget::check(&marked, &[]).is_ok());
        std::fs::write(marked.join("notes.md"), "mine").unwrap();
        let err = OutputTarget::check(&marked, &[]).unwrap_err();
        assert!(err.to_string().contains("(`notes.md`;"), "{err}");

        let empty = dir.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        assert!(OutputTarget::check(&empty, &[]).is_ok());
    }

    /// The directory holding an input, and its ancestors, are never targets.
    #[test]
    fn protects_the_inputs_directories() {
        let dir = tempfile::tempdir().unwrap();
        let b = dir.path().join("b");
        std::fs::create_dir(&b).unwrap();
        let problem = b.join("prob.toml");
        std::fs::write(&problem, "name = 'x'").unwrap();
        // Marked, so only the protection stops it.
        std::fs::write(b.join(MARKER), "").unwrap();
        for target in [b.clone(), dir.path().to_owned(), b.join("..").join("b")] {
            let err = OutputTarget::check(&target, &[&problem]).unwrap_err();
            assert!(matches!(err, OutputDirError::Protected { .. }), "{err}");
        }
        assert!(OutputTarget::check(&b.join("out"), &[&problem]).is_ok());
        for target in [".", "..", "/"] {
            let err = OutputTarget::check(Path::new(target), &[]).unwrap_err();
            assert!(matches!(err, OutputDirError::Invalid { .. }), "{err}");
        }
    }

    /// Below a file nothing can be created; an over-long name is refused.
    #[test]
    fn bad_parents_and_names_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("f");
        std::fs::write(&file, "").unwrap();
        let err = OutputTarget::check(&file.join("out"), &[]).unwrap_err();
        assert!(err.to_string().contains("is not a directory"), "{err}");
        let long = dir.path().join("x".repeat(250));
        let err = OutputTarget::check(&long, &[]).unwrap_err();
        assert!(err.to_string().contains("bytes long"), "{err}");
        let deep = dir.path().join("a/b/c");
        let staged = OutputTarget::check(&deep, &[]).unwrap().stage().unwrap();
        assert!(staged.commit().unwrap().is_dir());
    }

    /// A staging sibling left by a process that no longer exists is removed by the next
    /// run to the same target; one of a live process, or unmarked, stays.
    #[test]
    fn stale_staging_siblings_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out");
        let dead = dir.path().join(".out.tmp-4000000000-1");
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join(MARKER), "").unwrap();
        std::fs::write(dead.join("trajectory.csv"), "half").unwrap();
        let foreign = dir.path().join(".out.tmp-4000000001-1");
        std::fs::create_dir(&foreign).unwrap();
        std::fs::write(foreign.join("mine.txt"), "").unwrap();
        let live = dir
            .path()
            .join(format!(".out.tmp-{}-1", std::process::id()));
        std::fs::create_dir(&live).unwrap();
        let staged = OutputTarget::check(&target, &[]).unwrap().stage().unwrap();
        staged.commit().unwrap();
        assert!(!dead.exists());
        assert!(foreign.exists() && live.exists());
    }
}

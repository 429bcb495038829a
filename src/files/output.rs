//! Writing the files vito makes in a user's directory: atomically, through a temporary file
//! that is created exclusively and never through a link.
//!
//! The temporary file gets a random name beside the target (`.<name>.<random>.tmp`), created
//! with `O_CREAT | O_EXCL` (the `tempfile` crate), so a symbolic link or file planted under any
//! name is never opened, followed or overwritten; it is then renamed over the target. A target
//! that is itself a symbolic link is replaced by the file (the link's own target is never
//! written).

use std::io::{self, Write};
use std::os::unix::fs::PermissionsExt;
use std::path::Path;

/// Writes `contents` to `path` atomically: a reader sees the old file or the new one, never
/// half of it; nothing but `path` itself (and the exclusive temporary file) is touched.
/// The file's mode is 0666 less the process's umask, as for any newly created file.
pub fn write_atomic(path: &Path, contents: &[u8]) -> io::Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::new(io::ErrorKind::InvalidInput, "the path names no file"))?;
    let mut prefix = std::ffi::OsString::from(".");
    prefix.push(name);
    prefix.push(".");
    let mut tmp = tempfile::Builder::new()
        .prefix(&prefix)
        .suffix(".tmp")
        .permissions(std::fs::Permissions::from_mode(0o666))
        .tempfile_in(dir)?;
    tmp.write_all(contents)?;
    tmp.as_file().sync_all()?;
    tmp.persist(path).map(drop).map_err(|e| e.error)
}

/// Writes `path` atomically with `write`, which makes a file at the path it is given (for
/// writers that open a path themselves, as plotters does): that path lies in a fresh private
/// directory (mode 0700, created exclusively beside `path`), so no planted link can be there;
/// the file is then renamed over `path` and the directory removed. `write`'s error is
/// returned as it is, and so is an I/O error (the caller names `path`).
pub fn write_atomic_with<E: From<io::Error>>(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<(), E> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let private = tempfile::Builder::new()
        .prefix(".vito-write-")
        .tempdir_in(dir)?;
    let staged = private.path().join("file");
    write(&staged)?;
    Ok(std::fs::rename(&staged, path)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A link planted at the old predictable names and at the target itself: the link's
    /// target is never written; the target path becomes a regular file with the contents.
    #[test]
    fn writes_never_follow_a_planted_link() {
        let dir = tempfile::tempdir().unwrap();
        let victim = dir.path().join("victim.txt");
        std::fs::write(&victim, "precious").unwrap();
        let target = dir.path().join("page.html");
        for planted in [
            format!(".page.html.tmp-{}", std::process::id()),
            "page.svg.tmp".to_owned(),
        ] {
            std::os::unix::fs::symlink(&victim, dir.path().join(planted)).unwrap();
        }
        write_atomic(&target, b"new").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "new");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        let link = dir.path().join("link.html");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        write_atomic(&link, b"replaced").unwrap();
        assert!(!std::fs::symlink_metadata(&link).unwrap().is_symlink());
        assert_eq!(std::fs::read_to_string(&link).unwrap(), "replaced");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        let svg = dir.path().join("page.svg");
        write_atomic_with(&svg, |p| std::fs::write(p, "svg")).unwrap();
        assert_eq!(std::fs::read_to_string(&svg).unwrap(), "svg");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        // Nothing else is left behind: the victim, three links, three files.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 6);
    }
}

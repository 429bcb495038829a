//! Atomic output directories: write everything into a fresh sibling temp dir, then swap.
//!
//! The target is replaced only once the new directory is complete: the old one is renamed
//! aside, the new one renamed into place, and the old one removed. A crash or an error
//! before the swap leaves the target untouched (and at worst a `.<name>.tmp-*` sibling).

use std::io;
use std::path::{Path, PathBuf};

/// A directory being written, to become `target` on [`StagedDir::commit`].
#[derive(Debug)]
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
}

fn sibling(target: &Path, tag: &str) -> PathBuf {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let unique = format!(
        ".{name}.{tag}-{}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos())
    );
    target.with_file_name(unique)
}

impl StagedDir {
    /// Creates a fresh staging directory next to `target` (creating `target`'s parent).
    pub fn new(target: &Path) -> io::Result<StagedDir> {
        let target = if target.is_absolute() {
            target.to_owned()
        } else {
            std::env::current_dir()?.join(target)
        };
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent)?;
        }
        let staging = sibling(&target, "tmp");
        std::fs::create_dir(&staging)?;
        Ok(StagedDir {
            target,
            staging,
            committed: false,
        })
    }

    /// Where files are written until the commit.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The final directory.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Swaps the staged directory into place, replacing any existing target.
    pub fn commit(mut self) -> io::Result<PathBuf> {
        if self.target.exists() {
            let old = sibling(&self.target, "old");
            std::fs::rename(&self.target, &old)?;
            if let Err(e) = std::fs::rename(&self.staging, &self.target) {
                // Put the previous results back before reporting.
                let _ = std::fs::rename(&old, &self.target);
                return Err(e);
            }
            if old.is_dir() {
                std::fs::remove_dir_all(&old)?;
            } else {
                std::fs::remove_file(&old)?;
            }
        } else {
            std::fs::rename(&self.staging, &self.target)?;
        }
        self.committed = true;
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

/// Writes `contents` to `path` atomically (temp file in the same directory, then rename).
pub fn write_file_atomic(path: &Path, contents: &[u8]) -> io::Result<()> {
    let tmp = sibling(path, "tmp");
    std::fs::write(&tmp, contents)?;
    std::fs::rename(&tmp, path).inspect_err(|_| {
        let _ = std::fs::remove_file(&tmp);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("old.txt"), "old").unwrap();
        {
            let staged = StagedDir::new(&target).unwrap();
            std::fs::write(staged.path().join("new.txt"), "new").unwrap();
            // Dropped without commit: the old directory stays, the staging one goes.
        }
        assert!(target.join("old.txt").exists());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        let staged = StagedDir::new(&target).unwrap();
        std::fs::write(staged.path().join("new.txt"), "new").unwrap();
        staged.commit().unwrap();
        assert!(!target.join("old.txt").exists());
        assert_eq!(
            std::fs::read_to_string(target.join("new.txt")).unwrap(),
            "new"
        );
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}

//! Reading the files a user names (problem files, URDFs, warm starts, regression records):
//! regular files only, of bounded size. A FIFO or a device would block the read forever (or
//! never end), a directory gives a confusing error; each is an [`std::io::ErrorKind::InvalidInput`]
//! error saying what the path is, found from its metadata before anything is opened.

use std::io::{self, Read};
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::Path;

/// Largest problem file, warm start or regression record read (bytes).
pub const MAX_TEXT_BYTES: u64 = 16 << 20;

/// Largest URDF read (bytes).
pub const MAX_URDF_BYTES: u64 = 64 << 20;

/// Largest trajectory file `vito view` reads (bytes): a long simulation's CSV.
pub const MAX_TRAJECTORY_BYTES: u64 = 256 << 20;

/// What a non-regular file type is called in messages.
fn kind_name(file_type: std::fs::FileType) -> &'static str {
    if file_type.is_dir() {
        "a directory"
    } else if file_type.is_fifo() {
        "a FIFO (named pipe)"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

fn not_regular(file_type: std::fs::FileType) -> io::Error {
    io::Error::new(
        io::ErrorKind::InvalidInput,
        format!(
            "it is {}, not a regular file (vito reads only regular files)",
            kind_name(file_type)
        ),
    )
}

/// The regular file at `path` opened for reading, and its metadata. The type is checked from
/// the metadata before opening, and again on the open file (which is opened non-blocking, so
/// a FIFO swapped in between cannot block).
fn open_regular(path: &Path) -> io::Result<(std::fs::File, std::fs::Metadata)> {
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(not_regular(metadata.file_type()));
    }
    let file = std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(rustix::fs::OFlags::NONBLOCK.bits() as i32)
        .open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(not_regular(metadata.file_type()));
    }
    Ok((file, metadata))
}

/// The bytes of the regular file at `path` (symbolic links followed), at most `max_bytes`.
pub fn read_regular_file(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    let (file, metadata) = open_regular(path)?;
    let too_big = || {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "it is larger than {} MiB, the most vito reads",
                max_bytes >> 20
            ),
        )
    };
    if metadata.len() > max_bytes {
        return Err(too_big());
    }
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    file.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_big());
    }
    Ok(bytes)
}

/// Up to the first `max_bytes` of the regular file at `path` (symbolic links followed), with
/// the checks of [`read_regular_file`]: enough to recognise a file vito wrote.
pub fn read_regular_head(path: &Path, max_bytes: u64) -> io::Result<Vec<u8>> {
    let (file, _) = open_regular(path)?;
    let mut bytes = Vec::new();
    file.take(max_bytes).read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// [`read_regular_file`] as UTF-8 text.
pub fn read_regular_text(path: &Path, max_bytes: u64) -> io::Result<String> {
    String::from_utf8(read_regular_file(path, max_bytes)?)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidData, "it is not UTF-8 text"))
}

/// Largest duration or rate given on the command line (`--time-limit` in seconds,
/// `--duration` in time units, `--rate` in steps per time unit): 10⁹.
pub const MAX_SPAN: f64 = 1e9;

/// Checks a duration or rate given on the command line: a finite number in (0, [`MAX_SPAN`]];
/// the message names `option` and the range.
pub fn checked_span(option: &str, value: f64) -> Result<f64, String> {
    if value.is_finite() && value > 0.0 && value <= MAX_SPAN {
        Ok(value)
    } else {
        Err(format!(
            "{option} {value}: give a positive number up to {MAX_SPAN:e}"
        ))
    }
}

/// Checks a count given on the command line (`--starts`, `--jobs`) before anything is
/// allocated for it: 1 to `max`; the message says which bound it breaks.
pub fn checked_count(value: usize, max: usize) -> Result<usize, String> {
    if value == 0 {
        Err("give at least 1".into())
    } else if value > max {
        Err(format!("give at most {max}"))
    } else {
        Ok(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A directory, a FIFO and a device are refused by name without blocking; a file over
    /// the limit is refused; a regular file is read.
    #[test]
    fn only_regular_files_are_read() {
        let dir = tempfile::tempdir().unwrap();
        let err = read_regular_file(dir.path(), 100).unwrap_err();
        assert!(err.to_string().contains("a directory"), "{err}");
        let fifo = dir.path().join("fifo");
        rustix::fs::mknodat(
            rustix::fs::CWD,
            &fifo,
            rustix::fs::FileType::Fifo,
            rustix::fs::Mode::from_raw_mode(0o600),
            0,
        )
        .unwrap();
        let err = read_regular_file(&fifo, 100).unwrap_err();
        assert!(err.to_string().contains("FIFO"), "{err}");
        let err = read_regular_file(Path::new("/dev/zero"), 100).unwrap_err();
        assert!(err.to_string().contains("character device"), "{err}");
        let file = dir.path().join("f");
        std::fs::write(&file, "abc").unwrap();
        assert_eq!(read_regular_text(&file, 3).unwrap(), "abc");
        let err = read_regular_file(&file, 2).unwrap_err();
        assert!(err.to_string().contains("larger than"), "{err}");
    }
}

//! Files at the edges of the program: every input file is read through [`read_bounded`]
//! (regular files only, size capped, so `/dev/zero`, a FIFO or a directory get a clear error
//! instead of filling memory or blocking) and every output file is written through
//! [`write_atomic`] (a temporary name in the same folder, then a rename, so an interrupted run
//! never leaves a truncated file beside an older one).

use crate::error::{Error, Result};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// Largest scenario, vehicle or commands file (TOML), bytes (16 MiB).
pub const MAX_TOML_BYTES: u64 = 16 << 20;
/// Largest height-map PNG file, bytes (64 MiB).
pub const MAX_PNG_BYTES: u64 = 64 << 20;
/// Largest terrain mesh file (STL or OBJ), bytes (256 MiB).
pub const MAX_MESH_BYTES: u64 = 256 << 20;

fn io_error(path: &Path, message: String) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(message),
    }
}

/// What a path that is not a regular file is, for error messages.
fn kind_of(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        if let Some(k) = unix_kind(&t) {
            return k;
        }
    }
    "not a regular file"
}

/// FIFOs, devices and sockets by name (Unix).
#[cfg(unix)]
fn unix_kind(t: &std::fs::FileType) -> Option<&'static str> {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        Some("a FIFO (named pipe)")
    } else if t.is_char_device() || t.is_block_device() {
        Some("a device")
    } else if t.is_socket() {
        Some("a socket")
    } else {
        None
    }
}

/// Checks that `path` is a regular file (symbolic links followed) of at most `max_bytes`
/// without opening it (so a FIFO never blocks); the error says what it is instead.
pub fn check_regular(path: &Path, max_bytes: u64) -> Result<()> {
    let meta = std::fs::metadata(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if !meta.is_file() {
        return Err(io_error(
            path,
            format!(
                "is {}, not a regular file; give the path of a file",
                kind_of(&meta)
            ),
        ));
    }
    if meta.len() > max_bytes {
        return Err(io_error(
            path,
            format!(
                "is {} bytes, more than the limit of {max_bytes} bytes for this kind of file",
                meta.len()
            ),
        ));
    }
    Ok(())
}

/// Reads a regular file of at most `max_bytes` bytes (checked before opening, and again while
/// reading, in case it grows).
pub fn read_bounded(path: &Path, max_bytes: u64) -> Result<Vec<u8>> {
    check_regular(path, max_bytes)?;
    let file = std::fs::File::open(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let mut bytes = Vec::new();
    file.take(max_bytes + 1)
        .read_to_end(&mut bytes)
        .map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
    if bytes.len() as u64 > max_bytes {
        return Err(io_error(
            path,
            format!("grew past the limit of {max_bytes} bytes while being read"),
        ));
    }
    Ok(bytes)
}

/// Reads a UTF-8 text file of at most `max_bytes` bytes, as [`read_bounded`].
pub fn read_text_bounded(path: &Path, max_bytes: u64) -> Result<String> {
    String::from_utf8(read_bounded(path, max_bytes)?).map_err(|e| {
        io_error(
            path,
            format!(
                "is not UTF-8 text (invalid byte at offset {}); save it as UTF-8",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// The temporary name `write_atomic` writes `path` under first: same folder (so the rename
/// stays on one file system), same extension (writers that pick a format by it still work).
fn temporary_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".tmp-{}-{name}", std::process::id()))
}

/// Writes `path` atomically with a writer that needs a path of its own (an image encoder):
/// `write` gets the temporary path, which is renamed over `path` when it succeeds.
pub fn write_atomic_path(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let tmp = temporary_name(path);
    let r = write(&tmp).and_then(|()| {
        std::fs::rename(&tmp, path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })
    });
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

/// Writes `path` atomically: the bytes go to a temporary file in the same folder, which is
/// then renamed over `path`; a reader sees the old file or the whole new one, never a part.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// As [`write_atomic`], with the content produced by `fill` into a buffered writer.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let tmp = temporary_name(path);
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let result = (|| {
        let mut w = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_and_large_files_are_refused_with_what_they_are() {
        let dir = std::env::temp_dir().join(format!("tracksim-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let e = read_bounded(&dir, 100).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        let e = read_bounded(Path::new("/dev/zero"), 100)
            .unwrap_err()
            .to_string();
        assert!(e.contains("a device"), "{e}");
        let f = dir.join("big.toml");
        write_atomic(&f, &[b'#'; 101]).unwrap();
        let e = read_bounded(&f, 100).unwrap_err().to_string();
        assert!(e.contains("limit of 100 bytes"), "{e}");
        assert_eq!(read_bounded(&f, 101).unwrap().len(), 101);
        // No temporary file left beside the output.
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
        std::fs::remove_dir_all(&dir).ok();
    }
}

//! Files areo reads from its users — DEMs, labels, scenarios, rover and sweep files,
//! lists of instants: regular files only, each kind with a size limit, both checked
//! from the file's metadata before a byte is read. A FIFO would block forever, a
//! device like `/dev/zero` never ends, and a directory is not data; each is refused
//! with a message that says which it is.

use std::fs::File;
use std::io::{Error, ErrorKind, Read, Result};
use std::path::Path;

/// The largest text file read whole (scenarios, rover and sweep files, PDS3 labels,
/// lists of instants, grid maps): 64 MiB — a thousand times the largest shipped one.
pub const TEXT_LIMIT: u64 = 64 << 20;

/// The largest raster read (a DEM, an image a label points at): 1 TiB.
pub const RASTER_LIMIT: u64 = 1 << 40;

/// Checks that `path` is a regular file (symlinks followed) of at most `limit` bytes,
/// and returns its length.
pub fn check(path: &Path, limit: u64) -> Result<u64> {
    let meta = std::fs::metadata(path)?;
    let kind = meta.file_type();
    if !kind.is_file() {
        let what = if kind.is_dir() { "a directory" } else { special_kind(&meta) };
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{what}, not a regular file: areo reads regular files only"),
        ));
    }
    if meta.len() > limit {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{} bytes: larger than the {limit}-byte limit for a file of this kind", meta.len()),
        ));
    }
    Ok(meta.len())
}

#[cfg(unix)]
fn special_kind(meta: &std::fs::Metadata) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    let t = meta.file_type();
    if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special_kind(_: &std::fs::Metadata) -> &'static str {
    "a special file"
}

/// Whether `a` and `b` are the same file (device and inode, symlinks followed); false
/// if either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

/// Opens a checked file (see [`check`]).
pub fn open(path: &Path, limit: u64) -> Result<File> {
    check(path, limit)?;
    File::open(path)
}

/// Reads a checked file whole; never more than `limit` bytes, even if it grew.
pub fn read(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let len = check(path, limit)?;
    let mut bytes = Vec::with_capacity(len as usize);
    File::open(path)?.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(Error::new(ErrorKind::InvalidInput, format!("grew past the {limit}-byte limit while read")));
    }
    Ok(bytes)
}

/// Reads a checked text file whole (UTF-8).
pub fn read_text(path: &Path, limit: u64) -> Result<String> {
    String::from_utf8(read(path, limit)?)
        .map_err(|e| Error::new(ErrorKind::InvalidData, format!("not UTF-8 text: {e}")))
}

/// Reads at most `limit` bytes of text from a stream (standard input).
pub fn read_stream(stream: impl Read, limit: u64) -> Result<String> {
    let mut bytes = Vec::new();
    stream.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(Error::new(ErrorKind::InvalidInput, format!("more than {limit} bytes")));
    }
    String::from_utf8(bytes).map_err(|e| Error::new(ErrorKind::InvalidData, format!("not UTF-8 text: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_files_and_large_files_are_refused_before_reading() {
        let dir = std::env::temp_dir().join(format!("areo-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let small = dir.join("small.txt");
        std::fs::write(&small, "hello").unwrap();
        assert_eq!(read_text(&small, 5).unwrap(), "hello");
        let e = read_text(&small, 4).unwrap_err();
        assert!(e.to_string().contains("5 bytes: larger than the 4-byte limit"), "{e}");
        let e = check(&dir, TEXT_LIMIT).unwrap_err();
        assert!(e.to_string().starts_with("a directory, not a regular file"), "{e}");
        #[cfg(unix)]
        {
            let e = read(Path::new("/dev/zero"), TEXT_LIMIT).unwrap_err();
            assert!(e.to_string().starts_with("a character device"), "{e}");
            let fifo = dir.join("fifo");
            let _ = std::fs::remove_file(&fifo);
            // mkfifo from coreutils; a FIFO opened for reading would block forever.
            assert!(std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()));
            let e = read_text(&fifo, TEXT_LIMIT).unwrap_err();
            assert!(e.to_string().starts_with("a FIFO"), "{e}");
        }
        assert_eq!(read_stream(&b"12345"[..], 5).unwrap(), "12345");
        assert!(read_stream(&b"123456"[..], 5).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }
}

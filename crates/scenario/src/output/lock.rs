//! Advisory locks on output directories: commands that read and rewrite a directory's
//! shared files (`sweep expand`, `sweep collect`) take `DIR/.areo.lock` with `flock`,
//! so that racing calls run one after the other instead of mixing two expansions or
//! reading a file another is replacing. A call that finds the lock held says which
//! process holds it and waits. The lock goes with the process: a killed holder never
//! leaves it taken.

use std::fs::File;
use std::io::{Read, Seek, Write};
use std::path::Path;

use rustix::fs::{FlockOperation, flock};

use crate::error::{Error, Result};

/// A held lock; released when dropped (or when the process ends).
pub(crate) struct DirLock {
    _file: File,
}

/// Takes `dir`'s lock (creating `dir`), waiting while another process holds it.
pub(crate) fn lock_dir(dir: &Path) -> Result<DirLock> {
    let path = dir.join(".areo.lock");
    let io = |source| Error::Io { path: path.clone(), source };
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    let mut file =
        std::fs::OpenOptions::new().read(true).write(true).create(true).truncate(false).open(&path).map_err(io)?;
    if let Err(e) = flock(&file, FlockOperation::NonBlockingLockExclusive) {
        if e != rustix::io::Errno::WOULDBLOCK {
            return Err(io(e.into()));
        }
        let mut holder = String::new();
        let _ = file.read_to_string(&mut holder);
        tracing::warn!("{} is locked by {}: waiting for it", dir.display(), holder.trim());
        flock(&file, FlockOperation::LockExclusive).map_err(|e| io(e.into()))?;
    }
    // Say who holds it, for the next one to wait.
    let said =
        file.set_len(0).and_then(|()| file.rewind()).and_then(|()| writeln!(file, "process {}", std::process::id()));
    said.map_err(io)?;
    Ok(DirLock { _file: file })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_holder_waits_for_the_first() {
        let dir = std::env::temp_dir().join(format!("areo-lock-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let first = lock_dir(&dir).unwrap();
        let order = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let (d, o) = (dir.clone(), order.clone());
        // flock locks belong to open files: a second open in another thread waits too.
        let second = std::thread::spawn(move || {
            let _lock = lock_dir(&d).unwrap();
            o.lock().unwrap().push("second");
        });
        std::thread::sleep(std::time::Duration::from_millis(200));
        order.lock().unwrap().push("first done");
        drop(first);
        second.join().unwrap();
        assert_eq!(*order.lock().unwrap(), ["first done", "second"]);
        let _ = std::fs::remove_dir_all(&dir);
    }
}

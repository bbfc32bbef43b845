//! Staging: where outputs are written before they are put in place, and how they get
//! there whole.
//!
//! A staging name sits beside its target, hidden, and is this process's alone:
//! `.{target}.{kind}-{host}-{pid}-{n}` (the machine's name, letters and digits only;
//! `n` counts within the process), the target's part cut at a character boundary so
//! that the whole stays within [`NAME_MAX`] bytes, however long the target's name.
//! Writers of one target therefore never share a file, and a staging entry names the
//! process that made it, so the next writer of the target removes those whose process
//! is gone ([`clear_stale`]) — only entries of this user made on this machine (on a
//! shared file system another node's process ids mean nothing here), only by their
//! names (a link is removed, never followed).
//!
//! A finished directory replaces its target in one step where the kernel has
//! `renameat2(RENAME_EXCHANGE)` (Linux 3.15 on ext4, xfs, btrfs, tmpfs): the two swap
//! names atomically and the old set, now under the staging name, is removed. Elsewhere
//! (another OS, or a file system without it) the old set is first renamed aside to an
//! `old` staging name and the new one renamed in; a process killed between the two
//! leaves the target missing and the old set under its `old` name, which the next
//! writer of the target renames back before anything else.

use std::ffi::{OsStr, OsString};
use std::os::unix::ffi::{OsStrExt, OsStringExt};
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The longest file name, bytes (Linux's `NAME_MAX`, and that of the common file
/// systems elsewhere).
pub(crate) const NAME_MAX: usize = 255;

/// Staging names made by this process so far.
static MADE: AtomicU64 = AtomicU64::new(0);

/// This machine's name as staging names carry it: its letters and digits, at most 24.
pub(crate) fn host() -> &'static str {
    static HOST: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    HOST.get_or_init(|| {
        let uname = rustix::system::uname();
        let name: String =
            uname.nodename().to_string_lossy().chars().filter(char::is_ascii_alphanumeric).take(24).collect();
        if name.is_empty() { "host".into() } else { name }
    })
}

/// A staging name of `kind` (`partial`, `old`) beside `target`, this process's alone.
pub(crate) fn staging_path(target: &Path, kind: &str) -> PathBuf {
    let name = target.file_name().map_or_else(Vec::new, |n| n.as_bytes().to_vec());
    let tail = format!(".{kind}-{}-{}-{}", host(), std::process::id(), MADE.fetch_add(1, Ordering::Relaxed));
    let room = NAME_MAX - 1 - tail.len();
    let mut keep = name.len().min(room);
    // Cut at a character boundary when the name is UTF-8 (bytes otherwise).
    if let Ok(text) = std::str::from_utf8(&name) {
        while !text.is_char_boundary(keep) {
            keep -= 1;
        }
    }
    let mut staged = b".".to_vec();
    staged.extend_from_slice(&name[..keep]);
    staged.extend_from_slice(tail.as_bytes());
    target.with_file_name(OsString::from_vec(staged))
}

/// The machine and process id in `entry` if it is a staging name of `kind` for a
/// target named `target` (the name as [`staging_path`] cuts it).
fn staging_pid(entry: &OsStr, target: &OsStr, kind: &str) -> Option<(String, u32)> {
    let entry = entry.as_bytes();
    let rest = entry.strip_prefix(b".")?;
    let marker = format!(".{kind}-");
    let at = rest.windows(marker.len()).rposition(|w| w == marker.as_bytes())?;
    let (stem, tail) = (&rest[..at], &rest[at + marker.len()..]);
    if !target.as_bytes().starts_with(stem) || stem.is_empty() && !target.is_empty() {
        return None;
    }
    // A cut stem is only a cut of a name too long to fit.
    if stem.len() < target.len() && entry.len() < NAME_MAX - 4 {
        return None;
    }
    let mut parts = std::str::from_utf8(tail).ok()?.split('-');
    let (host, pid, n) = (parts.next()?, parts.next()?, parts.next()?);
    if parts.next().is_some() || host.is_empty() || !host.chars().all(|c| c.is_ascii_alphanumeric()) {
        return None;
    }
    n.parse::<u64>().ok()?;
    Some((host.to_string(), pid.parse().ok()?))
}

/// Whether process `pid` is running (or may be: one of another user's).
fn alive(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let Some(pid) = i32::try_from(pid).ok().and_then(rustix::process::Pid::from_raw) else { return false };
    match rustix::process::test_kill_process(pid) {
        Ok(()) => true,
        Err(e) => e == rustix::io::Errno::PERM,
    }
}

/// Removes the staging entries beside `target` that processes now gone left behind,
/// those of this user on this machine only; when `target` itself is missing, an `old` set of such a
/// process (killed between moving it aside and putting its new outputs in place) is
/// renamed back first. Best effort: what cannot be removed stays.
pub(crate) fn clear_stale(target: &Path) {
    let (Some(parent), Some(name)) = (target.parent(), target.file_name()) else { return };
    let parent = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
    let Ok(entries) = std::fs::read_dir(parent) else { return };
    let me = rustix::process::getuid().as_raw();
    let mut stale = Vec::new();
    for entry in entries.flatten() {
        let entry_name = entry.file_name();
        let kind = ["partial", "old"].into_iter().find(|k| staging_pid(&entry_name, name, k).is_some());
        let (Some(kind), Ok(meta)) = (kind, entry.path().symlink_metadata()) else { continue };
        let Some((made_on, pid)) = staging_pid(&entry_name, name, kind) else { continue };
        if meta.uid() == me && made_on == host() && !alive(pid) {
            stale.push((kind, entry.path(), meta.is_dir()));
        }
    }
    if target.symlink_metadata().is_err()
        && let Some((_, old, _)) = stale.iter().find(|(kind, _, dir)| *kind == "old" && *dir)
    {
        let _ = std::fs::rename(old, target);
    }
    for (_, path, dir) in stale {
        let _ = if dir { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
    }
}

/// Puts the finished directory `staging` in place of `dir`, the previous outputs (if
/// any) removed: atomically where the kernel can exchange two names, else by moving the
/// old set aside first (see the module's notes). Runs racing for `dir` each end with
/// their own set in place or an error; the last to finish stays.
pub(crate) fn put_in_place(staging: &Path, dir: &Path) -> std::io::Result<()> {
    for _ in 0..64 {
        match exchange(staging, dir) {
            // `staging` now holds the previous set.
            Ok(Swap::Exchanged) => return std::fs::remove_dir_all(staging),
            Ok(Swap::Placed) => return Ok(()),
            // Another run's outputs took the name in between: again.
            Ok(Swap::Raced) => {}
            Err(e) if unsupported(&e) => return move_aside_and_rename(staging, dir),
            Err(e) => return Err(e),
        }
    }
    Err(std::io::Error::other(format!("{} kept being replaced by other runs", dir.display())))
}

/// The fault tests' hook: with `AREO_PAUSE_BEFORE_PLACING` naming a file, a finished
/// run writes its staging directory's path there and waits up to a minute before
/// putting its outputs in place, for a test to kill it at that moment. Unset, nothing.
pub(crate) fn pause_for_tests(staging: &Path) {
    if let Some(flag) = std::env::var_os("AREO_PAUSE_BEFORE_PLACING")
        && std::fs::write(&flag, staging.as_os_str().as_bytes()).is_ok()
    {
        std::thread::sleep(std::time::Duration::from_secs(60));
    }
}

/// What [`exchange`] did.
enum Swap {
    /// `staging` and `dir` swapped names.
    Exchanged,
    /// `dir` did not exist: `staging` took its name.
    Placed,
    /// `dir` appeared or vanished between the two attempts.
    Raced,
}

#[cfg(target_os = "linux")]
fn exchange(staging: &Path, dir: &Path) -> std::io::Result<Swap> {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    let rename = |flags: RenameFlags| renameat_with(CWD, staging, CWD, dir, flags).map_err(std::io::Error::from);
    match rename(RenameFlags::EXCHANGE) {
        Ok(()) => Ok(Swap::Exchanged),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound && staging.exists() => {
            match rename(RenameFlags::NOREPLACE) {
                Ok(()) => Ok(Swap::Placed),
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(Swap::Raced),
                Err(e) => Err(e),
            }
        }
        Err(e) => Err(e),
    }
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &Path, _: &Path) -> std::io::Result<Swap> {
    Err(std::io::Error::from(std::io::ErrorKind::Unsupported))
}

/// Whether `e` says the kernel or the file system cannot exchange names.
fn unsupported(e: &std::io::Error) -> bool {
    e.kind() == std::io::ErrorKind::Unsupported
        || e.raw_os_error().is_some_and(|code| {
            [rustix::io::Errno::INVAL, rustix::io::Errno::NOSYS, rustix::io::Errno::NOTSUP]
                .iter()
                .any(|errno| errno.raw_os_error() == code)
        })
}

/// The fallback: the old set renamed aside, the new one renamed in, the old removed.
fn move_aside_and_rename(staging: &Path, dir: &Path) -> std::io::Result<()> {
    let mut last = None;
    for _ in 0..64 {
        let old = staging_path(dir, "old");
        match std::fs::rename(dir, &old) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
        let placed = std::fs::rename(staging, dir);
        if old.exists() {
            std::fs::remove_dir_all(&old)?;
        }
        match placed {
            Ok(()) => return Ok(()),
            Err(e) if dir.exists() => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("the output directory kept being replaced")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn staging_names_are_unique_fit_name_max_and_parse_back() {
        let long = "é".repeat(120) + "x"; // 241 bytes
        for target in ["valley-detour", long.as_str()] {
            let path = Path::new("/tmp/out").join(target);
            let (a, b) = (staging_path(&path, "partial"), staging_path(&path, "partial"));
            assert_ne!(a, b);
            let name = a.file_name().unwrap();
            assert!(name.len() <= NAME_MAX, "{} bytes", name.len());
            assert!(std::str::from_utf8(name.as_bytes()).is_ok(), "cut inside a character");
            assert_eq!(
                staging_pid(name, OsStr::new(target), "partial"),
                Some((host().to_string(), std::process::id()))
            );
            assert_eq!(staging_pid(name, OsStr::new(target), "old"), None);
        }
        // Another target's staging is not this one's, even when one name starts the other.
        let other = staging_path(Path::new("/tmp/out/valley"), "partial");
        assert_eq!(staging_pid(other.file_name().unwrap(), OsStr::new("valley-detour"), "partial"), None);
        let mine = staging_path(Path::new("/tmp/out/valley-detour"), "partial");
        assert_eq!(staging_pid(mine.file_name().unwrap(), OsStr::new("valley"), "partial"), None);
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("areo-staging-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn set(dir: &Path, contents: &str) {
        std::fs::create_dir_all(dir).unwrap();
        std::fs::write(dir.join("facts.json"), contents).unwrap();
    }

    #[test]
    fn a_finished_set_replaces_the_previous_one_whole() {
        let root = scratch("swap");
        let target = root.join("run");
        // No previous set: the new one takes the name.
        let first = staging_path(&target, "partial");
        set(&first, "1");
        put_in_place(&first, &target).unwrap();
        assert_eq!(std::fs::read_to_string(target.join("facts.json")).unwrap(), "1");
        // A previous set: replaced, and nothing of it left anywhere.
        let second = staging_path(&target, "partial");
        set(&second, "2");
        std::fs::write(target.join("stale.csv"), "old").unwrap();
        put_in_place(&second, &target).unwrap();
        assert_eq!(std::fs::read_to_string(target.join("facts.json")).unwrap(), "2");
        assert!(!target.join("stale.csv").exists());
        let names: Vec<_> = std::fs::read_dir(&root).unwrap().flatten().map(|e| e.file_name()).collect();
        assert_eq!(names, [OsString::from("run")]);
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn leftovers_of_processes_gone_are_cleared_and_an_old_set_restored() {
        let root = scratch("stale");
        let target = root.join("run");
        // Killed between moving its old set aside and renaming the new one in: the
        // target is missing, the old set under an `old` name, the new under `partial`.
        let (dead, here) = (4_194_305, host()); // above any Linux pid_max
        set(&root.join(format!(".run.old-{here}-{dead}-3")), "old");
        set(&root.join(format!(".run.partial-{here}-{dead}-2")), "new, unfinished");
        // This process's own staging, another target's and another machine's stay.
        let mine = staging_path(&target, "partial");
        set(&mine, "mine");
        set(&root.join(format!(".runs.partial-{here}-{dead}-0")), "another target's");
        set(&root.join(format!(".run.partial-{here}x-{dead}-0")), "another machine's");
        clear_stale(&target);
        assert_eq!(std::fs::read_to_string(target.join("facts.json")).unwrap(), "old");
        let mut names: Vec<String> =
            std::fs::read_dir(&root).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
        names.sort();
        let mine = mine.file_name().unwrap().to_string_lossy().into_owned();
        let mut want = vec![
            format!(".runs.partial-{here}-{dead}-0"),
            format!(".run.partial-{here}x-{dead}-0"),
            mine,
            "run".to_string(),
        ];
        want.sort();
        assert_eq!(names, want);
        let _ = std::fs::remove_dir_all(&root);
    }
}

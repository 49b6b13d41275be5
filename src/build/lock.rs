//! One build per folder at a time: an advisory lock (`flock`) on the folder itself, so
//! that nothing is added to the folder and a killed build's lock goes with its process.

use anyhow::{bail, Context, Result};
use std::fs::{File, TryLockError};
use std::path::Path;

/// A held lock on a folder; released when dropped (or when the process ends).
pub struct Lock(#[allow(dead_code)] File);

impl Lock {
    /// Lock `dir` shared (created when missing): any number of shared holders at once
    /// (the stage commands of different experiments), none beside an exclusive one (a
    /// build). Waits, saying so, or with `wait` false refuses.
    pub fn acquire_shared(dir: &Path, wait: bool) -> Result<Self> {
        Self::take(dir, wait, true)
    }

    /// Lock `dir` (created when missing). When another build holds it: wait, saying so
    /// on standard error, or with `wait` false refuse.
    pub fn acquire(dir: &Path, wait: bool) -> Result<Self> {
        Self::take(dir, wait, false)
    }

    fn take(dir: &Path, wait: bool, shared: bool) -> Result<Self> {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("{}: cannot create folder", dir.display()))?;
        let f = File::open(dir).with_context(|| format!("{}: cannot open", dir.display()))?;
        let tried = if shared {
            f.try_lock_shared()
        } else {
            f.try_lock()
        };
        match tried {
            Ok(()) => return Ok(Self(f)),
            Err(TryLockError::WouldBlock) => {}
            Err(TryLockError::Error(e)) => {
                return Err(e).with_context(|| format!("{}: cannot lock", dir.display()))
            }
        }
        // A shared holder waits only for a build; an exclusive one for anyone else.
        let who = if shared { "a" } else { "another" };
        if !wait {
            bail!(
                "{}: {who} rollfric build is using this folder (--no-wait given)",
                dir.display()
            );
        }
        eprintln!(
            "{}: {who} rollfric build is using this folder; waiting for it to finish",
            dir.display()
        );
        if shared { f.lock_shared() } else { f.lock() }
            .with_context(|| format!("{}: cannot lock", dir.display()))?;
        Ok(Self(f))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_the_folder_waits_or_refuses() {
        let d = tempfile::tempdir().unwrap();
        let first = Lock::acquire(d.path(), false).unwrap();
        let e = Lock::acquire(d.path(), false).err().expect("held");
        assert!(format!("{e:#}").contains("another rollfric build"), "{e:#}");
        let dir = d.path().to_path_buf();
        let waiter = std::thread::spawn(move || Lock::acquire(&dir, true).map(|_| ()));
        std::thread::sleep(std::time::Duration::from_millis(200));
        assert!(!waiter.is_finished(), "waits while the first holds it");
        drop(first);
        waiter.join().unwrap().unwrap();
    }

    #[test]
    fn shared_locks_coexist_and_exclude_an_exclusive_one() {
        let d = tempfile::tempdir().unwrap();
        let a = Lock::acquire_shared(d.path(), false).unwrap();
        let b = Lock::acquire_shared(d.path(), false).unwrap();
        assert!(
            Lock::acquire(d.path(), false).is_err(),
            "a build waits for stages"
        );
        drop((a, b));
        let build = Lock::acquire(d.path(), false).unwrap();
        let e = Lock::acquire_shared(d.path(), false).err().expect("held");
        assert!(format!("{e:#}").contains("a rollfric build"), "{e:#}");
        drop(build);
        Lock::acquire_shared(d.path(), false).unwrap();
    }
}

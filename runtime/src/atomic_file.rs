//! Files replaced atomically: a write goes to a temporary file in the same directory, is synced,
//! renamed over the target and the directory is synced, so a reader (even after `kill -9` or a
//! power loss) sees either the old complete file or the new one, never a mix.
//!
//! Used for every file ncplc replaces: the retain record, a golden trace rewritten by
//! `ncplc replay --update`, the output of `ncplc trace pack`, a PLC source `ncplc fmt` formats.

use std::fs::File;
use std::io;
use std::path::Path;

/// Replaces `path` with `bytes` atomically (see the module doc).
pub fn write(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_with(path, |tmp| std::fs::write(tmp, bytes))
}

/// Replaces `path` atomically with what `fill` writes to the temporary file it is given (for a
/// writer that takes a path, as plotters' PNG back end does); nothing is replaced when `fill`
/// fails, and the temporary file is removed.
pub fn write_with(path: &Path, fill: impl FnOnce(&Path) -> io::Result<()>) -> io::Result<()> {
    let pending = Pending::create(path)?;
    fill(pending.path())?;
    pending.commit()
}

/// A replacement of a file being written: its temporary file, which [`Pending::commit`] syncs
/// and renames over the target; dropped without a commit, the temporary file is removed and the
/// target is untouched (for a writer that streams, as `ncplc replay --update` does).
#[derive(Debug)]
pub struct Pending {
    tmp: tempfile::NamedTempFile,
    target: std::path::PathBuf,
}

impl Pending {
    /// Creates the temporary file that will replace `path` (in the same directory, with the same
    /// extension: a writer may choose its format by it).
    pub fn create(path: &Path) -> io::Result<Pending> {
        let dir = parent_dir(path);
        let mut builder = tempfile::Builder::new();
        let suffix = path.extension().map_or_else(
            || ".tmp".to_string(),
            |e| format!(".{}", e.to_string_lossy()),
        );
        builder.prefix(".ncplc-").suffix(&suffix);
        // The usual mode of a new file (0666 less the umask: 0644 typically), not tempfile's 0600.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o666));
        }
        Ok(Pending {
            tmp: builder.tempfile_in(dir)?,
            target: path.to_path_buf(),
        })
    }

    /// The temporary file's path.
    pub fn path(&self) -> &Path {
        self.tmp.path()
    }

    /// The temporary file, to write to.
    pub fn file(&mut self) -> &mut File {
        self.tmp.as_file_mut()
    }

    /// Syncs the temporary file and renames it over the target, then syncs the directory.
    pub fn commit(self) -> io::Result<()> {
        File::open(self.tmp.path())?.sync_all()?;
        let dir = parent_dir(&self.target).to_path_buf();
        self.tmp.persist(&self.target).map_err(|e| e.error)?;
        // Make the rename itself durable; a directory that cannot be opened for syncing (some
        // file systems) still has the complete new file.
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

/// The directory `path` is in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_the_file_and_leaves_no_temporary_behind() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("golden.jsonl");
        std::fs::write(&path, b"old contents").expect("seed");
        write(&path, b"new").expect("write");
        assert_eq!(std::fs::read(&path).expect("read"), b"new");
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("golden.jsonl")]);
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_gets_0666_less_the_umask() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("retain.bin");
        // SAFETY: umask only sets the process's file-creation mask; read it back by setting it.
        let umask = unsafe { libc::umask(0o022) };
        // SAFETY: as above; restores the mask.
        unsafe { libc::umask(umask) };
        write(&path, b"x").expect("write");
        let mode = std::fs::metadata(&path).expect("meta").permissions().mode() & 0o777;
        assert_eq!(mode, 0o666 & !umask);
    }

    #[test]
    fn a_missing_directory_is_an_error_and_writes_nothing() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("no/such/dir/file");
        let e = write(&path, b"x").expect_err("no directory");
        assert_eq!(e.kind(), io::ErrorKind::NotFound);
        assert!(!path.exists());
    }
}

//! Files written whole or not at all: a temporary file beside the target, renamed over it
//! only when complete. A target that already exists and is not a file (`/dev/null`, a FIFO, a
//! terminal) is written straight into: a rename would put a file in its place.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// A file being written. Nothing appears at the target path until [`AtomicFile::commit`];
/// dropping it uncommitted (an error, a panic, Ctrl-C handled by unwinding) removes the
/// temporary file.
pub struct AtomicFile {
    target: PathBuf,
    /// The temporary file renamed over the target (`None`: the target is a device or a
    /// FIFO, written straight into).
    temp: Option<PathBuf>,
    writer: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Starts writing `target` (through a hidden temporary file in the same directory, so
    /// the final rename never crosses file systems; straight into a target that exists and is
    /// neither a file nor a directory).
    pub fn create(target: &Path) -> Result<Self> {
        let io = |source| Error::Io {
            path: target.to_path_buf(),
            source,
        };
        let name = (target.file_name())
            .ok_or_else(|| io(std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name")))?;
        let special = std::fs::metadata(target).is_ok_and(|m| !m.is_file() && !m.is_dir());
        let (temp, file) = if special {
            (None, std::fs::OpenOptions::new().write(true).open(target).map_err(io)?)
        } else {
            let temp = target.with_file_name(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
            let file = File::create(&temp).map_err(io)?;
            (Some(temp), file)
        };
        Ok(Self {
            target: target.to_path_buf(),
            temp,
            writer: Some(BufWriter::new(file)),
        })
    }

    /// The writer to fill.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("not yet committed")
    }

    /// An I/O error on this file, as the library's error.
    pub fn error(&self, source: std::io::Error) -> Error {
        Error::Io {
            path: self.target.clone(),
            source,
        }
    }

    /// Flushes the file and renames it into place.
    ///
    /// No `fsync`: the rename alone makes the file whole or absent whatever happens to the
    /// process (an error, a panic, Ctrl-C, a kill). Only an operating-system crash or a power
    /// cut right after the run could leave it empty, and a run's outputs are made again by
    /// running it; a flush to disk took about 0.6 ms per file here (a whole 8 s wave takes 32 ms).
    pub fn commit(mut self) -> Result<()> {
        let writer = self.writer.take().expect("committed once");
        let file = writer.into_inner().map_err(|e| Error::Io {
            path: self.target.clone(),
            source: e.into_error(),
        })?;
        drop(file);
        match &self.temp {
            Some(temp) => std::fs::rename(temp, &self.target).map_err(|e| self.error(e)),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some()
            && let Some(temp) = &self.temp
        {
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Writes `bytes` to `target` atomically.
pub fn write_atomically(target: &Path, bytes: &[u8]) -> Result<()> {
    let mut file = AtomicFile::create(target)?;
    file.writer().write_all(bytes).map_err(|e| file.error(e))?;
    file.commit()
}

/// Checks, before a run, that `path` can be written later: it names a file and its directory
/// exists. `option` names the command-line option in the error.
pub fn check_output_path(path: &Path, option: &str) -> Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if path.file_name().is_none() {
        return Err(Error::argument(option, format!("{}: not a file name", path.display())));
    }
    if !dir.is_dir() {
        return Err(Error::argument(
            option,
            format!("{}: directory {} does not exist", path.display(), dir.display()),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A FIFO as the target (as `/dev/null` is a device): the bytes go through it, and it is
    /// still a FIFO afterwards, not a file renamed over it.
    #[test]
    fn a_fifo_is_written_into_not_replaced() {
        use std::os::unix::fs::FileTypeExt;
        let dir = std::env::temp_dir().join(format!("faze4-atomic-fifo-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("out.csv");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        // read and write: on Linux opening a FIFO so does not wait for a writer
        let mut reader = std::fs::OpenOptions::new().read(true).write(true).open(&fifo).unwrap();
        let bytes = b"t,q1\n0,0.5\n";
        write_atomically(&fifo, bytes).unwrap();
        assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        let mut got = [0; 11];
        std::io::Read::read_exact(&mut reader, &mut got).unwrap();
        assert_eq!(&got, bytes);
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn output_paths_are_checked_before_the_run() {
        assert!(check_output_path(Path::new("/nonexistent-faze4/x.svg"), "--plot").is_err());
        assert!(check_output_path(Path::new("x.html"), "--html").is_ok());
        assert!(check_output_path(&std::env::temp_dir().join("x.html"), "--html").is_ok());
    }

    #[test]
    fn nothing_appears_until_commit_and_an_abandoned_file_leaves_nothing() {
        let dir = std::env::temp_dir().join(format!("faze4-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("out.txt");
        let mut f = AtomicFile::create(&target).unwrap();
        f.writer().write_all(b"half").unwrap();
        assert!(!target.exists());
        drop(f);
        assert!(!target.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "temporary file removed");
        write_atomically(&target, b"whole").unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"whole");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! Files written whole or not at all, and the outputs of a run written all or none.
//!
//! Every output goes through an [`Outputs`] set: each file is written to a hidden temporary
//! beside its target, and [`Outputs::commit`] renames them all into place only once every one
//! is complete. An error (or a panic) before then removes every temporary, so no existing file
//! changes. A target that is a symbolic link is written through (the file it names is
//! replaced, the link stays). A target that exists and is neither a file nor a directory
//! (`/dev/null`, a FIFO, a terminal) is written straight into: a rename would put a file in
//! its place.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};

use crate::error::{Error, Result};

/// The files of one run or one sweep, committed together.
///
/// A clone is a handle to the same set (a sweep's threads stage their trails into it). The
/// temporaries left when the last handle is dropped uncommitted are removed.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    inner: Arc<Mutex<Staged>>,
    /// Each file is renamed into place as soon as it is complete (a file on its own).
    immediate: bool,
}

/// What an [`Outputs`] set holds.
#[derive(Debug, Default)]
struct Staged {
    /// The targets claimed so far (resolved through links), with the option that names each
    /// and the path as given (devices and FIFOs too, which may be claimed twice).
    claimed: Vec<(PathBuf, String, PathBuf)>,
    /// Complete temporaries waiting for the commit: (temporary, resolved target).
    files: Vec<(PathBuf, PathBuf)>,
    /// The files the run reads, which no output may replace.
    inputs: Inputs,
}

impl Drop for Staged {
    fn drop(&mut self) {
        for (temp, _) in &self.files {
            let _ = std::fs::remove_file(temp);
        }
    }
}

impl Outputs {
    /// An empty set: nothing appears until [`Outputs::commit`].
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// A set whose files each appear as soon as they are complete (one output on its own).
    pub fn immediate() -> Outputs {
        Outputs {
            immediate: true,
            ..Outputs::default()
        }
    }

    /// Makes this set refuse any output that is one of `inputs` ([`Inputs::check`]): the
    /// outputs claimed so far at once, those claimed later in [`Outputs::claim`], and every file
    /// again when it is created.
    pub fn reading(&self, inputs: Inputs) -> Result<()> {
        let mut staged = self.staged();
        for (_, option, given) in &staged.claimed {
            inputs.check(given, option)?;
        }
        staged.inputs = inputs;
        Ok(())
    }

    fn staged(&self) -> MutexGuard<'_, Staged> {
        // a thread that panicked while staging left the list whole (pushes only)
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Checks, before a run, that `path` can be written later (see [`check_output_path`]), that
    /// it is none of the run's inputs ([`Outputs::reading`]) and that no other output of the set
    /// names the same file (links resolved). `option` names the command-line option in the
    /// error. A device or a FIFO may be named by several options.
    pub fn claim(&self, path: &Path, option: &str) -> Result<()> {
        check_output_path(path, option)?;
        self.staged().inputs.check(path, option)?;
        let target = resolve(path).map_err(|source| Error::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut staged = self.staged();
        if let Some((_, other, _)) = (staged.claimed.iter()).find(|(t, _, _)| *t == target && !is_special(&target)) {
            return Err(Error::argument(
                option,
                format!(
                    "{}: the same file as the {other} output; give each output its own file",
                    path.display()
                ),
            ));
        }
        staged.claimed.push((target, option.to_string(), path.to_path_buf()));
        Ok(())
    }

    /// The option that claimed `resolved`, if any.
    fn option_of(&self, resolved: &Path) -> Option<String> {
        let staged = self.staged();
        staged
            .claimed
            .iter()
            .find(|(t, _, _)| t == resolved)
            .map(|(_, o, _)| o.clone())
    }

    /// Starts writing `target` as a file of this set.
    pub fn create(&self, target: &Path) -> Result<AtomicFile> {
        AtomicFile::within(self, target)
    }

    /// Writes `bytes` to `target` as a file of this set.
    pub fn write(&self, target: &Path, bytes: &[u8]) -> Result<()> {
        let mut file = self.create(target)?;
        file.writer().write_all(bytes).map_err(|e| file.error(e))?;
        file.commit()
    }

    /// Takes `target` back out of the set, its temporary removed: a file made whole that is
    /// not to be written after all (the trail of a sweep's run that a stop ended early).
    pub fn withdraw(&self, target: &Path) {
        let Ok(resolved) = resolve(target) else {
            return;
        };
        self.staged().files.retain(|(temp, staged)| {
            let keep = *staged != resolved;
            if !keep {
                let _ = std::fs::remove_file(temp);
            }
            keep
        });
    }

    /// A complete temporary waiting for the commit.
    fn stage(&self, temp: PathBuf, target: PathBuf) -> Result<()> {
        let mut staged = self.staged();
        if staged.files.iter().any(|(_, t)| *t == target) {
            let _ = std::fs::remove_file(&temp);
            return Err(Error::Io {
                path: target,
                source: std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "written twice by one run: give each output its own file",
                ),
            });
        }
        staged.files.push((temp, target));
        drop(staged);
        match self.immediate {
            true => self.commit(),
            false => Ok(()),
        }
    }

    /// Renames every complete file into place. If a rename fails, the files already renamed
    /// are put back as they were (the old file, or none), the other temporaries are removed,
    /// and the error is returned: the set is committed whole or not at all.
    ///
    /// No `fsync`: the renames alone make each file whole or absent whatever happens to the
    /// process (an error, a panic, a signal, a kill). Only an operating-system crash or a power
    /// cut right after the run could leave one empty, and a run's outputs are made again by
    /// running it; a flush to disk took about 0.6 ms per file here (a whole 8 s wave takes 32 ms).
    pub fn commit(&self) -> Result<()> {
        let files = std::mem::take(&mut self.staged().files);
        // a hard link keeps each old file until every rename has succeeded
        let backups: Vec<Option<PathBuf>> = files
            .iter()
            .map(|(_, target)| {
                let backup = hidden_beside(target, "bak");
                let linked = target.is_file() && std::fs::hard_link(target, &backup).is_ok();
                linked.then_some(backup)
            })
            .collect();
        let mut result = Ok(());
        for (k, (temp, target)) in files.iter().enumerate() {
            if let Err(source) = std::fs::rename(temp, target) {
                for ((_, target), backup) in files[..k].iter().zip(&backups) {
                    let _ = match backup {
                        Some(b) => std::fs::rename(b, target),
                        None => std::fs::remove_file(target),
                    };
                }
                for (temp, _) in &files[k..] {
                    let _ = std::fs::remove_file(temp);
                }
                result = Err(Error::Io {
                    path: target.clone(),
                    source,
                });
                break;
            }
        }
        for backup in backups.iter().flatten() {
            let _ = std::fs::remove_file(backup);
        }
        result
    }
}

/// The longest file name most file systems take (Linux's `NAME_MAX`, in bytes).
const NAME_MAX: usize = 255;

/// `.NAME.PID.EXT` beside `target`. A name too long for that (a valid 255-byte name) keeps as
/// much of itself as fits, then `~` and a hash of the whole name, so that the temporary's name
/// stays within [`NAME_MAX`] and two long names still get two temporaries.
fn hidden_beside(target: &Path, ext: &str) -> PathBuf {
    use std::hash::{Hash, Hasher};
    use std::os::unix::ffi::OsStringExt;
    let name = target.file_name().unwrap_or("out".as_ref()).as_encoded_bytes();
    let suffix = format!(".{}.{ext}", std::process::id());
    let mut hidden = vec![b'.'];
    if 1 + name.len() + suffix.len() <= NAME_MAX {
        hidden.extend_from_slice(name);
    } else {
        let mut hasher = std::hash::DefaultHasher::new();
        name.hash(&mut hasher);
        let tag = format!("~{:016x}", hasher.finish());
        hidden.extend_from_slice(&name[..NAME_MAX - 1 - suffix.len() - tag.len()]);
        hidden.extend_from_slice(tag.as_bytes());
    }
    hidden.extend_from_slice(suffix.as_bytes());
    target.with_file_name(std::ffi::OsString::from_vec(hidden))
}

/// Whether `path` exists and is neither a file nor a directory (a device, a FIFO, a socket).
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// The file `path` names: its symbolic links followed (a dangling one to the file it would
/// create) and its directory made canonical, so that two spellings of one file compare equal.
fn resolve(path: &Path) -> std::io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    // as the kernel does, give up after 40 links
    for _ in 0..40 {
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let next = parent(&path).join(std::fs::read_link(&path)?);
                // a link the kernel follows to what no path names is kept as it is:
                // `/dev/stdout` on a pipe or a socket (`/proc/self/fd/1` → `pipe:[…]`)
                if std::fs::symlink_metadata(&next).is_err() && std::fs::metadata(&path).is_ok() {
                    break;
                }
                path = next;
            }
            _ => break,
        }
    }
    let name = path
        .file_name()
        .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"))?
        .to_os_string();
    Ok(std::fs::canonicalize(parent(&path))?.join(name))
}

/// The directory of `path` (`.` for a bare name).
fn parent(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// A file being written. Nothing appears at the target path until [`AtomicFile::commit`]
/// (and, in an [`Outputs`] set, until the set's commit); dropping it uncommitted (an error, a
/// panic) removes the temporary file.
pub struct AtomicFile {
    /// The path as given, for messages.
    target: PathBuf,
    /// The file it names, links followed.
    resolved: PathBuf,
    /// The temporary file renamed over the target (`None`: the target is a device or a
    /// FIFO, written straight into).
    temp: Option<PathBuf>,
    writer: Option<BufWriter<File>>,
    outputs: Outputs,
    /// The option that claimed the target, which its errors name.
    option: Option<String>,
}

impl AtomicFile {
    /// Starts writing `target` on its own (it appears when committed): through a hidden
    /// temporary file in the same directory, so the final rename never crosses file systems;
    /// straight into a target that exists and is neither a file nor a directory.
    pub fn create(target: &Path) -> Result<Self> {
        Self::within(&Outputs::immediate(), target)
    }

    fn within(outputs: &Outputs, target: &Path) -> Result<Self> {
        let option = resolve(target).ok().and_then(|r| outputs.option_of(&r));
        let io = |source| io_error(option.as_deref(), target, source);
        if ends_in_slash(target) {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "ends in '/': not a file name",
            )));
        }
        let resolved = resolve(target).map_err(io)?;
        (outputs.staged().inputs).check(target, option.as_deref().unwrap_or("output"))?;
        let (temp, file) = if is_special(&resolved) {
            (
                None,
                std::fs::OpenOptions::new().write(true).open(&resolved).map_err(io)?,
            )
        } else {
            if resolved.is_dir() {
                return Err(io(std::io::Error::new(
                    std::io::ErrorKind::IsADirectory,
                    "is a directory",
                )));
            }
            let temp = hidden_beside(&resolved, "tmp");
            let file = File::create(&temp).map_err(io)?;
            // a file replaced keeps its permissions (600 stays 600)
            if let Ok(old) = std::fs::metadata(&resolved) {
                let _ = file.set_permissions(old.permissions());
            }
            (Some(temp), file)
        };
        Ok(Self {
            target: target.to_path_buf(),
            resolved,
            temp,
            writer: Some(BufWriter::new(file)),
            outputs: outputs.clone(),
            option,
        })
    }

    /// The writer to fill.
    pub fn writer(&mut self) -> &mut BufWriter<File> {
        self.writer.as_mut().expect("not yet committed")
    }

    /// An I/O error on this file, as the library's error (naming the option that claimed it).
    pub fn error(&self, source: std::io::Error) -> Error {
        io_error(self.option.as_deref(), &self.target, source)
    }

    /// Flushes the file and hands it to its set, which renames it into place (at once for a
    /// file on its own, at the set's commit otherwise).
    pub fn commit(mut self) -> Result<()> {
        let writer = self.writer.take().expect("committed once");
        let flushed = writer.into_inner().map_err(|e| e.into_error());
        let temp = self.temp.take();
        let file = match flushed {
            Ok(file) => file,
            Err(e) => {
                if let Some(temp) = &temp {
                    let _ = std::fs::remove_file(temp);
                }
                return Err(self.error(e));
            }
        };
        drop(file);
        match temp {
            Some(temp) => self.outputs.stage(temp, self.resolved.clone()),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if let Some(temp) = &self.temp {
            self.writer.take();
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// The files a run reads (the URDF, its meshes, the trajectory, the motors file, the parts of a
/// merge and their metadata), so that no output replaces one: an output that is the same file
/// as an input (the same device and inode, so through any link, hard link or spelling) is
/// refused before anything is written. Only regular files are kept (`/dev/stdin` may read
/// what `/dev/stdout` writes to).
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    /// (path as given, what reads it, device and inode)
    files: Vec<(PathBuf, String, (u64, u64))>,
}

impl Inputs {
    /// No inputs.
    pub fn new() -> Inputs {
        Inputs::default()
    }

    /// Adds the file at `path`, read as `role` (the field that names it between backticks,
    /// `` `urdf` ``, or what it is, `the mesh of link 'base'`). A path that is not an existing regular file is skipped.
    pub fn add(&mut self, path: &Path, role: impl Into<String>) {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = std::fs::metadata(path)
            && m.is_file()
        {
            self.files.push((path.to_path_buf(), role.into(), (m.dev(), m.ino())));
        }
    }

    /// [`Inputs::add`], by value.
    pub fn with(mut self, path: &Path, role: impl Into<String>) -> Inputs {
        self.add(path, role);
        self
    }

    /// Refuses `output`, named by `option`, if it is one of these inputs.
    pub fn check(&self, output: &Path, option: &str) -> Result<()> {
        use std::os::unix::fs::MetadataExt;
        let Ok(m) = std::fs::metadata(output) else {
            return Ok(()); // not there yet: no input
        };
        match self.files.iter().find(|(_, _, id)| *id == (m.dev(), m.ino())) {
            Some((path, role, _)) => Err(Error::argument(
                option,
                format!(
                    "{} is {}{}: an output never replaces an input of its run; name another file",
                    output.display(),
                    match role.starts_with('`') {
                        true => format!("the {role} input"),
                        false => role.clone(),
                    },
                    match path == output {
                        true => String::new(),
                        false => format!(" ({})", path.display()),
                    }
                ),
            )),
            None => Ok(()),
        }
    }
}

/// An I/O error on `path`: the option's error when an option claimed it, else the file's.
fn io_error(option: Option<&str>, path: &Path, source: std::io::Error) -> Error {
    match option {
        Some(option) => Error::Output {
            option: option.to_string(),
            path: path.to_path_buf(),
            source,
        },
        None => Error::Io {
            path: path.to_path_buf(),
            source,
        },
    }
}

/// Whether `path` is written with a trailing `/` (a directory's spelling).
fn ends_in_slash(path: &Path) -> bool {
    path.as_os_str().as_encoded_bytes().last() == Some(&b'/')
}

/// Writes `bytes` to `target` atomically (on its own).
pub fn write_atomically(target: &Path, bytes: &[u8]) -> Result<()> {
    Outputs::immediate().write(target, bytes)
}

/// Checks, before a run, that `path` can be written later: it names a file (not a directory,
/// not a path ending in `/`) and its directory exists. `option` names the command-line option
/// in the error.
pub fn check_output_path(path: &Path, option: &str) -> Result<()> {
    let dir = parent(path);
    if path.file_name().is_none() || ends_in_slash(path) {
        return Err(Error::argument(option, format!("{}: not a file name", path.display())));
    }
    if !dir.is_dir() {
        return Err(Error::argument(
            option,
            format!("{}: directory {} does not exist", path.display(), dir.display()),
        ));
    }
    if path.is_dir() {
        return Err(Error::argument(
            option,
            format!("{}: is a directory; give a file name", path.display()),
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

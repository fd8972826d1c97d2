//! Output files written atomically: the one place pointillist writes what it renders.
//!
//! Contract (docs/RELIABILITY.md, "No data lost"):
//! - [`Destination::check`] decides, before any work, whether a path may be written: a symbolic
//!   link is followed to the file it names (the link stays a link), an existing path must be a
//!   regular file, and it must not be one of the inputs (the scene file, a texture, a vertex
//!   file) under any name. Every refusal is a one-line [`ImageError`] naming the path.
//! - [`Destination::create`] opens a [`PendingFile`]: a temporary file with a short random name
//!   in the destination's folder (so a destination name of up to 255 bytes still works).
//!   [`PendingFile::commit`] flushes it to disk, gives it the destination's mode (an existing
//!   file's permissions; a new file gets what the umask leaves of 0666) and renames it over the
//!   destination; dropped uncommitted, it is removed. [`commit_all`] commits several (a PNG
//!   sequence) as one step.
//! - [`discard_pending`], for a signal handler, removes every temporary file not yet committed
//!   and makes later commits fail with [`ImageError::Interrupted`]: a destination then holds
//!   either its old content or a complete new file, never part of one, and no temporary file is
//!   left behind.

use std::collections::HashSet;
use std::fs::{self, File, Permissions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

use crate::ImageError;

/// Temporary files not yet committed (a set: adding and removing one is O(1), so that a
/// sequence of 100,000 frames commits or drops in linear time), files committed, and whether
/// [`discard_pending`] has run.
struct Pending {
    paths: Option<HashSet<PathBuf>>,
    committed: usize,
    discarded: bool,
}

static PENDING: Mutex<Pending> = Mutex::new(Pending {
    paths: None,
    committed: 0,
    discarded: false,
});

impl Pending {
    fn paths(&mut self) -> &mut HashSet<PathBuf> {
        self.paths.get_or_insert_with(HashSet::new)
    }
}

fn pending() -> MutexGuard<'static, Pending> {
    // A panic while the lock was held cannot leave the set inconsistent (each change is one
    // insert or one remove), so a poisoned lock is still good.
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary file a [`PendingFile`] holds and refuses every later commit. For a
/// signal handler that is about to end the process: nothing it leaves behind is half written.
/// Returns how many files were committed before.
pub fn discard_pending() -> usize {
    let mut p = pending();
    p.discarded = true;
    for path in p.paths().drain() {
        let _ = fs::remove_file(path);
    }
    p.committed
}

fn io_error(op: &'static str, path: &Path, source: io::Error) -> ImageError {
    ImageError::Io {
        op,
        path: path.to_path_buf(),
        source,
    }
}

/// The identity of a file: its device and inode.
#[cfg(unix)]
fn file_id(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let m = fs::metadata(path).ok()?;
    Some((m.dev(), m.ino()))
}

/// The identity of a file: its canonical path.
#[cfg(not(unix))]
fn file_id(path: &Path) -> Option<PathBuf> {
    fs::canonicalize(path).ok()
}

/// What kind of file a metadata describes, for refusals ("a directory", "a named pipe").
pub fn file_kind(m: &fs::Metadata) -> &'static str {
    let t = m.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a named pipe";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else {
        "not a regular file"
    }
}

/// A path checked to be writable as an output ([`Destination::check`]).
#[derive(Clone, Debug)]
pub struct Destination {
    /// The path as given, for messages.
    given: PathBuf,
    /// The file written: the given path with symbolic links followed.
    target: PathBuf,
    /// The existing file's permissions, kept by the new file.
    permissions: Option<Permissions>,
}

impl Destination {
    /// Checks that `path` may be written: follows symbolic links, refuses anything that exists
    /// and is not a regular file, and refuses any of `inputs` (the files the render reads).
    pub fn check(path: &Path, inputs: &[PathBuf]) -> Result<Destination, ImageError> {
        let refuse = |why: String| ImageError::Io {
            op: "write",
            path: path.to_path_buf(),
            source: io::Error::new(io::ErrorKind::InvalidInput, why),
        };
        if path.file_name().is_none() {
            return Err(refuse("the path has no file name".into()));
        }
        let target = resolve_links(path).map_err(|e| io_error("write", path, e))?;
        let permissions = match fs::metadata(&target) {
            Ok(m) if m.is_file() => Some(m.permissions()),
            Ok(m) => {
                return Err(refuse(format!(
                    "it is {}; outputs are only written to regular files",
                    file_kind(&m)
                )));
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(io_error("write", path, e)),
        };
        if permissions.is_some()
            && let Some(id) = file_id(&target)
            && let Some(input) = inputs.iter().find(|p| file_id(p).as_ref() == Some(&id))
        {
            return Err(refuse(format!(
                "it is the input {}; choose another output name",
                input.display()
            )));
        }
        let folder = folder_of(&target);
        match fs::metadata(folder) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(refuse(format!("{} is not a folder", folder.display()))),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Err(refuse(format!(
                    "folder {} does not exist",
                    folder.display()
                )));
            }
            Err(e) => {
                return Err(refuse(format!(
                    "folder {} cannot be used: {e}",
                    folder.display()
                )));
            }
        }
        Ok(Destination {
            given: path.to_path_buf(),
            target,
            permissions,
        })
    }

    /// The path as given.
    pub fn path(&self) -> &Path {
        &self.given
    }

    /// Opens a temporary file beside the destination; see [`PendingFile`].
    pub fn create(&self) -> Result<PendingFile, ImageError> {
        let folder = folder_of(&self.target);
        let mut builder = tempfile::Builder::new();
        builder.prefix(".pointillist-").suffix(".tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // Created as any new file is: 0666 less the umask. An existing file's permissions
            // are given back at commit.
            builder.permissions(Permissions::from_mode(0o666));
        }
        let mut p = pending();
        if p.discarded {
            return Err(ImageError::Interrupted);
        }
        let temp = builder
            .tempfile_in(folder)
            .map_err(|e| io_error("create a temporary file for", &self.given, e))?;
        p.paths().insert(temp.path().to_path_buf());
        drop(p);
        let (file, temp_path) = temp.into_parts();
        Ok(PendingFile {
            writer: Some(BufWriter::new(file)),
            temp: Some(temp_path),
            dest: self.clone(),
        })
    }

    /// Writes `bytes` as the file, atomically: for outputs that are whole in memory (a report,
    /// a list of calls).
    pub fn write_bytes(&self, bytes: &[u8]) -> Result<(), ImageError> {
        let mut file = self.create()?;
        file.write_all(bytes)
            .map_err(|e| io_error("write", &self.given, e))?;
        file.commit()
    }

    /// Writes `width` x `height` RGBA8 pixels as a PNG file (crate::png::write_png_rgba8),
    /// atomically.
    pub fn write_png(
        &self,
        width: u32,
        height: u32,
        rgba: &[u8],
        compression: crate::png::Compression,
    ) -> Result<(), ImageError> {
        let mut file = self.create()?;
        crate::png::write_png_rgba8(&mut file, width, height, rgba, compression).map_err(|e| {
            ImageError::File {
                path: self.given.clone(),
                source: Box::new(e),
            }
        })?;
        file.commit()
    }
}

/// The folder a file is in ("." for a bare name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// `path` with symbolic links followed, up to 40 of them (the Linux limit); a dangling link
/// gives the path it names.
fn resolve_links(path: &Path) -> io::Result<PathBuf> {
    let mut path = path.to_path_buf();
    for _ in 0..40 {
        match fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => {
                let link = fs::read_link(&path)?;
                path = folder_of(&path).join(link);
            }
            Ok(_) => return Ok(path),
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(path),
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other("too many levels of symbolic links"))
}

/// An output being written: a temporary file beside its destination (see [`Destination`]).
/// Writes go through a buffer; [`PendingFile::commit`] puts it in place, dropping it removes it.
pub struct PendingFile {
    writer: Option<BufWriter<File>>,
    temp: Option<tempfile::TempPath>,
    dest: Destination,
}

impl PendingFile {
    /// The temporary file's path (for a program that writes it, such as ffmpeg).
    pub fn temp_path(&self) -> &Path {
        self.temp.as_deref().unwrap_or(Path::new(""))
    }

    /// The destination.
    pub fn destination(&self) -> &Destination {
        &self.dest
    }

    /// Flushes and syncs the data, gives the file the destination's permissions and closes
    /// it, so that many pending files (a long PNG sequence) hold no file descriptors. Further
    /// writes fail; [`PendingFile::commit`] does this itself.
    pub fn close(&mut self) -> Result<(), ImageError> {
        let given = &self.dest.given;
        let Some(writer) = self.writer.take() else {
            return Ok(());
        };
        let file = writer
            .into_inner()
            .map_err(|e| io_error("write", given, e.into_error()))?;
        file.sync_all().map_err(|e| io_error("write", given, e))?;
        if let Some(perm) = &self.dest.permissions {
            file.set_permissions(perm.clone())
                .map_err(|e| io_error("set the permissions of", given, e))?;
        }
        Ok(())
    }

    /// Puts the file in place of its destination (see [`commit_all`]).
    pub fn commit(self) -> Result<(), ImageError> {
        commit_all(vec![self])
    }
}

impl Write for PendingFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.writer {
            Some(w) => w.write(buf),
            None => Err(io::Error::other("the output is already finished")),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.writer {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            let mut p = pending();
            p.paths().remove(&*temp);
            // Removed while the list is locked, so that it is never removed twice.
            drop(temp);
        }
    }
}

/// Puts every file in place of its destination, in order, under one lock: a
/// [`discard_pending`] comes before all of them (none is committed) or after all of them. Fails
/// with [`ImageError::Interrupted`] after a [`discard_pending`]; a failure leaves the files not
/// yet committed removed and their destinations untouched.
pub fn commit_all(mut files: Vec<PendingFile>) -> Result<(), ImageError> {
    for f in &mut files {
        f.close()?;
    }
    let mut folders = Vec::new();
    let mut p = pending();
    if p.discarded {
        return Err(ImageError::Interrupted);
    }
    for f in &mut files {
        let Some(temp) = f.temp.take() else {
            continue;
        };
        p.paths().remove(&*temp);
        if let Err(e) = temp.persist(&f.dest.target) {
            // Removed while the list is locked; the files after it are removed when dropped.
            drop(e.path);
            return Err(io_error(
                "rename a temporary file over",
                &f.dest.given,
                e.error,
            ));
        }
        p.committed += 1;
        folders.push(folder_of(&f.dest.target).to_path_buf());
    }
    drop(p);
    // Make the renames durable where the platform allows; failure here does not undo them.
    folders.dedup();
    for folder in folders {
        if let Ok(d) = File::open(folder) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder, removed when the test ends.
    fn scratch(tag: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("pointillist-output-{tag}-"))
            .tempdir()
            .unwrap()
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    fn write(dest: &Path, inputs: &[PathBuf], data: &[u8]) -> Result<(), ImageError> {
        Destination::check(dest, inputs)?.write_bytes(data)
    }

    #[test]
    fn an_input_is_never_an_output_under_any_name() {
        let tmp = scratch("input");
        let dir = tmp.path().to_path_buf();
        let scene = dir.join("scene.toml");
        fs::write(&scene, b"format = 1").unwrap();
        let inputs = [scene.clone()];
        let e = write(&scene, &inputs, b"png").unwrap_err().to_string();
        assert!(
            e.contains("scene.toml") && e.contains("is the input"),
            "{e}"
        );
        // Another name for the same file: a hard link, a symbolic link, a dotted path.
        fs::hard_link(&scene, dir.join("hard.png")).unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink("scene.toml", dir.join("soft.png")).unwrap();
        for name in ["hard.png", "soft.png", "./scene.toml"] {
            if !cfg!(unix) && name == "soft.png" {
                continue;
            }
            let e = write(&dir.join(name), &inputs, b"png").unwrap_err();
            assert!(e.to_string().contains("is the input"), "{name}: {e}");
        }
        assert_eq!(fs::read(&scene).unwrap(), b"format = 1");
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_and_modes_kept() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = scratch("links");
        let dir = tmp.path().to_path_buf();
        let real = dir.join("real.png");
        fs::write(&real, b"old").unwrap();
        fs::set_permissions(&real, Permissions::from_mode(0o600)).unwrap();
        let link = dir.join("link.png");
        std::os::unix::fs::symlink("real.png", &link).unwrap();
        write(&link, &[], b"new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"new");
        let mode = fs::metadata(&real).unwrap().permissions().mode() & 0o7777;
        assert_eq!(mode, 0o600);
        // A new file gets 0666 less the umask, like any file a program creates.
        let probe = dir.join("probe");
        fs::write(&probe, b"").unwrap();
        let usual = fs::metadata(&probe).unwrap().permissions().mode() & 0o7777;
        write(&dir.join("fresh.png"), &[], b"x").unwrap();
        let fresh = fs::metadata(dir.join("fresh.png")).unwrap().permissions();
        assert_eq!(fresh.mode() & 0o7777, usual);
        assert_eq!(
            listing(&dir),
            ["fresh.png", "link.png", "probe", "real.png"]
        );
    }

    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_written() {
        let tmp = scratch("special");
        let dir = tmp.path().to_path_buf();
        let fifo = dir.join("pipe.png");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if made.is_ok_and(|s| s.success()) {
            let e = write(&fifo, &[], b"x").unwrap_err().to_string();
            assert!(e.contains("pipe.png") && e.contains("a named pipe"), "{e}");
            assert!(!fs::metadata(&fifo).unwrap().is_file());
        }
        let e = write(Path::new("/dev/null"), &[], b"x")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/dev/null") && e.contains("a character device"),
            "{e}"
        );
        assert!(!fs::metadata("/dev/null").unwrap().is_file());
        let e = write(&dir, &[], b"x").unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        let e = write(&dir.join("no").join("x.png"), &[], b"x").unwrap_err();
        assert!(e.to_string().contains("folder"), "{e}");
    }

    #[test]
    fn names_up_to_255_bytes_work_and_nothing_stays_behind() {
        let tmp = scratch("long");
        let dir = tmp.path().to_path_buf();
        for len in [240, 241, 250, 255] {
            let name = format!("{}.png", "n".repeat(len - 4));
            write(&dir.join(&name), &[], b"data").unwrap();
            assert_eq!(fs::read(dir.join(&name)).unwrap(), b"data");
            fs::remove_file(dir.join(&name)).unwrap();
        }
        // Dropped without a commit: removed, the old file untouched.
        fs::write(dir.join("keep.png"), b"old").unwrap();
        let mut f = Destination::check(&dir.join("keep.png"), &[])
            .unwrap()
            .create()
            .unwrap();
        f.write_all(b"half").unwrap();
        assert_eq!(listing(&dir).len(), 2);
        drop(f);
        assert_eq!(listing(&dir), ["keep.png"]);
        assert_eq!(fs::read(dir.join("keep.png")).unwrap(), b"old");
        // Several at once.
        let dests: Vec<PendingFile> = (0..3)
            .map(|i| {
                let mut f = Destination::check(&dir.join(format!("f{i}.png")), &[])
                    .unwrap()
                    .create()
                    .unwrap();
                f.write_all(&[i]).unwrap();
                f
            })
            .collect();
        commit_all(dests).unwrap();
        assert_eq!(listing(&dir), ["f0.png", "f1.png", "f2.png", "keep.png"]);
        assert!(!pending().paths().iter().any(|p| p.starts_with(&dir)));
    }
}

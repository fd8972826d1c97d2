//! The vertex bytes of a draw ([`crate::Command::Draw`]): rows the scene gives (`vertices =`),
//! encoded, or a raw vertex file (`file =`) mapped from the kernel's page cache, not copied.

use std::fmt;
use std::fs::File;
use std::io::Read;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use memmap2::{Mmap, MmapOptions};

/// Little-endian FVF vertex bytes, `fvf.stride()` per vertex: derefs to `&[u8]`; a clone shares
/// the bytes (an `Arc`), so a scene clones cheaply however large its vertex files.
///
/// A raw vertex file (`file =`) is a read-only shared memory map of the file, made with
/// `MAP_POPULATE` (the page cache's pages mapped up front, so the draw takes no page faults)
/// after the file's length was checked; nothing is copied into the process. The file stays open
/// for as long as the bytes live, and its length is checked again after the map is made
/// ([`crate::parse`]) and before and after each draw that reads it ([`crate::Scene::replay`]):
/// a file whose size changed gives an error naming it. Code that reads the bytes itself, outside
/// a replay, calls [`VertexBytes::check_unchanged`] first.
///
/// What a map cannot protect against, and the checks only narrow:
/// - A file **truncated while a draw reads it** (another process shortening it in place between
///   the check before the draw and the draw's last read) makes the draw's read of a page past
///   the new end fault, and the process dies of `SIGBUS`, as any program reading a mapped file
///   does. A private map (`MAP_PRIVATE`) does not help: truncation unmaps the file's pages from
///   private maps too (tried on Linux 6.18, with `MAP_POPULATE` as well). Only a copy would, and
///   the copy is what this type saves (a quarter of `render`'s CPU time for W1, measured in
///   docs/PERFORMANCE.md).
///   Replacing the file (writing a new one and renaming it over the old, as most tools do) is
///   safe: the map keeps the old file's pages.
/// - A file **rewritten in place at the same length** during a draw changes the vertices that
///   draw reads partway; the checks look at the length only.
///
/// An empty file is not mapped (it holds zero vertices); a file that cannot be mapped (a file
/// system without `mmap`) is read into memory instead, checked the same way.
#[derive(Clone)]
pub struct VertexBytes(Repr);

#[derive(Clone)]
enum Repr {
    /// Bytes in memory: encoded rows, or a file that could not be mapped.
    Owned(Arc<[u8]>),
    /// A mapped vertex file.
    Mapped(Arc<MappedFile>),
}

/// A vertex file's map and the open file, for checking its length.
struct MappedFile {
    map: Mmap,
    file: File,
    path: PathBuf,
}

impl VertexBytes {
    /// The vertex file these bytes are mapped from; `None` for bytes in memory.
    pub fn mapped_file(&self) -> Option<&Path> {
        match &self.0 {
            Repr::Owned(_) => None,
            Repr::Mapped(m) => Some(&m.path),
        }
    }

    /// Checks that a mapped vertex file still has the length it had when it was mapped (bytes
    /// in memory always pass): the error, one line, names the file and both lengths.
    pub fn check_unchanged(&self) -> Result<(), String> {
        let Repr::Mapped(m) = &self.0 else {
            return Ok(());
        };
        let now = m.file.metadata().map_err(|e| {
            format!(
                "cannot check the length of vertex file `{}`: {e}",
                m.path.display()
            )
        })?;
        if now.len() != m.map.len() as u64 {
            return Err(format!(
                "vertex file `{}` changed size after the scene was read ({} bytes, now {}); \
                 the draw cannot use it",
                m.path.display(),
                m.map.len(),
                now.len()
            ));
        }
        Ok(())
    }

    /// The vertex file at `path`, which was a regular file of `len` bytes when it was checked:
    /// mapped (read when it cannot be mapped), then its length checked again. Errors are one
    /// line naming the file.
    pub(crate) fn read_file(path: &Path, len: u64) -> Result<VertexBytes, String> {
        let cannot =
            |e: std::io::Error| format!("cannot read vertex file `{}`: {e}", path.display());
        let changed = |now: String| {
            format!(
                "vertex file `{}` changed while it was read ({len} bytes, then {now})",
                path.display()
            )
        };
        let file = File::open(path).map_err(cannot)?;
        let opened = file.metadata().map_err(cannot)?;
        if !opened.is_file() {
            return Err(format!("vertex file `{}` is not a file", path.display()));
        }
        if opened.len() != len {
            return Err(changed(opened.len().to_string()));
        }
        let Ok(size) = usize::try_from(len) else {
            return Err(cannot(std::io::Error::from(
                std::io::ErrorKind::OutOfMemory,
            )));
        };
        // Zero bytes cannot be mapped, and a map that fails falls back to a read; both read at
        // most one byte more than the length, to see that the file did not grow.
        let map = if size == 0 {
            None
        } else {
            map_file(&file, size).ok()
        };
        let Some(map) = map else {
            let mut bytes = Vec::with_capacity(size);
            (&file)
                .take(len + 1)
                .read_to_end(&mut bytes)
                .map_err(cannot)?;
            if bytes.len() != size {
                let then = if bytes.len() > size {
                    "more".to_string()
                } else {
                    bytes.len().to_string()
                };
                return Err(changed(then));
            }
            return Ok(bytes.into());
        };
        let now = file.metadata().map_err(cannot)?.len();
        if now != len {
            return Err(changed(now.to_string()));
        }
        Ok(VertexBytes(Repr::Mapped(Arc::new(MappedFile {
            map,
            file,
            path: path.to_path_buf(),
        }))))
    }
}

/// A read-only shared map of the first `len` bytes of `file`, its pages mapped up front.
#[allow(unsafe_code)] // The map: memmap2's `map` is unsafe because the file may change.
fn map_file(file: &File, len: usize) -> std::io::Result<Mmap> {
    // SAFETY: the map is read only, and its bytes are only read (as `&[u8]`, by draws). Another
    // process changing the file underneath is what `map` is unsafe for: a truncation makes reads
    // past the new end raise SIGBUS (which ends the process; no wrong value is read), and a
    // write in place changes bytes a draw reads. `VertexBytes` documents both, and its length
    // checks (after this map, before and after each draw) turn a size change seen then into an
    // error; the draws read vertex bytes as plain data, with no invariant a changed byte breaks.
    unsafe { MmapOptions::new().len(len).populate().map(file) }
}

impl Deref for VertexBytes {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        match &self.0 {
            Repr::Owned(b) => b,
            Repr::Mapped(m) => &m.map,
        }
    }
}

impl AsRef<[u8]> for VertexBytes {
    fn as_ref(&self) -> &[u8] {
        self
    }
}

impl From<Vec<u8>> for VertexBytes {
    fn from(bytes: Vec<u8>) -> Self {
        VertexBytes(Repr::Owned(bytes.into()))
    }
}

impl FromIterator<u8> for VertexBytes {
    fn from_iter<I: IntoIterator<Item = u8>>(bytes: I) -> Self {
        bytes.into_iter().collect::<Vec<u8>>().into()
    }
}

impl Default for VertexBytes {
    fn default() -> Self {
        Vec::new().into()
    }
}

/// Equal when the bytes are, wherever they live.
impl PartialEq for VertexBytes {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

impl Eq for VertexBytes {}

impl PartialEq<[u8]> for VertexBytes {
    fn eq(&self, other: &[u8]) -> bool {
        **self == *other
    }
}

impl PartialEq<Vec<u8>> for VertexBytes {
    fn eq(&self, other: &Vec<u8>) -> bool {
        **self == **other
    }
}

/// Bytes in memory print as a `Vec<u8>` does; a mapped file prints its name and length.
impl fmt::Debug for VertexBytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.0 {
            Repr::Owned(b) => fmt::Debug::fmt(&**b, f),
            Repr::Mapped(m) => f
                .debug_struct("Mapped")
                .field("file", &m.path)
                .field("len", &m.map.len())
                .finish(),
        }
    }
}

//! Texture files in, render targets out.
//!
//! Contract:
//! - [`dds::load_dds`] and [`png::load_png`] decode a file held in memory into a
//!   [`Texture`] (full mip chain, D3DCOLOR texels); [`load_texture`] reads a file from disk and
//!   picks the decoder by the file's signature, or by its extension (`.png`, `.dds`,
//!   case-insensitive) when the signature is not recognised.
//! - [`png::write_png_rgba8`] encodes an RGBA8 image; [`output`] is where every output file is
//!   written (atomically, never over an input or a file that is not a regular file), and
//!   [`write_png_atomic`] writes one PNG through it.
//! - Every failure is an [`ImageError`] with a one-line message that says what is wrong and where
//!   (byte offset, header field, file path). No input makes these functions panic, and sizes are
//!   limited to [`MAX_TEXTURE_SIZE`] per axis before anything large is allocated.

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use pointillist_core::RenderTarget;
use pointillist_core::texture::{Texture, TextureError, check_size};

pub mod dds;
pub mod output;
pub mod png;

/// Largest width or height of a loaded texture (the core limit, [`pointillist_core::texture`]).
pub const MAX_TEXTURE_SIZE: u32 = pointillist_core::texture::MAX_TEXTURE_SIZE;

/// Why an image could not be read or written.
#[derive(Debug)]
#[non_exhaustive]
pub enum ImageError {
    /// The data ends before something it declares.
    Truncated {
        /// What was being read ("DDS header", "mip level 2 (4x4)", ...).
        what: String,
        /// Byte offset where it starts.
        offset: usize,
        /// Bytes it needs from there.
        needed: usize,
        /// Length of the data.
        len: usize,
    },
    /// The DDS signature is not "DDS ".
    BadMagic {
        /// The first bytes found (fewer than four when the data is shorter).
        found: Vec<u8>,
    },
    /// A header field has an invalid value.
    BadField {
        /// Field name as in the format's documentation.
        field: &'static str,
        /// Byte offset of the field.
        offset: usize,
        /// The value found.
        value: u32,
        /// What a valid value looks like.
        expected: &'static str,
    },
    /// A pixel format or feature this crate does not decode.
    Unsupported {
        /// The format (FourCC, flags, bit count and masks) or feature.
        detail: String,
    },
    /// The decoded levels do not form a valid texture.
    Texture(TextureError),
    /// The PNG decoder rejected the data.
    PngDecode(::png::DecodingError),
    /// The PNG encoder failed.
    PngEncode(::png::EncodingError),
    /// A pixel buffer does not hold `width * height * 4` bytes.
    BufferSize {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Bytes required (`None` when the size overflows).
        expected: Option<usize>,
        /// Bytes given.
        actual: usize,
    },
    /// Neither the signature nor the extension names a known format.
    UnknownFormat,
    /// A file-system operation failed.
    Io {
        /// The operation ("read", "create", "rename", ...).
        op: &'static str,
        /// The path it was applied to.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// The process is being interrupted: [`output::discard_pending`] has run, so nothing more
    /// is written.
    Interrupted,
    /// An error while loading or writing a given file.
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: Box<ImageError>,
    },
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::Truncated {
                what,
                offset,
                needed,
                len,
            } => write!(
                f,
                "truncated data: {what} needs {needed} bytes at offset {offset} but the data is {len} bytes long"
            ),
            ImageError::BadMagic { found } => {
                write!(
                    f,
                    "not a DDS file: signature at offset 0 is {found:02X?}, expected \"DDS \""
                )
            }
            ImageError::BadField {
                field,
                offset,
                value,
                expected,
            } => write!(
                f,
                "invalid header field {field} at offset {offset}: {value} (0x{value:X}), expected {expected}"
            ),
            ImageError::Unsupported { detail } => write!(f, "unsupported {detail}"),
            ImageError::Texture(e) => write!(f, "invalid texture: {e}"),
            ImageError::PngDecode(e) => write!(f, "PNG decoding failed: {e}"),
            ImageError::PngEncode(e) => write!(f, "PNG encoding failed: {e}"),
            ImageError::BufferSize {
                width,
                height,
                expected,
                actual,
            } => match expected {
                Some(n) => write!(
                    f,
                    "pixel buffer for {width}x{height} RGBA8 needs {n} bytes but has {actual}"
                ),
                None => write!(
                    f,
                    "pixel buffer for {width}x{height} RGBA8 is too large to address (has {actual} bytes)"
                ),
            },
            ImageError::UnknownFormat => write!(
                f,
                "unknown image format: neither a PNG nor a DDS signature, and no .png or .dds extension"
            ),
            ImageError::Io { op, path, source } => {
                write!(f, "cannot {op} {}: {source}", path.display())
            }
            ImageError::Interrupted => write!(f, "interrupted: no output written"),
            ImageError::File { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for ImageError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ImageError::Texture(e) => Some(e),
            ImageError::PngDecode(e) => Some(e),
            ImageError::PngEncode(e) => Some(e),
            ImageError::Io { source, .. } => Some(source),
            ImageError::File { source, .. } => Some(source.as_ref()),
            _ => None,
        }
    }
}

impl From<TextureError> for ImageError {
    fn from(e: TextureError) -> Self {
        ImageError::Texture(e)
    }
}

/// The file formats this crate reads.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Format {
    /// Portable Network Graphics.
    Png,
    /// DirectDraw Surface.
    Dds,
}

impl Format {
    /// The format whose signature starts `bytes`, if any.
    pub fn from_magic(bytes: &[u8]) -> Option<Format> {
        if bytes.starts_with(png::PNG_SIGNATURE) {
            Some(Format::Png)
        } else if bytes.starts_with(dds::DDS_MAGIC) {
            Some(Format::Dds)
        } else {
            None
        }
    }

    /// The format a path's extension names (`png` or `dds`, case-insensitive), if any.
    pub fn from_extension(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?;
        if ext.eq_ignore_ascii_case("png") {
            Some(Format::Png)
        } else if ext.eq_ignore_ascii_case("dds") {
            Some(Format::Dds)
        } else {
            None
        }
    }
}

/// Decodes a texture held in memory, choosing the decoder by its signature.
pub fn decode_texture(bytes: &[u8]) -> Result<Texture, ImageError> {
    match Format::from_magic(bytes) {
        Some(Format::Png) => png::load_png(bytes),
        Some(Format::Dds) => dds::load_dds(bytes),
        None => Err(ImageError::UnknownFormat),
    }
}

/// Reads a texture file: PNG or DDS, recognised by its signature, or else by its extension
/// (`.png`, `.dds`, case-insensitive). Every error names the path.
pub fn load_texture(path: &Path) -> Result<Texture, ImageError> {
    let bytes = fs::read(path).map_err(|source| ImageError::Io {
        op: "read",
        path: path.to_path_buf(),
        source,
    })?;
    let format = Format::from_magic(&bytes).or_else(|| Format::from_extension(path));
    let result = match format {
        Some(Format::Png) => png::load_png(&bytes),
        Some(Format::Dds) => dds::load_dds(&bytes),
        None => Err(ImageError::UnknownFormat),
    };
    result.map_err(|e| ImageError::File {
        path: path.to_path_buf(),
        source: Box::new(e),
    })
}

/// What [`load_texture`] holds for a file besides the file's own bytes, read from its header
/// alone so that a memory budget refuses a texture before it is decoded
/// ([`texture_decode_cost`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct DecodeCost {
    /// The texture: a full mip chain of 4-byte texels, held for the render.
    pub texture: u64,
    /// Held only while it is decoded: a PNG decoder's 8-bit output (4 bytes a pixel at most
    /// after expansion); 0 for DDS.
    pub scratch: u64,
}

/// The [`DecodeCost`] of the texture file at `path`, from its header; `None` when the header
/// gives no size within [`MAX_TEXTURE_SIZE`] (the decoder then refuses the file with its own
/// message).
pub fn texture_decode_cost(path: &Path) -> Option<DecodeCost> {
    let mut head = Vec::with_capacity(24);
    fs::File::open(path)
        .and_then(|f| io::Read::read_to_end(&mut io::Read::take(f, 24), &mut head))
        .ok()?;
    let word = |at: usize, le: bool| -> Option<u32> {
        let b: [u8; 4] = head.get(at..at + 4)?.try_into().ok()?;
        Some(if le {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    };
    let format = Format::from_magic(&head).or_else(|| Format::from_extension(path));
    // PNG: IHDR is the first chunk (width, height big-endian at 16 and 20); DDS: height and
    // width little-endian at 12 and 16.
    let size = match format {
        Some(Format::Png) if head.get(12..16) == Some(b"IHDR") => {
            word(16, false).zip(word(20, false))
        }
        Some(Format::Dds) => word(16, true).zip(word(12, true)),
        _ => None,
    };
    let (w, h) = size.filter(|&(w, h)| check_size(w, h).is_ok())?;
    let (mut lw, mut lh, mut texture) = (u64::from(w), u64::from(h), 0);
    loop {
        texture += lw * lh * 4;
        if lw == 1 && lh == 1 {
            break;
        }
        (lw, lh) = ((lw / 2).max(1), (lh / 2).max(1));
    }
    let scratch = if format == Some(Format::Png) {
        u64::from(w) * u64::from(h) * 4
    } else {
        0
    };
    Some(DecodeCost { texture, scratch })
}

/// Saves a render target as an RGBA8 PNG holding its exact bytes, alpha included, through
/// [`write_png_atomic`] (SCENE.md, command line).
pub fn save_target_png(target: &RenderTarget, path: &Path) -> Result<(), ImageError> {
    write_png_atomic(path, target.width, target.height, &target.to_rgba8())
}

/// Writes an RGBA8 image as a PNG file atomically, through [`output::Destination`] (no inputs
/// to protect): an existing file keeps its old content on failure, and no temporary file stays.
pub fn write_png_atomic(
    path: &Path,
    width: u32,
    height: u32,
    rgba: &[u8],
) -> Result<(), ImageError> {
    output::Destination::check(path, &[])?.write_png(width, height, rgba, png::Compression::Fast)
}

/// Writes `bytes` as a file atomically, through [`output::Destination`] (no inputs to
/// protect), like [`write_png_atomic`]: for outputs whole in memory (a report, a list of calls).
pub fn write_file_atomic(path: &Path, bytes: &[u8]) -> Result<(), ImageError> {
    output::Destination::check(path, &[])?.write_bytes(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh folder, removed when the test ends.
    fn scratch_dir(tag: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("pointillist-image-{tag}-"))
            .tempdir()
            .unwrap()
    }

    fn leftovers(dir: &Path) -> Vec<String> {
        fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".tmp"))
            .collect()
    }

    const RGBA_2X1: [u8; 8] = [255, 0, 0, 255, 0, 0, 255, 128];

    #[test]
    fn write_png_atomic_writes_and_replaces() {
        let tmp = scratch_dir("write");
        let dir = tmp.path().to_path_buf();
        let path = dir.join("out.png");
        write_png_atomic(&path, 2, 1, &RGBA_2X1).unwrap();
        let t = load_texture(&path).unwrap();
        assert_eq!(t.levels()[0].texels, vec![0xFFFF_0000, 0x8000_00FF]);
        write_png_atomic(&path, 1, 1, &[1, 2, 3, 4]).unwrap();
        let t = load_texture(&path).unwrap();
        assert_eq!(t.levels()[0].texels, vec![0x0401_0203]);
        assert!(leftovers(&dir).is_empty());
    }

    #[test]
    fn write_png_atomic_failure_leaves_target_and_no_temp_file() {
        let tmp = scratch_dir("fail");
        let dir = tmp.path().to_path_buf();
        // The target is a non-empty directory: the rename must fail and change nothing.
        let target = dir.join("taken.png");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("keep"), b"x").unwrap();
        let e = write_png_atomic(&target, 2, 1, &RGBA_2X1).unwrap_err();
        assert!(e.to_string().contains("taken.png"), "{e}");
        assert_eq!(fs::read(target.join("keep")).unwrap(), b"x");
        assert!(leftovers(&dir).is_empty());

        // A bad buffer fails before touching the file system.
        let old = dir.join("old.png");
        fs::write(&old, b"old content").unwrap();
        let e = write_png_atomic(&old, 2, 2, &RGBA_2X1).unwrap_err();
        assert!(
            e.to_string().contains("old.png") && e.to_string().contains("16"),
            "{e}"
        );
        assert_eq!(fs::read(&old).unwrap(), b"old content");

        // A missing directory names the path.
        let missing = dir.join("no-such-dir").join("x.png");
        let e = write_png_atomic(&missing, 2, 1, &RGBA_2X1).unwrap_err();
        assert!(e.to_string().contains("no-such-dir"), "{e}");
        assert!(leftovers(&dir).is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn write_png_atomic_in_read_only_directory_keeps_old_file() {
        use std::os::unix::fs::PermissionsExt;
        let tmp = scratch_dir("ro");
        let dir = tmp.path().to_path_buf();
        let path = dir.join("old.png");
        fs::write(&path, b"old content").unwrap();
        fs::set_permissions(&dir, fs::Permissions::from_mode(0o555)).unwrap();
        // Privileged users can write anyway; then there is nothing to test.
        let probe = dir.join("probe");
        let privileged = fs::write(&probe, b"").is_ok();
        let _ = fs::remove_file(&probe);
        if !privileged {
            let e = write_png_atomic(&path, 2, 1, &RGBA_2X1).unwrap_err();
            assert!(e.to_string().contains("old.png"), "{e}");
            assert_eq!(fs::read(&path).unwrap(), b"old content");
        }
        fs::set_permissions(&dir, fs::Permissions::from_mode(0o755)).unwrap();
        assert!(leftovers(&dir).is_empty());
    }

    #[test]
    fn load_texture_by_magic_then_extension_and_names_the_path() {
        let tmp = scratch_dir("load");
        let dir = tmp.path().to_path_buf();
        let png_bytes = png::encode_png_rgba8(2, 1, &RGBA_2X1).unwrap();
        // Signature wins over a misleading extension.
        let odd = dir.join("really-a-png.dds");
        fs::write(&odd, &png_bytes).unwrap();
        assert_eq!(load_texture(&odd).unwrap().width(), 2);
        // Unknown signature: the extension picks the decoder, whose error names the path.
        let bad = dir.join("broken.DDS");
        fs::write(&bad, b"garbage!").unwrap();
        let e = load_texture(&bad).unwrap_err().to_string();
        assert!(e.contains("broken.DDS") && e.contains("DDS"), "{e}");
        let bad = dir.join("broken.Png");
        fs::write(&bad, b"garbage!").unwrap();
        let e = load_texture(&bad).unwrap_err().to_string();
        assert!(e.contains("broken.Png") && e.contains("PNG"), "{e}");
        let unknown = dir.join("mystery.bin");
        fs::write(&unknown, b"garbage!").unwrap();
        let e = load_texture(&unknown).unwrap_err().to_string();
        assert!(e.contains("mystery.bin") && e.contains("unknown"), "{e}");
        let e = load_texture(&dir.join("absent.png"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("absent.png") && e.contains("read"), "{e}");
        assert!(matches!(
            decode_texture(b"nothing"),
            Err(ImageError::UnknownFormat)
        ));
    }
}

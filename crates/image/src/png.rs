//! PNG in and out.
//!
//! Contract:
//! - [`load_png`] accepts every PNG colour type and bit depth: palette, grey and low bit depths
//!   are expanded, tRNS becomes alpha, 16-bit samples are reduced to 8 bits (the `png` crate's
//!   EXPAND, STRIP_16 and ALPHA transformations), and the result is a [`Texture`] whose level 0
//!   holds the image (first frame of an APNG) and whose smaller levels are box-filtered.
//!   Images wider or taller than [`crate::MAX_TEXTURE_SIZE`] are rejected before decoding.
//! - [`write_png_rgba8`] (and [`encode_png_rgba8`], into memory) writes 8-bit RGBA,
//!   non-interlaced, rows top to bottom, compressed as [`Compression`] says (the same pixels
//!   whatever the level).

use std::io::{Cursor, Write};

use ::png::{BitDepth, ColorType, Decoder, Encoder, Transformations};
use pointillist_core::color::rgba8_to_argb;
use pointillist_core::texture::{Texture, check_size};

use crate::ImageError;

/// The eight bytes every PNG file starts with.
pub const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

/// How hard PNG output is compressed (`--compression`): every level writes the same pixels.
/// Measured in docs/PERFORMANCE.md ("PNG compression"): `Fast` is 11x to 27x faster than
/// `Default` for files 1.15x to 1.55x larger.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Compression {
    /// fdeflate with adaptive row filters (the png crate's `Fast`).
    #[default]
    Fast,
    /// zlib level 6 with adaptive row filters (the png crate's `Balanced`).
    Default,
    /// zlib level 9 with adaptive row filters (the png crate's `High`).
    Best,
}

impl Compression {
    /// Sets this level on a PNG (or APNG) encoder.
    pub fn apply<W: Write>(self, encoder: &mut Encoder<W>) {
        encoder.set_compression(match self {
            Compression::Fast => ::png::Compression::Fast,
            Compression::Default => ::png::Compression::Balanced,
            Compression::Best => ::png::Compression::High,
        });
    }
}

/// Decodes a PNG file held in memory into a texture (RGBA8 texels as D3DCOLOR).
pub fn load_png(bytes: &[u8]) -> Result<Texture, ImageError> {
    let mut decoder = Decoder::new(Cursor::new(bytes));
    decoder.set_transformations(
        Transformations::EXPAND | Transformations::STRIP_16 | Transformations::ALPHA,
    );
    let header = decoder.read_header_info().map_err(ImageError::PngDecode)?;
    let (width, height) = (header.width, header.height);
    check_size(width, height).map_err(ImageError::Texture)?;
    let mut reader = decoder.read_info().map_err(ImageError::PngDecode)?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| ImageError::Unsupported {
            detail: format!("PNG of {width}x{height}: its decoded size cannot be addressed"),
        })?;
    let mut buf = vec![0u8; size];
    let out = reader.next_frame(&mut buf).map_err(ImageError::PngDecode)?;
    if out.bit_depth != BitDepth::Eight {
        return Err(ImageError::Unsupported {
            detail: format!("PNG output bit depth {:?} after expansion", out.bit_depth),
        });
    }
    let channels = match out.color_type {
        ColorType::Grayscale => 1,
        ColorType::GrayscaleAlpha => 2,
        ColorType::Rgb => 3,
        ColorType::Rgba => 4,
        ColorType::Indexed => {
            return Err(ImageError::Unsupported {
                detail: "PNG output colour type Indexed after expansion".to_string(),
            });
        }
    };
    // The frame may be a sub-rectangle for APNG; its size is what the buffer holds.
    let (w, h) = (out.width as usize, out.height as usize);
    let line = out.line_size;
    let mut texels = Vec::with_capacity(w * h);
    for y in 0..h {
        let row =
            buf.get(y * line..y * line + w * channels)
                .ok_or_else(|| ImageError::Truncated {
                    what: format!("PNG row {y}"),
                    offset: y * line,
                    needed: w * channels,
                    len: buf.len(),
                })?;
        for px in row.chunks_exact(channels) {
            let rgba = match *px {
                [l] => [l, l, l, 255],
                [l, a] => [l, l, l, a],
                [r, g, b] => [r, g, b, 255],
                [r, g, b, a] => [r, g, b, a],
                _ => unreachable!("chunks_exact yields 1 to 4 bytes"),
            };
            texels.push(rgba8_to_argb(rgba));
        }
    }
    Ok(Texture::from_argb(out.width, out.height, texels)?)
}

/// Encodes `width` x `height` RGBA8 pixels (rows top to bottom) as a PNG file, compressed
/// [`Compression::Fast`].
pub fn encode_png_rgba8(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, ImageError> {
    let mut out = Vec::new();
    write_png_rgba8(&mut out, width, height, rgba, Compression::Fast)?;
    Ok(out)
}

/// Writes `width` x `height` RGBA8 pixels (rows top to bottom) as a PNG file to `out`, without
/// a copy of the encoded file in memory.
pub fn write_png_rgba8<W: Write>(
    out: W,
    width: u32,
    height: u32,
    rgba: &[u8],
    compression: Compression,
) -> Result<(), ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::Unsupported {
            detail: format!("PNG of {width}x{height} pixels (a PNG has at least one per axis)"),
        });
    }
    let expected = (width as usize)
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(4));
    if expected != Some(rgba.len()) {
        return Err(ImageError::BufferSize {
            width,
            height,
            expected,
            actual: rgba.len(),
        });
    }
    let mut encoder = Encoder::new(out, width, height);
    encoder.set_color(ColorType::Rgba);
    encoder.set_depth(BitDepth::Eight);
    compression.apply(&mut encoder);
    let mut writer = encoder.write_header().map_err(ImageError::PngEncode)?;
    writer
        .write_image_data(rgba)
        .map_err(ImageError::PngEncode)?;
    writer.finish().map_err(ImageError::PngEncode)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pointillist_core::texture::TextureError;

    fn encode_with(
        width: u32,
        height: u32,
        color: ColorType,
        depth: BitDepth,
        palette: Option<(&[u8], &[u8])>,
        data: &[u8],
    ) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut e = Encoder::new(&mut out, width, height);
            e.set_color(color);
            e.set_depth(depth);
            if let Some((plte, trns)) = palette {
                e.set_palette(plte.to_vec());
                e.set_trns(trns.to_vec());
            }
            let mut w = e.write_header().unwrap();
            w.write_image_data(data).unwrap();
            w.finish().unwrap();
        }
        out
    }

    #[test]
    fn png_round_trip_rgba8() {
        let rgba: Vec<u8> = (0..3 * 2 * 4).map(|i| (i * 11) as u8).collect();
        let bytes = encode_png_rgba8(3, 2, &rgba).unwrap();
        assert!(bytes.starts_with(PNG_SIGNATURE));
        let t = load_png(&bytes).unwrap();
        assert_eq!((t.width(), t.height()), (3, 2));
        let expect: Vec<u32> = rgba
            .chunks_exact(4)
            .map(|c| rgba8_to_argb([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(t.levels()[0].texels, expect);
        assert_eq!(t.levels().len(), 2);
    }

    #[test]
    fn every_compression_level_writes_the_same_pixels() {
        // A gradient with noise in its low bits: compressible, not trivially.
        let (w, h) = (64u32, 48u32);
        let rgba: Vec<u8> = (0..w * h * 4)
            .map(|i| {
                ((i / 4 % w) * 3 + (i / 4 / w) * 2 + (i.wrapping_mul(2_654_435_761) >> 29)) as u8
            })
            .collect();
        let mut sizes = Vec::new();
        for c in [Compression::Fast, Compression::Default, Compression::Best] {
            let mut out = Vec::new();
            write_png_rgba8(&mut out, w, h, &rgba, c).unwrap();
            let t = load_png(&out).unwrap();
            let texels: Vec<u32> = rgba
                .chunks_exact(4)
                .map(|p| rgba8_to_argb([p[0], p[1], p[2], p[3]]))
                .collect();
            assert_eq!(t.levels()[0].texels, texels, "{c:?}");
            sizes.push(out.len());
        }
        assert!(sizes[1] < sizes[0], "zlib beats fdeflate: {sizes:?}");
        assert_eq!(encode_png_rgba8(w, h, &rgba).unwrap().len(), sizes[0]);
    }

    #[test]
    fn png_expands_gray_16bit_and_palette() {
        // 16-bit grey: the high byte survives.
        let bytes = encode_with(
            2,
            1,
            ColorType::Grayscale,
            BitDepth::Sixteen,
            None,
            &[0x12, 0x34, 0xAB, 0xCD],
        );
        let t = load_png(&bytes).unwrap();
        assert_eq!(t.levels()[0].texels, vec![0xFF12_1212, 0xFFAB_ABAB]);
        // 1-bit grey expands to 0 / 255.
        let bytes = encode_with(
            3,
            1,
            ColorType::Grayscale,
            BitDepth::One,
            None,
            &[0b1010_0000],
        );
        let t = load_png(&bytes).unwrap();
        assert_eq!(
            t.levels()[0].texels,
            vec![0xFFFF_FFFF, 0xFF00_0000, 0xFFFF_FFFF]
        );
        // Grey + alpha.
        let bytes = encode_with(
            1,
            1,
            ColorType::GrayscaleAlpha,
            BitDepth::Eight,
            None,
            &[0x40, 0x80],
        );
        assert_eq!(
            load_png(&bytes).unwrap().levels()[0].texels,
            vec![0x8040_4040]
        );
        // RGB without alpha.
        let bytes = encode_with(1, 1, ColorType::Rgb, BitDepth::Eight, None, &[1, 2, 3]);
        assert_eq!(
            load_png(&bytes).unwrap().levels()[0].texels,
            vec![0xFF01_0203]
        );
        // Palette with tRNS for the first entry only, 2-bit indices.
        let plte = [10, 20, 30, 40, 50, 60];
        let trns = [0x33];
        let bytes = encode_with(
            2,
            1,
            ColorType::Indexed,
            BitDepth::Two,
            Some((&plte, &trns)),
            &[0b0001_0000],
        );
        let t = load_png(&bytes).unwrap();
        assert_eq!(t.levels()[0].texels, vec![0x330A_141E, 0xFF28_323C]);
    }

    #[test]
    fn png_errors_without_panic() {
        let good = encode_png_rgba8(4, 4, &[7u8; 64]).unwrap();
        // Every prefix is handled; one that cuts into the image data is an error (the png
        // crate tolerates a missing IEND chunk, the last 12 bytes).
        for n in 0..good.len() {
            let r = load_png(&good[..n]);
            assert!(n >= good.len() - 12 || r.is_err(), "prefix {n}");
        }
        let mut flipped = good.clone();
        for i in (8..flipped.len()).step_by(3) {
            flipped[i] ^= 0x5A;
            let _ = load_png(&flipped);
        }
        assert!(matches!(
            load_png(b"garbage"),
            Err(ImageError::PngDecode(_))
        ));
        let e = encode_png_rgba8(2, 2, &[0; 15]).unwrap_err();
        assert!(matches!(
            e,
            ImageError::BufferSize {
                expected: Some(16),
                actual: 15,
                ..
            }
        ));
        assert!(matches!(
            encode_png_rgba8(0, 2, &[]),
            Err(ImageError::Unsupported { .. })
        ));
    }

    #[test]
    fn png_size_limit_is_checked_before_decoding() {
        // A 20000x1 grey image: the header alone must be enough to reject it.
        let bytes = encode_with(
            20000,
            1,
            ColorType::Grayscale,
            BitDepth::One,
            None,
            &[0u8; 2500],
        );
        let e = load_png(&bytes).unwrap_err();
        assert!(
            matches!(
                e,
                ImageError::Texture(TextureError::TooLarge {
                    width: 20000,
                    height: 1,
                    ..
                })
            ),
            "{e}"
        );
        assert!(e.to_string().contains("20000x1"));
    }
}

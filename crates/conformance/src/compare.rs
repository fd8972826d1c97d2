//! Comparing pointillist's image with the device's (SPEC 7's tolerances), and the magnified
//! difference image the report shows.

use pointillist_core::tolerance::{Tolerance, channel_difference};

use crate::runner::Image;

/// pointillist's image of a case, and where its sprites sample by points (SPEC 7,
/// `pointillist_core::tolerance::sprite_texel_edges`) the images of the same draws with sprite
/// coordinates nudged by `SPRITE_TEXEL_NUDGES`: a device pixel may match any of them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Drawn {
    /// The image under pointillist's rules.
    pub image: Image,
    /// The nudged images; empty where no sprite samples by points.
    pub nudged: Vec<Image>,
}

impl From<Image> for Drawn {
    fn from(image: Image) -> Drawn {
        Drawn {
            image,
            nudged: Vec::new(),
        }
    }
}

/// How two images of one case differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comparison {
    /// Pixels with a channel further apart than the tolerance.
    pub pixels_differing: u64,
    /// The largest difference of one channel over the whole image, in 1/255 steps.
    pub max_channel_difference: u8,
    /// Pixels that match only a nudged image: within `2^-6` of a texel edge, the device took the
    /// neighbouring texel (SPEC 7).
    pub neighbour_texels: u64,
    /// The first pixel beyond the tolerance, with pointillist's and the device's RGBA there.
    pub first: Option<(u32, u32, [u8; 4], [u8; 4])>,
    /// The magnified difference image.
    pub diff: Image,
    /// How many times the difference image is magnified.
    pub scale: u32,
}

/// The magnification that shows a `width` x `height` image at about 256 pixels across its
/// larger side: 1 to 16.
pub fn scale_for(width: u32, height: u32) -> u32 {
    (256 / width.max(height).max(1)).clamp(1, 16)
}

/// Compares `ours` (pointillist) with `theirs` (the device), same size, channel by channel
/// (alpha included); a pixel's difference is the smallest of pointillist's image's and the
/// nudged images' ([`Drawn`]). The difference image is magnified by [`scale_for`]: a pixel
/// that is equal shows pointillist's colour at a quarter of its brightness, one within the
/// tolerance dark yellow, one beyond it red, brighter the larger the difference.
pub fn compare(ours: &Drawn, theirs: &Image, tolerance: Tolerance) -> Comparison {
    let (w, h) = (ours.image.width, ours.image.height);
    let scale = scale_for(w, h);
    let limit = tolerance.steps();
    let mut pixels_differing = 0;
    let mut neighbour_texels = 0;
    let mut max_channel_difference = 0;
    let mut first = None;
    let mut marks = Vec::with_capacity(w as usize * h as usize * 4);
    let pixel = |p: &[u8]| u32::from_le_bytes([p[0], p[1], p[2], p[3]]);
    let apart = |a: &[u8], b: &[u8]| channel_difference(pixel(a), pixel(b));
    for (i, (a, b)) in ours
        .image
        .rgba
        .chunks_exact(4)
        .zip(theirs.rgba.chunks_exact(4))
        .enumerate()
    {
        let own = apart(a, b);
        let mut d = own;
        for n in &ours.nudged {
            d = d.min(apart(&n.rgba[i * 4..i * 4 + 4], b));
        }
        if own > limit && d <= limit {
            neighbour_texels += 1;
        }
        max_channel_difference = max_channel_difference.max(d);
        let mark = if d == 0 {
            [a[0] / 4, a[1] / 4, a[2] / 4, 255]
        } else if d <= limit {
            [128, 128, 0, 255]
        } else {
            pixels_differing += 1;
            if first.is_none() {
                let (x, y) = (i as u32 % w, i as u32 / w);
                first = Some((x, y, [a[0], a[1], a[2], a[3]], [b[0], b[1], b[2], b[3]]));
            }
            [128 + d / 2, 0, 0, 255]
        };
        marks.extend_from_slice(&mark);
    }
    let (dw, dh) = (w * scale, h * scale);
    // Only small images are magnified; a large one is shown as it is, without a copy.
    let rgba = if scale == 1 {
        marks
    } else {
        let mut rgba = Vec::with_capacity(dw as usize * dh as usize * 4);
        for y in 0..dh {
            for x in 0..dw {
                let at = (y / scale * w + x / scale) as usize * 4;
                rgba.extend_from_slice(&marks[at..at + 4]);
            }
        }
        rgba
    };
    Comparison {
        pixels_differing,
        neighbour_texels,
        max_channel_difference,
        first,
        diff: Image {
            width: dw,
            height: dh,
            rgba,
        },
        scale,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, px: &[[u8; 4]]) -> Image {
        Image {
            width: w,
            height: h,
            rgba: px.concat(),
        }
    }

    #[test]
    fn counts_pixels_beyond_the_tolerance_and_the_largest_difference() {
        let a = image(
            2,
            2,
            &[[0, 0, 0, 255], [8, 8, 8, 255], [1, 2, 3, 4], [9, 9, 9, 9]],
        );
        let b = image(
            2,
            2,
            &[[0, 0, 0, 255], [9, 8, 8, 255], [1, 2, 3, 40], [9, 9, 9, 9]],
        );
        let a = Drawn::from(a);
        let exact = compare(&a, &b, Tolerance::Exact);
        assert_eq!(exact.pixels_differing, 2);
        assert_eq!(exact.max_channel_difference, 36, "alpha counts");
        assert_eq!(exact.first, Some((1, 0, [8, 8, 8, 255], [9, 8, 8, 255])));
        let one = compare(&a, &b, Tolerance::Steps(1));
        assert_eq!(one.pixels_differing, 1);
        assert_eq!(one.first.map(|f| (f.0, f.1)), Some((0, 1)));
        // 2x2 is shown 16 times larger; the pixel within the tolerance is dark yellow, the
        // one beyond it red.
        assert_eq!((one.scale, one.diff.width, one.diff.height), (16, 32, 32));
        let at = |x: usize, y: usize| &one.diff.rgba[(y * 32 + x) * 4..][..4];
        assert_eq!(at(31, 0), [128, 128, 0, 255]);
        assert_eq!(at(0, 31), [146, 0, 0, 255]);
        assert_eq!(at(15, 15), [0, 0, 0, 255]);
        assert_eq!(at(16, 16), [2, 2, 2, 255]);
    }

    /// SPEC 7: a pixel that matches a nudged image only (a sprite pixel whose device took the
    /// neighbouring texel) is within the tolerance and counted; the others are compared as
    /// before.
    #[test]
    fn a_pixel_may_match_a_nudged_image() {
        let ours = Drawn {
            image: image(3, 1, &[[0, 0, 0, 255], [10, 0, 0, 255], [20, 0, 0, 255]]),
            nudged: vec![
                image(3, 1, &[[0, 0, 0, 255], [50, 0, 0, 255], [20, 0, 0, 255]]),
                image(3, 1, &[[0, 0, 0, 255], [10, 0, 0, 255], [90, 0, 0, 255]]),
            ],
        };
        let theirs = image(3, 1, &[[0, 0, 0, 255], [50, 0, 0, 255], [70, 0, 0, 255]]);
        let c = compare(&ours, &theirs, Tolerance::Exact);
        assert_eq!((c.pixels_differing, c.neighbour_texels), (1, 1));
        assert_eq!(c.first, Some((2, 0, [20, 0, 0, 255], [70, 0, 0, 255])));
        assert_eq!(
            c.max_channel_difference, 20,
            "the nearest image's difference"
        );
    }

    #[test]
    fn magnification_keeps_large_images_as_they_are() {
        assert_eq!(scale_for(1, 1), 16);
        assert_eq!(scale_for(64, 16), 4);
        assert_eq!(scale_for(100, 30), 2);
        assert_eq!(scale_for(640, 480), 1);
    }
}

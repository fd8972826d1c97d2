//! What a point looks like and what its size is measured in: `marker` and `size_units`.
//!
//! A square is D3D9's point as it is (SPEC 4.1). A circle is the same square drawn as a point
//! sprite (POINTSPRITEENABLE, SPEC 4.3) showing [`disc`], an antialiased disc inscribed in the
//! sprite, through the texture path every other textured draw takes: its mip chain (box
//! filtered, SPEC 5.2) is sampled trilinearly (MIN, MAG and MIPFILTER LINEAR), so a small disc
//! shows its coverage averaged rather than a few sampled texels. The pixels are those of a
//! scene drawing the same texture and states: exact, deterministic, the same on Dask.

use std::sync::{Arc, OnceLock};

use pointillist_core::texture::Texture;

use crate::{Blend, PlotError};

/// The shape a point is drawn as.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum Marker {
    /// The D3D9 point: a square of `size` pixels.
    #[default]
    Square,
    /// An antialiased disc of diameter `size` (the square's side), drawn as a sprite.
    Circle,
}

impl Marker {
    /// Every marker.
    pub const ALL: [Marker; 2] = [Marker::Square, Marker::Circle];

    /// The marker named `name` (`"square"`, `"circle"`).
    pub fn from_name(name: &str) -> Result<Marker, PlotError> {
        named(&Self::ALL, Self::name, "marker", name)
    }

    /// The marker's name.
    pub fn name(self) -> &'static str {
        match self {
            Marker::Square => "square",
            Marker::Circle => "circle",
        }
    }
}

/// What a point's size is measured in.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum SizeUnits {
    /// Pixels of the target (D3D9's POINTSIZE and PSIZE of a pre-transformed vertex).
    #[default]
    Pixels,
    /// Units of x's data range: `pixels = size * (width / (x_hi - x_lo))`, the scale of the
    /// one formula that maps x ([`crate::axes`]), computed in f64 and rounded once to f32.
    Data,
}

impl SizeUnits {
    /// Both units.
    pub const ALL: [SizeUnits; 2] = [SizeUnits::Pixels, SizeUnits::Data];

    /// The units named `name` (`"pixels"`, `"data"`).
    pub fn from_name(name: &str) -> Result<SizeUnits, PlotError> {
        named(&Self::ALL, Self::name, "size_units", name)
    }

    /// The units' name.
    pub fn name(self) -> &'static str {
        match self {
            SizeUnits::Pixels => "pixels",
            SizeUnits::Data => "data",
        }
    }
}

/// The one of `all` whose name is `name`, or an error naming the argument `arg` and listing
/// the names.
fn named<T: Copy>(
    all: &[T],
    name_of: fn(T) -> &'static str,
    arg: &str,
    name: &str,
) -> Result<T, PlotError> {
    all.iter()
        .copied()
        .find(|&v| name_of(v) == name)
        .ok_or_else(|| {
            let names: Vec<String> = all.iter().map(|&v| format!("{:?}", name_of(v))).collect();
            PlotError::Value(format!(
                "{arg} must be {}; got {name:?}",
                names.join(" or ")
            ))
        })
}

/// Side of the disc texture's level 0, in texels.
pub const DISC_SIZE: u32 = 64;

/// The sprite a circle marker shows with `blend`: a `DISC_SIZE` square texture whose texel at
/// centre `(i + 0.5, j + 0.5)` covers `c = clamp(R + 0.5 - d, 0, 1)` of the disc of radius
/// `R = DISC_SIZE / 2` about the texture's centre, `d` the distance between the two centres (a
/// one-texel ramp across the edge), as a byte `round(255 c)`. Its colour is white with alpha
/// `c` for "alpha" and "replace" (which drop the outside with the alpha test, ALPHAREF 128),
/// and `c` in every channel for "add" and "max", whose ONE factors ignore alpha, so that
/// outside the disc adds nothing and the edge adds its share.
pub fn disc(blend: Blend) -> Texture {
    let n = DISC_SIZE;
    let r = f64::from(n) / 2.0;
    let texels = (0..n * n)
        .map(|k| {
            let (i, j) = (f64::from(k % n) + 0.5, f64::from(k / n) + 0.5);
            let d = ((i - r).powi(2) + (j - r).powi(2)).sqrt();
            let c = (255.0 * (r + 0.5 - d).clamp(0.0, 1.0)).round() as u32;
            match blend {
                Blend::Add | Blend::Max => c * 0x0101_0101,
                Blend::Alpha | Blend::Replace => (c << 24) | 0x00FF_FFFF,
            }
        })
        .collect();
    Texture::from_argb(n, n, texels).expect("a 64x64 texture is within every limit")
}

/// [`disc`] for `blend`, made once a process for each of its two colourings (premultiplied for
/// "add" and "max", white for "alpha" and "replace") and shared by every draw and tile.
pub(crate) fn shared_disc(blend: Blend) -> Arc<Texture> {
    static DISCS: [OnceLock<Arc<Texture>>; 2] = [OnceLock::new(), OnceLock::new()];
    let premultiplied = matches!(blend, Blend::Add | Blend::Max);
    DISCS[usize::from(premultiplied)]
        .get_or_init(|| Arc::new(disc(blend)))
        .clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_disc_is_round_symmetric_and_antialiased() {
        for blend in Blend::ALL {
            let t = disc(blend);
            let level = &t.levels()[0];
            let at = |x: u32, y: u32| level.texels[(y * DISC_SIZE + x) as usize];
            let alpha = |x: u32, y: u32| at(x, y) >> 24;
            let last = DISC_SIZE - 1;
            assert_eq!(alpha(32, 32), 255, "{blend:?}: the centre is covered");
            assert_eq!(alpha(0, 0), 0, "{blend:?}: the corners are not");
            assert_eq!(alpha(last, last), 0);
            for y in 0..DISC_SIZE {
                for x in 0..DISC_SIZE {
                    let v = at(x, y);
                    assert_eq!(v, at(last - x, y), "mirrored left-right");
                    assert_eq!(v, at(x, last - y), "mirrored top-bottom");
                    assert_eq!(v, at(y, x), "mirrored about the diagonal");
                }
            }
            let edge = (0..DISC_SIZE)
                .flat_map(|y| (0..DISC_SIZE).map(move |x| (x, y)))
                .filter(|&(x, y)| (1..255).contains(&alpha(x, y)))
                .count();
            assert!(
                edge > 100,
                "{blend:?}: an antialiased edge of {edge} texels"
            );
            let premultiplied = matches!(blend, Blend::Add | Blend::Max);
            let (r, a) = (at(0, 0) & 0xFF, alpha(0, 0));
            assert_eq!(r == a, premultiplied, "{blend:?}: colour of the outside");
        }
    }

    /// One 40-pixel circle at the centre of a 64x64 plot: the centre is the point's colour,
    /// the square's corners are the clear colour, the edge is in between, and the picture is
    /// symmetric; in data units, size 4 on a 0..16 range of 64 pixels is the same circle.
    #[test]
    fn a_circle_is_a_disc_and_data_units_scale_by_the_x_range() {
        use crate::{Colors, Column, DataRange, Plot, Points, Sizes};
        let draw = |plot: &Plot, x: f32, size: f32| {
            let xs = [x];
            let points = Points {
                size: Sizes::Constant(size),
                color: Colors::Constant(0xFFFF_FFFF),
                ..Points::new(Column::F32(&xs), Column::F32(&xs))
            };
            plot.render(&points).unwrap()
        };
        for blend in Blend::ALL {
            let plot = Plot {
                blend,
                marker: Marker::Circle,
                ..Plot::new(64, 64)
            };
            let rgba = draw(&plot, 31.5, 40.0);
            let red = |x: usize, y: usize| rgba[(y * 64 + x) * 4];
            assert_eq!(red(32, 32), 255, "{blend:?}: centre");
            assert_eq!(red(13, 13), 0, "{blend:?}: the square's corner");
            assert_eq!(red(31, 14), 255, "{blend:?}: inside the top edge");
            let edge = (0..64).filter(|&x| (1..255).contains(&red(x, 18))).count();
            let expect_edge = blend != Blend::Replace;
            assert_eq!(edge > 0, expect_edge, "{blend:?}: an antialiased edge");
            for y in 0..64 {
                for x in 0..64 {
                    assert_eq!(red(x, y), red(63 - x, y), "{blend:?} ({x}, {y})");
                    assert_eq!(red(x, y), red(y, x), "{blend:?} ({x}, {y})");
                }
            }
            let data = Plot {
                size_units: SizeUnits::Data,
                x_range: Some(DataRange { lo: 0.0, hi: 16.0 }),
                y_range: Some(DataRange { lo: 0.0, hi: 16.0 }),
                ..plot.clone()
            };
            // x = 8 maps to pixel 31.5 on both axes (y upwards, the range square).
            assert_eq!(
                draw(&data, 8.0, 10.0),
                rgba,
                "{blend:?}: 10 units of 16 on 64 px"
            );
        }
        let textured = Plot {
            marker: Marker::Circle,
            texture: Some(Arc::new(disc(Blend::Add))),
            ..Plot::new(8, 8)
        };
        assert!(textured.check_marker().is_err());
        let unranged = Plot {
            size_units: SizeUnits::Data,
            ..Plot::new(8, 8)
        };
        let e = unranged.check_marker().unwrap_err().to_string();
        assert!(e.contains("x_range and y_range"), "{e}");
    }

    #[test]
    fn names_round_trip_and_unknown_ones_are_refused() {
        for m in Marker::ALL {
            assert_eq!(Marker::from_name(m.name()).unwrap(), m);
        }
        for u in SizeUnits::ALL {
            assert_eq!(SizeUnits::from_name(u.name()).unwrap(), u);
        }
        let e = Marker::from_name("disc").unwrap_err().to_string();
        assert!(e.contains("marker") && e.contains("\"disc\""), "{e}");
        let e = SizeUnits::from_name("points").unwrap_err().to_string();
        assert!(e.contains("size_units"), "{e}");
    }
}

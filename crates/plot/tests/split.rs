//! Drawing one set of points in parts gives the pixels of drawing them at once: partial images
//! combined for the presets that commute, screen tiles for every draw.

use std::sync::Arc;

use pointillist_core::point::PixelRect;
use pointillist_core::texture::Texture;
use pointillist_plot::tiles::{TileBin, Tiles};
use pointillist_plot::{Blend, Colors, Column, DataRange, Plot, Points, Sizes};
use proptest::prelude::*;

/// Columns of `n` points from a fixed sequence: positions in data units over `[-0.1, 1.1]`
/// (so some squares hang over the target's edges), fractional sizes up to `max_size`, colours
/// with every alpha, depths in `[0, 1]`.
struct Columns {
    x: Vec<f64>,
    y: Vec<f32>,
    z: Vec<f32>,
    size: Vec<f32>,
    color: Vec<u32>,
}

fn columns(n: usize, seed: u64, max_size: f32) -> Columns {
    let mut s = seed;
    let mut next = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 40) as f64 / (1u64 << 24) as f64
    };
    let mut c = Columns {
        x: Vec::new(),
        y: Vec::new(),
        z: Vec::new(),
        size: Vec::new(),
        color: Vec::new(),
    };
    for _ in 0..n {
        c.x.push(next() * 1.2 - 0.1);
        c.y.push((next() * 1.2 - 0.1) as f32);
        c.z.push(next() as f32);
        c.size.push((next() * f64::from(max_size)) as f32);
        c.color.push((next() * f64::from(u32::MAX)) as u32);
    }
    c
}

impl Columns {
    fn points(&self, rows: std::ops::Range<usize>, depth: bool) -> Points<'_> {
        Points {
            x: Column::F64(&self.x[rows.clone()]),
            y: Column::F32(&self.y[rows.clone()]),
            z: depth.then(|| Column::F32(&self.z[rows.clone()])),
            size: Sizes::PerPoint(Column::F32(&self.size[rows.clone()])),
            color: Colors::Argb(&self.color[rows]),
        }
    }
}

fn plot(blend: Blend, width: u32, height: u32) -> Plot {
    let range = Some(DataRange { lo: 0.0, hi: 1.0 });
    Plot {
        blend,
        clear: 0xC0_30_60_90,
        x_range: range,
        y_range: range,
        ..Plot::new(width, height)
    }
}

/// A 5x3 texture with texels of every alpha, so that sprite coordinates (SPEC 4.3) show.
fn texture() -> Arc<Texture> {
    let texels = (0..15u32)
        .map(|i| i.wrapping_mul(0x1327_5B3D) | 0x10)
        .collect();
    Arc::new(Texture::from_argb(5, 3, texels).unwrap())
}

/// Splits rows `0..n` at `cuts` (sorted, inside `0..=n`).
fn parts(n: usize, cuts: &[usize]) -> Vec<std::ops::Range<usize>> {
    let mut bounds = vec![0];
    bounds.extend(cuts.iter().copied());
    bounds.push(n);
    bounds.windows(2).map(|w| w[0]..w[1]).collect()
}

/// The image of `parts` of `c` binned part by part into `tiles`, each tile's pieces merged in
/// index order and drawn, the tiles assembled.
fn tiled(
    plot: &Plot,
    c: &Columns,
    parts: &[std::ops::Range<usize>],
    depth: bool,
    tiles: &Tiles,
) -> Vec<u8> {
    let pieces: Vec<Vec<TileBin>> = parts
        .iter()
        .map(|r| {
            plot.bin(&c.points(r.clone(), depth), r.start as u64, tiles)
                .unwrap()
        })
        .collect();
    let layout = c.points(0..0, depth).layout();
    let stride = layout.stride();
    let width = plot.width as usize;
    let mut image = vec![0u8; width * plot.height as usize * 4];
    for t in 0..tiles.len() {
        let mut vertices = Vec::new();
        let mut last = None;
        for piece in &pieces {
            let bin = &piece[t];
            for (k, &i) in bin.index.iter().enumerate() {
                assert!(last < Some(i), "pieces arrive in index order");
                last = Some(i);
                vertices.extend_from_slice(&bin.vertices[k * stride..(k + 1) * stride]);
            }
        }
        let rect = tiles.rect(t);
        let tile = plot.render_tile(&layout, &vertices, rect).unwrap();
        let w = (rect.x1 - rect.x0) as usize * 4;
        for (j, row) in tile.chunks_exact(w).enumerate() {
            let o = ((rect.y0 as usize + j) * width + rect.x0 as usize) * 4;
            image[o..o + w].copy_from_slice(row);
        }
    }
    image
}

#[test]
fn tiles_give_the_pixels_of_the_full_draw_for_every_preset() {
    let c = columns(3000, 11, 9.0);
    let tiles = Tiles::new(61, 47, 8, 5).unwrap();
    for blend in Blend::ALL {
        for depth in [false, true] {
            for tex in [None, Some(texture())] {
                let plot = Plot {
                    texture: tex.clone(),
                    ..plot(blend, 61, 47)
                };
                let full = plot.render(&c.points(0..3000, depth)).unwrap();
                let split = tiled(&plot, &c, &parts(3000, &[700, 701, 2222]), depth, &tiles);
                assert!(
                    full == split,
                    "{blend:?} depth {depth} texture {}",
                    tex.is_some()
                );
            }
        }
    }
}

/// Squares whose edges fall within a float step of a tile boundary: the left edge `X - S/2`
/// rounds to the boundary `e` in the target's coordinates but not in the tile's (`X - e` is
/// exact and small), so a tile that moved its points into its own coordinates would cover
/// other pixels. The tiles draw them as the full target does.
#[test]
fn squares_straddling_tile_edges_cover_the_same_pixels() {
    let mut x = Vec::new();
    let mut y = Vec::new();
    let mut size = Vec::new();
    let mut moved_differs = 0;
    for (k, e) in [16.0f32, 32.0, 48.0, 64.0].into_iter().enumerate() {
        for a in [0.5f32, 1.0, 1.5] {
            for j in -3i32..=3 {
                for i in 0..6 {
                    let cx = e + a + j as f32 * 2f32.powi(-19);
                    let s = 2.0 * a - i as f32 * 2f32.powi(-23);
                    let cy = 80.0 - cx + (k as f32) * 0.25;
                    x.push(cx);
                    y.push(cy);
                    size.push(s);
                    let left = (cx - s / 2.0).ceil();
                    let moved = ((cx - e) - s / 2.0).ceil() + e;
                    moved_differs += usize::from(left != moved);
                }
            }
        }
    }
    assert!(moved_differs > 20, "only {moved_differs} edges would move");
    let n = x.len() as u32;
    let color: Vec<u32> = (0..n)
        .map(|k| 0x3000_0000 | k.wrapping_mul(0x9E37_79B9) >> 8)
        .collect();
    for blend in Blend::ALL {
        let plot = Plot {
            blend,
            ..Plot::new(80, 80)
        };
        let points = Points {
            x: Column::F32(&x),
            y: Column::F32(&y),
            z: None,
            size: Sizes::PerPoint(Column::F32(&size)),
            color: Colors::Argb(&color),
        };
        let full = plot.render(&points).unwrap();
        let tiles = Tiles::new(80, 80, 16, 16).unwrap();
        let bins = plot.bin(&points, 0, &tiles).unwrap();
        let layout = points.layout();
        let mut image = vec![0u8; 80 * 80 * 4];
        for (t, bin) in bins.iter().enumerate() {
            let rect = tiles.rect(t);
            let tile = plot.render_tile(&layout, &bin.vertices, rect).unwrap();
            for (j, row) in tile.chunks_exact(16 * 4).enumerate() {
                let o = ((rect.y0 as usize + j) * 80 + rect.x0 as usize) * 4;
                image[o..o + 64].copy_from_slice(row);
            }
        }
        assert!(full == image, "{blend:?}");
    }
}

#[test]
fn each_point_goes_to_the_tiles_its_square_covers_and_no_other() {
    // Size 3 at 9.0: covers 7.5..10.5, pixels 8, 9, 10: tiles 0 and 1 of width 10 across.
    // Size 1 at 9.5: [9, 10) covers 9 only. Size 0.4 at 9.5 covers nothing.
    let x = [9.0f32, 9.5, 9.5, 35.0];
    let y = [2.0f32, 2.0, 2.0, 2.0];
    let s = [3.0f32, 1.0, 0.4, 1.0];
    let plot = Plot::new(30, 10);
    let points = Points {
        size: Sizes::PerPoint(Column::F32(&s)),
        ..Points::new(Column::F32(&x), Column::F32(&y))
    };
    let tiles = Tiles::new(30, 10, 10, 10).unwrap();
    let bins = plot.bin(&points, 100, &tiles).unwrap();
    assert_eq!(bins[0].index, [100, 101]);
    assert_eq!(bins[1].index, [100]);
    assert!(bins[2].index.is_empty(), "x = 35 is off the target");
    assert_eq!(bins[0].vertices.len(), 2 * 6);
    assert_eq!(
        tiles.rect(2),
        PixelRect {
            x0: 20,
            y0: 0,
            x1: 30,
            y1: 10
        }
    );
}

#[test]
fn behaviours_reach_every_path_of_a_draw() {
    // Size 0.4 at 9.5 covers nothing by default; minimum_size=one_pixel draws it as size 1,
    // pixel 9. The device, the counts, partial images and tiles all see the switch.
    let x = [9.5f32, 9.5, 3.5];
    let y = [2.5f32, 2.5, 7.5];
    let s = [0.4f32, 0.4, 0.25];
    let mut plot = Plot {
        clear: 0xFF00_0000,
        ..Plot::new(20, 10)
    };
    let lit = |rgba: &[u8]| -> Vec<(usize, [u8; 4])> {
        rgba.chunks_exact(4)
            .enumerate()
            .filter(|(_, p)| p[..3] != [0, 0, 0])
            .map(|(i, p)| (i, p.try_into().unwrap()))
            .collect()
    };
    for (option, expected) in [
        ("none", vec![]),
        (
            "one_pixel",
            vec![
                (2 * 20 + 9, [0x20, 0x40, 0x60, 0xFF]),
                (7 * 20 + 3, [0x10, 0x20, 0x30, 0xFF]),
            ],
        ),
    ] {
        plot.behaviours.set("minimum_size", option).unwrap();
        let constant = Points {
            size: Sizes::PerPoint(Column::F32(&s)),
            color: Colors::Constant(0xFF10_2030),
            ..Points::new(Column::F32(&x), Column::F32(&y))
        };
        // Counted: one colour, no depth.
        assert!(plot.counts(&constant).unwrap().is_some());
        assert_eq!(lit(&plot.render(&constant).unwrap()), expected, "{option}");
        let mut device = vec![0u8; 20 * 10 * 4];
        plot.render_on_device(&constant, &mut device).unwrap();
        assert_eq!(lit(&device), expected, "{option} on the device");
        let mut image = plot.partial().render(&constant).unwrap();
        plot.finish(&mut image).unwrap();
        assert_eq!(lit(&image), expected, "{option} partial");
        let tiles = Tiles::new(20, 10, 8, 8).unwrap();
        let bins = plot.bin(&constant, 0, &tiles).unwrap();
        let mut tiled = vec![0u8; 20 * 10 * 4];
        for (t, bin) in bins.iter().enumerate() {
            let r = tiles.rect(t);
            let tile = plot
                .render_tile(&constant.layout(), &bin.vertices, r)
                .unwrap();
            let w = (r.x1 - r.x0) as usize * 4;
            for (j, row) in tile.chunks_exact(w).enumerate() {
                let o = ((r.y0 as usize + j) * 20 + r.x0 as usize) * 4;
                tiled[o..o + w].copy_from_slice(row);
            }
        }
        assert_eq!(lit(&tiled), expected, "{option} tiled");
    }
}

#[test]
fn partial_images_combine_to_the_full_draw_for_add_and_max() {
    // Big squares and bright colours so that additions saturate.
    let c = columns(4000, 5, 14.0);
    for blend in [Blend::Add, Blend::Max] {
        for tex in [None, Some(texture())] {
            let plot = Plot {
                texture: tex,
                ..plot(blend, 50, 40)
            };
            let full = plot.render(&c.points(0..4000, false)).unwrap();
            let partial = plot.partial();
            let images: Vec<Vec<u8>> = parts(4000, &[1, 1000, 1000, 3999])
                .into_iter()
                .map(|r| partial.render(&c.points(r, false)).unwrap())
                .collect();
            // A tree: ((0 1) (2 (3 4))), combined in an order unlike the points'.
            let mut a = images[1].clone();
            blend.combine(&mut a, &images[0]).unwrap();
            let mut b = images[4].clone();
            blend.combine(&mut b, &images[3]).unwrap();
            blend.combine(&mut b, &images[2]).unwrap();
            blend.combine(&mut b, &a).unwrap();
            plot.finish(&mut b).unwrap();
            assert!(full == b, "{blend:?}");
            if blend == Blend::Add {
                let saturated = full.iter().filter(|&&v| v == 255).count();
                assert!(saturated > full.len() / 2, "{saturated} channels saturated");
            }
        }
    }
}

#[test]
fn order_dependent_images_refuse_to_combine() {
    let mut a = vec![0u8; 8];
    for blend in [Blend::Alpha, Blend::Replace] {
        let e = blend.combine(&mut a, &[0u8; 8]).unwrap_err().to_string();
        assert!(e.contains("depends on the order"), "{e}");
    }
    let e = Blend::Add
        .combine(&mut a, &[0u8; 4])
        .unwrap_err()
        .to_string();
    assert_eq!(e, "images of 8 and 4 bytes differ in size");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn any_tiling_of_any_split_is_exact(
        seed in any::<u64>(),
        tw in 1u32..40,
        th in 1u32..30,
        cut in 0usize..600,
        blend in 0usize..4,
        depth in any::<bool>(),
    ) {
        let c = columns(600, seed, 12.0);
        let plot = plot(Blend::ALL[blend], 37, 29);
        let tiles = Tiles::new(37, 29, tw, th).unwrap();
        let full = plot.render(&c.points(0..600, depth)).unwrap();
        let split = tiled(&plot, &c, &parts(600, &[cut]), depth, &tiles);
        prop_assert!(full == split);
    }
}

/// The points of `c` in `rows` with one colour and constant or per-point sizes.
fn one_colour<'a>(c: &'a Columns, rows: std::ops::Range<usize>, per_point: bool) -> Points<'a> {
    Points {
        size: if per_point {
            Sizes::PerPoint(Column::F32(&c.size[rows.clone()]))
        } else {
            Sizes::Constant(2.5)
        },
        color: Colors::Constant(0x80_40_C0_10),
        ..c.points(rows, false)
    }
}

#[test]
fn counts_of_parts_added_give_the_pixels_of_the_full_draw() {
    // 20 000 points of up to 6 pixels on 16x12: many pixels are covered more than 255 times,
    // so the saturation of the counts and of their sums is exercised.
    let c = columns(20_000, 11, 6.0);
    let n = c.x.len();
    for blend in [Blend::Add, Blend::Max, Blend::Replace] {
        for per_point in [false, true] {
            let plot = plot(blend, 16, 12);
            let want = plot.render(&one_colour(&c, 0..n, per_point)).unwrap();
            let full = plot
                .counts(&one_colour(&c, 0..n, per_point))
                .unwrap()
                .unwrap();
            assert!(full.iter().filter(|&&k| k == 255).count() > 20);
            // Parts added in reverse order: counts add in any order.
            let mut sum = vec![0u8; 16 * 12];
            for rows in parts(n, &[0, 3, 7_000, 7_001, 15_000]).into_iter().rev() {
                let counts = plot
                    .counts(&one_colour(&c, rows, per_point))
                    .unwrap()
                    .unwrap();
                Plot::add_counts(&mut sum, &counts).unwrap();
            }
            assert_eq!(sum, full, "{blend:?} {per_point}");
            let empty = one_colour(&c, 0..0, per_point);
            assert_eq!(plot.from_counts(&empty, &sum).unwrap(), want, "{blend:?}");
        }
    }
    // Not counted: colour columns, depth, a texture, alpha; wrong sizes are errors.
    let plot = plot(Blend::Add, 16, 12);
    assert_eq!(plot.counts(&c.points(0..n, false)).unwrap(), None);
    let textured = Plot {
        texture: Some(texture()),
        ..plot.clone()
    };
    assert_eq!(textured.counts(&one_colour(&c, 0..n, false)).unwrap(), None);
    let alpha = Plot {
        blend: Blend::Alpha,
        ..plot.clone()
    };
    assert_eq!(alpha.counts(&one_colour(&c, 0..n, false)).unwrap(), None);
    assert!(
        alpha
            .from_counts(&one_colour(&c, 0..0, false), &[0; 192])
            .is_err()
    );
    assert!(
        plot.from_counts(&one_colour(&c, 0..0, false), &[0; 191])
            .is_err()
    );
    assert!(Plot::add_counts(&mut [0; 3], &[0; 4]).is_err());
    let mut s = [250u8, 0, 255];
    Plot::add_counts(&mut s, &[10, 7, 1]).unwrap();
    assert_eq!(s, [255, 7, 255]);
}

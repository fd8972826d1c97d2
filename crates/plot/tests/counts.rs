//! `Plot::render` counts draws of one colour straight from the columns (crates/plot/src/
//! counts.rs): it gives the pixels of the device's draw through the CPU backend
//! (`Plot::render_on_device`), bit for bit, on any number of threads.

use pointillist_plot::{Blend, Colors, Column, DataRange, Plot, PlotError, Points, Sizes};
use proptest::prelude::*;

fn on_device(plot: &Plot, points: &Points<'_>) -> Result<Vec<u8>, PlotError> {
    let mut out = vec![0u8; plot.width as usize * plot.height as usize * 4];
    plot.render_on_device(points, &mut out)?;
    Ok(out)
}

/// Values on the rules' edges: pixel boundaries and centres of a 32-pixel range, just off
/// them, outside the target, huge and infinite.
fn edge_value(k: u32) -> f64 {
    let special = [
        -1e300,
        -f64::INFINITY,
        f64::INFINITY,
        1e40,
        -0.5,
        1.5,
        f64::MIN_POSITIVE,
        -0.0,
        3.5e38,
    ];
    match k % 5 {
        0 => f64::from(k / 5 % 40) / 32.0 - 0.125,
        1 => (f64::from(k / 5 % 40) + 0.5) / 32.0 - 0.125,
        2 => f64::from(k / 5 % 40) / 32.0 - 0.125 + 1e-7,
        3 => f64::from(k / 5 % 40) / 32.0 - 0.125 - 1e-9,
        _ => special[(k / 5) as usize % special.len()],
    }
}

/// Sizes on the clamp's and the coverage rule's edges (SPEC 2.3, 4.1).
fn edge_size(k: u32) -> f32 {
    let sizes = [
        1.0,
        0.0,
        0.5,
        1.000_000_1,
        0.999_999_94,
        1.5,
        2.0,
        3.999,
        7.25,
        -1.0,
        f32::INFINITY,
        1e-40,
        9000.0,
    ];
    sizes[k as usize % sizes.len()]
}

fn blend(k: u8) -> Blend {
    Blend::ALL[usize::from(k) % Blend::ALL.len()]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn counted_draws_are_the_devices_pixels(
        xs in prop::collection::vec(any::<u32>(), 1..400),
        ys in prop::collection::vec(any::<u32>(), 400),
        sizes in prop::collection::vec(any::<u32>(), 400),
        colour in any::<u32>(),
        preset in any::<u8>(),
        per_point in any::<bool>(),
        f32_x in any::<bool>(),
        f32_y in any::<bool>(),
        ranges in any::<bool>(),
        width in 1u32..40,
        height in 1u32..40,
        clear in any::<u32>(),
        threads in 1usize..=4,
    ) {
        let n = xs.len();
        let scale = |v: f64, pixels: u32| if ranges { v } else { v * f64::from(pixels) };
        let x64: Vec<f64> = xs.iter().map(|&k| scale(edge_value(k), width)).collect();
        let x32: Vec<f32> = x64.iter().map(|&v| v as f32).collect();
        let y64: Vec<f64> = ys[..n].iter().map(|&k| scale(edge_value(k), height)).collect();
        let y32: Vec<f32> = y64.iter().map(|&v| v as f32).collect();
        let size: Vec<f32> = sizes[..n].iter().map(|&k| edge_size(k)).collect();
        let points = Points {
            x: if f32_x { Column::F32(&x32) } else { Column::F64(&x64) },
            y: if f32_y { Column::F32(&y32) } else { Column::F64(&y64) },
            z: None,
            size: if per_point {
                Sizes::PerPoint(Column::F32(&size))
            } else {
                Sizes::Constant(size[0])
            },
            color: Colors::Constant(colour),
        };
        let range = ranges.then_some(DataRange { lo: 0.0, hi: 1.0 });
        let plot = Plot {
            blend: blend(preset),
            clear,
            x_range: range,
            y_range: range,
            ..Plot::new(width, height)
        };
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let counted = pool.install(|| plot.render(&points)).unwrap();
        prop_assert!(counted == on_device(&plot, &points).unwrap());
    }
}

/// `n` points scattered over `-0.1..1.1` on both axes (a linear congruential sequence from
/// `seed`): with a `0..1` data range, some fall on the target's edges and off it.
fn scattered(n: usize, mut s: u64) -> (Vec<f32>, Vec<f32>) {
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    let x: Vec<f32> = (0..n).map(|_| next() * 1.2 - 0.1).collect();
    let y: Vec<f32> = (0..n).map(|_| next() * 1.2 - 0.1).collect();
    (x, y)
}

/// Enough points for several count images on 1 to 4 threads, most pixels saturated, some
/// points on the target's edges and off it, every preset.
#[test]
fn any_thread_count_gives_the_devices_pixels() {
    let (x, y) = scattered(700_000, 7);
    for (blend, colour) in [
        (Blend::Add, 0x0301_0204),
        (Blend::Max, 0x8040_2010),
        (Blend::Replace, 0x1234_5678),
    ] {
        let range = Some(DataRange { lo: 0.0, hi: 1.0 });
        let plot = Plot {
            blend,
            clear: 0xFF10_2030,
            x_range: range,
            y_range: range,
            ..Plot::new(61, 47)
        };
        let points = Points {
            color: Colors::Constant(colour),
            ..Points::new(Column::F32(&x), Column::F32(&y))
        };
        let reference = on_device(&plot, &points).unwrap();
        if blend == Blend::Add {
            let saturated = reference.iter().filter(|&&v| v == 255).count();
            assert!(
                saturated > reference.len() / 2,
                "{saturated} channels saturated"
            );
        }
        for threads in 1..=4 {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let image = pool.install(|| plot.render(&points)).unwrap();
            assert!(image == reference, "{blend:?} on {threads} threads");
        }
    }
}

/// `Plot::add_counts_of` counts parts of the points into one sum (the first thread into the sum
/// itself, others into images of their own): the counts of all the points, on any number of
/// threads, saturating on top of what the sum held.
#[test]
fn counts_of_parts_into_one_sum_on_any_thread_count() {
    let (x, y) = scattered(700_000, 11);
    let n = x.len();
    let range = Some(DataRange { lo: 0.0, hi: 1.0 });
    let plot = Plot {
        x_range: range,
        y_range: range,
        ..Plot::new(131, 97)
    };
    let part = |rows: std::ops::Range<usize>| Points {
        size: Sizes::Constant(1.5),
        color: Colors::Constant(0x0102_0304),
        ..Points::new(Column::F32(&x[rows.clone()]), Column::F32(&y[rows]))
    };
    let all = plot.counts(&part(0..n)).unwrap().unwrap();
    // Held before: 0 on most pixels, 200 on every seventh, where the sum saturates.
    let before: Vec<u8> = (0..all.len())
        .map(|i| if i % 7 == 0 { 200 } else { 0 })
        .collect();
    let want: Vec<u8> = before
        .iter()
        .zip(&all)
        .map(|(&b, &c)| b.saturating_add(c))
        .collect();
    assert!(all.iter().all(|&c| c < 255) && want.contains(&255));
    for threads in 1..=4 {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut sum = before.clone();
        for rows in [300_000..n, 0..1, 1..300_000] {
            assert!(
                pool.install(|| plot.add_counts_of(&part(rows), &mut sum))
                    .unwrap()
            );
        }
        assert!(sum == want, "{threads} threads");
    }
    // Not counted (a colour column): false, the sum untouched; a sum of the wrong size.
    let colours = vec![0u32; n];
    let mut sum = before.clone();
    let coloured = Points {
        color: Colors::Argb(&colours),
        ..part(0..n)
    };
    assert!(!plot.add_counts_of(&coloured, &mut sum).unwrap());
    assert!(sum == before);
    let err = plot.add_counts_of(&part(0..n), &mut sum[1..]).unwrap_err();
    assert_eq!(err.to_string(), "12706 counts for a 131x97 target");
}

#[test]
fn nan_is_the_same_error_as_the_devices() {
    let x = [0.5f64, 0.25, 0.75, 0.1];
    let y = [0.5f64, f64::NAN, 0.5, 0.5];
    let size = [1.0f32, 2.0, f32::NAN, 1.0];
    let cases = [
        Points::new(Column::F64(&x), Column::F64(&y)),
        Points {
            size: Sizes::PerPoint(Column::F32(&size)),
            ..Points::new(Column::F64(&x), Column::F64(&x))
        },
    ];
    for (points, expected) in cases.iter().zip(["y[1] is NaN", "size[2] is NaN"]) {
        let plot = Plot::new(8, 8);
        let counted = plot.render(points).unwrap_err().to_string();
        let device = on_device(&plot, points).unwrap_err().to_string();
        assert_eq!(counted, expected);
        assert_eq!(device, expected);
    }
}

#[test]
fn bad_targets_are_the_devices_errors() {
    let x = [0.5f32];
    let points = Points::new(Column::F32(&x), Column::F32(&x));
    for (w, h) in [(0, 4), (4, 0), (16385, 1)] {
        let plot = Plot::new(w, h);
        let counted = plot.render(&points).unwrap_err();
        assert_eq!(counted, on_device(&plot, &points).unwrap_err());
        assert!(
            counted.to_string().contains("outside 1..=16384"),
            "{counted}"
        );
    }
}

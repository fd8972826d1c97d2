//! GIF palettes: the time and the accuracy of each quantiser on real frames, to choose the one
//! `animate` uses (docs/PERFORMANCE.md, "GIF palettes").
//!
//! ```text
//! pointillist animate scenes/snow.toml -o frames/%04d.png --frames 20
//! cargo run --release -p pointillist --example gif_quantisers -- 5 frames/*.png
//! ```
//!
//! For each quantiser: the median time to quantise one frame (opaque RGB, 256 colours) and to
//! encode it as a GIF frame, the PSNR of the quantised frame against the frame (RGB, all
//! frames), and the GIF's size. Runs alternate quantiser by quantiser, `ROUNDS` times.

use std::time::{Duration, Instant};

use quantette::deps::palette::{FromColor, Oklab, Srgb};
use quantette::{ImageRef, Pipeline, QuantizeMethod};

/// A quantised frame: an RGB palette and one index per pixel.
struct Indexed {
    palette: Vec<[u8; 3]>,
    indices: Vec<u8>,
}

/// NeuQuant (the gif crate's `Frame::from_rgba_speed`) at `speed` (1 best .. 30 fastest).
fn neuquant(speed: i32, w: u32, h: u32, rgba: &[u8]) -> Indexed {
    let mut rgba = rgba.to_vec();
    let frame = gif::Frame::from_rgba_speed(w as u16, h as u16, &mut rgba, speed);
    let palette = frame
        .palette
        .expect("a local palette")
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Indexed {
        palette,
        indices: frame.buffer.into_owned(),
    }
}

/// quantette's pipeline (Oklab) with `method`, with or without Floyd-Steinberg dithering.
fn quantette(method: QuantizeMethod, dither: bool, w: u32, h: u32, rgba: &[u8]) -> Indexed {
    let rgb: Vec<Srgb<u8>> = rgba
        .chunks_exact(4)
        .map(|p| Srgb::new(p[0], p[1], p[2]))
        .collect();
    let image = ImageRef::new(w, h, rgb.as_slice()).expect("w x h pixels");
    let mut pipeline = Pipeline::new().quantize_method(method);
    if !dither {
        pipeline = pipeline.ditherer(None);
    }
    let (palette, indices) = pipeline
        .input_image(image)
        .output_srgb8_indexed_image()
        .into_parts();
    Indexed {
        palette: palette.iter().map(|c| [c.red, c.green, c.blue]).collect(),
        indices,
    }
}

/// Squared error of `q` against the RGB of `rgba`, summed.
fn squared_error(q: &Indexed, rgba: &[u8]) -> f64 {
    rgba.chunks_exact(4)
        .zip(&q.indices)
        .map(|(p, &i)| {
            let c = q.palette[usize::from(i)];
            (0..3)
                .map(|k| (f64::from(p[k]) - f64::from(c[k])).powi(2))
                .sum::<f64>()
        })
        .sum()
}

/// The Oklab distance (ΔE, x100) of `q` from `rgba`, summed over the pixels: the error as the
/// eye weighs it, where the squared RGB error weighs every channel and level alike.
fn oklab_error(q: &Indexed, rgba: &[u8]) -> f64 {
    let lab = |c: [u8; 3]| Oklab::from_color(Srgb::new(c[0], c[1], c[2]).into_format::<f32>());
    let palette: Vec<Oklab> = q.palette.iter().map(|&c| lab(c)).collect();
    rgba.chunks_exact(4)
        .zip(&q.indices)
        .map(|(p, &i)| {
            let (a, b) = (lab([p[0], p[1], p[2]]), palette[usize::from(i)]);
            let d = [a.l - b.l, a.a - b.a, a.b - b.b];
            f64::from((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()) * 100.0
        })
        .sum()
}

/// Writes `q` as one GIF frame into `gif`.
fn encode(q: &Indexed, w: u32, h: u32, gif: &mut gif::Encoder<Vec<u8>>) {
    let palette: Vec<u8> = q.palette.iter().flatten().copied().collect();
    let frame =
        gif::Frame::from_palette_pixels(w as u16, h as u16, q.indices.clone(), palette, None);
    gif.write_frame(&frame).expect("in memory");
}

fn main() {
    let mut args = std::env::args().skip(1);
    let rounds: usize = args
        .next()
        .and_then(|r| r.parse().ok())
        .expect("usage: gif_quantisers ROUNDS FRAME.png...");
    let frames: Vec<(u32, u32, Vec<u8>)> = args
        .map(|path| {
            let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
            let t =
                pointillist::image::png::load_png(&bytes).unwrap_or_else(|e| panic!("{path}: {e}"));
            let level = &t.levels()[0];
            let rgba = level
                .texels
                .iter()
                .flat_map(|&c| {
                    let [r, g, b, _] = pointillist::color::argb_to_rgba8(c);
                    [r, g, b, 255]
                })
                .collect();
            (level.width, level.height, rgba)
        })
        .collect();
    assert!(!frames.is_empty(), "no frame given");
    type Quantiser = (&'static str, fn(u32, u32, &[u8]) -> Indexed);
    let quantisers: [Quantiser; 6] = [
        ("NeuQuant speed 10 (default before)", |w, h, p| {
            neuquant(10, w, h, p)
        }),
        ("NeuQuant speed 30 (animate)", |w, h, p| {
            neuquant(30, w, h, p)
        }),
        ("NeuQuant speed 1", |w, h, p| neuquant(1, w, h, p)),
        ("quantette Wu", |w, h, p| {
            quantette(QuantizeMethod::Wu, false, w, h, p)
        }),
        ("quantette Wu, dithered", |w, h, p| {
            quantette(QuantizeMethod::Wu, true, w, h, p)
        }),
        ("quantette k-means", |w, h, p| {
            quantette(QuantizeMethod::kmeans(), false, w, h, p)
        }),
    ];
    let (w, h) = (frames[0].0, frames[0].1);
    println!(
        "{} frames of {w}x{h}, {rounds} rounds; medians per frame",
        frames.len()
    );
    let mut quantise = vec![Vec::new(); quantisers.len()];
    let mut encoding = vec![Vec::new(); quantisers.len()];
    let mut results = Vec::new();
    for round in 0..rounds {
        for (k, (_, quantiser)) in quantisers.iter().enumerate() {
            let mut gif =
                gif::Encoder::new(Vec::new(), w as u16, h as u16, &[]).expect("in memory");
            let (mut error, mut delta_e, mut pixels) = (0.0, 0.0, 0usize);
            for (fw, fh, rgba) in &frames {
                let start = Instant::now();
                let q = quantiser(*fw, *fh, rgba);
                let quantised = Instant::now();
                encode(&q, *fw, *fh, &mut gif);
                quantise[k].push(quantised - start);
                encoding[k].push(quantised.elapsed());
                if round == 0 {
                    error += squared_error(&q, rgba);
                    delta_e += oklab_error(&q, rgba);
                }
                pixels += rgba.len() / 4;
            }
            let bytes = gif.into_inner().expect("in memory").len();
            if round == 0 {
                let mse = error / (pixels as f64 * 3.0);
                let psnr = 10.0 * (255.0f64 * 255.0 / mse).log10();
                results.push((psnr, delta_e / pixels as f64, bytes));
            }
        }
    }
    let median = |v: &mut Vec<Duration>| {
        v.sort();
        v[v.len() / 2]
    };
    println!("| quantiser | quantise | GIF frame | PSNR (RGB) | mean Oklab ΔE x100 | GIF |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for (k, (name, _)) in quantisers.iter().enumerate() {
        let (psnr, delta_e, bytes) = results[k];
        println!(
            "| {name} | {:.1} ms | {:.1} ms | {psnr:.2} dB | {delta_e:.3} | {:.2} MB |",
            median(&mut quantise[k]).as_secs_f64() * 1e3,
            median(&mut encoding[k]).as_secs_f64() * 1e3,
            bytes as f64 / 1e6
        );
    }
}

//! Times the png crate's compression presets on given images (docs/PERFORMANCE.md, "PNG
//! compression"): each preset encodes each image in turn, alternating, and the median time and
//! the file size are printed.
//!
//! `cargo run --release -p pointillist-image --example png_compression -- RUNS A.png B.png ...`

use std::time::{Duration, Instant};

use png::{BitDepth, ColorType, Compression, Decoder, Encoder, Transformations};

const PRESETS: [(&str, Compression); 5] = [
    ("none", Compression::NoCompression),
    ("fastest (fdeflate, Up)", Compression::Fastest),
    ("fast (fdeflate, adaptive)", Compression::Fast),
    ("balanced (zlib 6)", Compression::Balanced),
    ("high (zlib 9)", Compression::High),
];

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: png_compression RUNS IMAGE.png...";
    let runs: usize = args.next().and_then(|r| r.parse().ok()).ok_or(usage)?;
    for path in args {
        let bytes = std::fs::read(&path).map_err(|e| format!("{path}: {e}"))?;
        let mut decoder = Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(Transformations::EXPAND | Transformations::ALPHA);
        let mut reader = decoder.read_info().map_err(|e| format!("{path}: {e}"))?;
        let mut rgba = vec![0; reader.output_buffer_size().ok_or("too large")?];
        let info = reader
            .next_frame(&mut rgba)
            .map_err(|e| format!("{path}: {e}"))?;
        let (w, h) = (info.width, info.height);
        let mut times = vec![Vec::new(); PRESETS.len()];
        let mut sizes = vec![0; PRESETS.len()];
        for _ in 0..runs {
            for (k, &(_, preset)) in PRESETS.iter().enumerate() {
                let start = Instant::now();
                let mut out = Vec::new();
                let mut enc = Encoder::new(&mut out, w, h);
                enc.set_color(ColorType::Rgba);
                enc.set_depth(BitDepth::Eight);
                enc.set_compression(preset);
                let mut writer = enc.write_header().map_err(|e| e.to_string())?;
                writer.write_image_data(&rgba).map_err(|e| e.to_string())?;
                writer.finish().map_err(|e| e.to_string())?;
                times[k].push(start.elapsed());
                sizes[k] = out.len();
            }
        }
        println!("{path} ({w}x{h}, {} bytes raw):", rgba.len());
        for (k, (name, _)) in PRESETS.iter().enumerate() {
            println!(
                "  {name:<26} {:>8.2} ms  {:>10} bytes",
                median(&mut times[k]).as_secs_f64() * 1e3,
                sizes[k]
            );
        }
    }
    Ok(())
}

fn median(t: &mut [Duration]) -> Duration {
    t.sort();
    t[t.len() / 2]
}

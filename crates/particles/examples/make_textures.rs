//! Writes the preset sprite textures ([`presets::textures`]) as PNG files, so that the scenes
//! under `scenes/` can be regenerated exactly:
//! `cargo run -p pointillist-particles --example make_textures -- scenes/textures`.

use std::path::PathBuf;

use pointillist_particles::presets;

fn main() {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "scenes/textures".into()),
    );
    for (name, texture) in presets::textures() {
        let level = &texture.levels()[0];
        let rgba: Vec<u8> = level
            .texels
            .iter()
            .flat_map(|&c| pointillist_core::color::argb_to_rgba8(c))
            .collect();
        let path = dir.join(name);
        if let Err(e) =
            pointillist_image::write_png_atomic(&path, texture.width(), texture.height(), &rgba)
        {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
        println!("wrote {}", path.display());
    }
}

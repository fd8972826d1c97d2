//! The sprite textures under `scenes/textures/` are exactly what [`presets::textures`] makes:
//! regenerate them with
//! `cargo run -p pointillist-particles --example make_textures -- scenes/textures`.

use std::path::Path;

use pointillist_particles::presets;

#[test]
fn scene_textures_are_the_presets() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/textures");
    for (name, made) in presets::textures() {
        let file = pointillist_image::load_texture(&dir.join(name))
            .unwrap_or_else(|e| panic!("{name}: {e} (regenerate with the make_textures example)"));
        assert_eq!(
            file.levels()[0],
            made.levels()[0],
            "{name} differs from presets::textures() (regenerate with the make_textures example)"
        );
    }
}

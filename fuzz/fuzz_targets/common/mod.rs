//! What every texture loader target checks.

use pointillist_core::texture::Texture;
use pointillist_image::ImageError;

/// A loaded texture has a whole top level and a mip chain down to 1x1; a refusal is one line.
pub fn check_loaded(loaded: Result<Texture, ImageError>) {
    match loaded {
        Ok(t) => {
            let top = &t.levels()[0];
            assert_eq!(top.texels.len(), top.width as usize * top.height as usize);
            let last = t.levels().last().expect("a texture has a level");
            assert_eq!((last.width, last.height), (1, 1));
        }
        Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
    }
}

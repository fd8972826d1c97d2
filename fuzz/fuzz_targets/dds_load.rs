//! The DDS texture loader (DXT1/3/5, mask formats, mip levels) on arbitrary bytes: a texture
//! with a full mip chain or an `ImageError` with a one-line message, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match pointillist_image::dds::load_dds(data) {
        Ok(t) => {
            let top = &t.levels()[0];
            assert_eq!(top.texels.len(), top.width as usize * top.height as usize);
            let last = t.levels().last().expect("a texture has a level");
            assert_eq!((last.width, last.height), (1, 1));
        }
        Err(e) => assert!(!e.to_string().contains('\n'), "{e}"),
    }
});

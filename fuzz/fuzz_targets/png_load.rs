//! The PNG texture loader on arbitrary bytes: a texture with a full mip chain or an `ImageError`
//! with a one-line message, never a panic.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| common::check_loaded(pointillist_image::png::load_png(data)));

//! The DDS texture loader (DXT1/3/5, mask formats, mip levels) on arbitrary bytes: a texture
//! with a full mip chain or an `ImageError` with a one-line message, never a panic.
#![no_main]

mod common;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| common::check_loaded(pointillist_image::dds::load_dds(data)));

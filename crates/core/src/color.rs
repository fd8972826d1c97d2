//! Colour conversions between D3DCOLOR storage and float arithmetic (SPEC 1).
//!
//! Storage is `u32` 0xAARRGGBB; arithmetic is [`Rgba`], four f32 in 0..=1. Float to unorm
//! conversion saturates and rounds to nearest.

/// A colour in arithmetic form: r, g, b, a, each nominally in 0..=1.
pub type Rgba = [f32; 4];

/// Opaque white, the default diffuse colour (SPEC 4.2).
pub const WHITE: u32 = 0xFFFF_FFFF;

/// Converts an 8-bit unorm channel to float.
#[inline]
pub fn unorm8_to_f32(v: u8) -> f32 {
    f32::from(v) * (1.0 / 255.0)
}

/// Converts a float to an 8-bit unorm channel: saturate, then round to nearest (SPEC 1).
/// NaN becomes 0.
#[inline]
pub fn f32_to_unorm8(v: f32) -> u8 {
    // Round half away from zero without a libm call: `x - trunc(x)` is exact for x in 0..=255.
    // NaN stays NaN through the clamp and `as` maps it to 0.
    let x = v.clamp(0.0, 1.0) * 255.0;
    let t = x as u8;
    if x - f32::from(t) >= 0.5 { t + 1 } else { t }
}

/// Splits a D3DCOLOR into float channels.
#[inline]
pub fn unpack(argb: u32) -> Rgba {
    let [a, r, g, b] = argb.to_be_bytes();
    [
        unorm8_to_f32(r),
        unorm8_to_f32(g),
        unorm8_to_f32(b),
        unorm8_to_f32(a),
    ]
}

/// Packs float channels into a D3DCOLOR (saturating, round to nearest).
#[inline]
pub fn pack(c: Rgba) -> u32 {
    u32::from_be_bytes([
        f32_to_unorm8(c[3]),
        f32_to_unorm8(c[0]),
        f32_to_unorm8(c[1]),
        f32_to_unorm8(c[2]),
    ])
}

/// Reorders a D3DCOLOR into RGBA8 bytes, the order PNG files and most image APIs use.
#[inline]
pub fn argb_to_rgba8(argb: u32) -> [u8; 4] {
    let [a, r, g, b] = argb.to_be_bytes();
    [r, g, b, a]
}

/// Builds a D3DCOLOR from RGBA8 bytes.
#[inline]
pub fn rgba8_to_argb(rgba: [u8; 4]) -> u32 {
    u32::from_be_bytes([rgba[3], rgba[0], rgba[1], rgba[2]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_1_unorm_round_trips_every_byte() {
        for v in 0..=255u8 {
            assert_eq!(f32_to_unorm8(unorm8_to_f32(v)), v);
        }
    }

    #[test]
    fn spec_1_float_to_unorm_rounds_to_nearest_and_saturates() {
        assert_eq!(f32_to_unorm8(0.5), 128);
        assert_eq!(f32_to_unorm8(127.4 / 255.0), 127);
        assert_eq!(f32_to_unorm8(127.6 / 255.0), 128);
        assert_eq!(f32_to_unorm8(-3.0), 0);
        assert_eq!(f32_to_unorm8(7.0), 255);
        assert_eq!(f32_to_unorm8(f32::NAN), 0);
        for k in 0..=25_500u32 {
            let v = k as f32 / 25_500.0;
            assert_eq!(f32_to_unorm8(v), (v * 255.0).round() as u8, "{v}");
        }
    }

    #[test]
    fn pack_unpack_round_trip() {
        for c in [0xFF00_0000u32, 0x1234_5678, 0xFFFF_FFFF, 0x00AB_CDEF] {
            assert_eq!(pack(unpack(c)), c);
            assert_eq!(rgba8_to_argb(argb_to_rgba8(c)), c);
        }
        assert_eq!(unpack(0x80FF_0000), [1.0, 0.0, 0.0, 128.0 / 255.0]);
    }
}

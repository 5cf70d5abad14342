//! Twins of the GLSL packing built-ins (`packSnorm2x16`, `unpackHalf2x16`, ...), so that
//! the CPU decodes a packed patch record to the bits the shaders decode it to.

use glam::Vec2;

/// `unpackSnorm2x16`: two signed 16-bit values, low half first, as `clamp(v / 32767, -1, 1)`.
pub fn unpack_snorm2x16(word: u32) -> Vec2 {
    let part = |bits: u32| ((bits as u16 as i16) as f32 / 32767.0).clamp(-1.0, 1.0);
    Vec2::new(part(word & 0xffff), part(word >> 16))
}

/// `packSnorm2x16`: the inverse of `unpack_snorm2x16`, rounding to the nearest step.
pub fn pack_snorm2x16(value: Vec2) -> u32 {
    let part = |v: f32| ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    part(value.x) | (part(value.y) << 16)
}

/// `unpackUnorm2x16`: two unsigned 16-bit values, low half first, as `v / 65535`.
pub fn unpack_unorm2x16(word: u32) -> Vec2 {
    Vec2::new((word & 0xffff) as f32 / 65535.0, (word >> 16) as f32 / 65535.0)
}

/// `packUnorm2x16`: the inverse of `unpack_unorm2x16`, rounding to the nearest step.
pub fn pack_unorm2x16(value: Vec2) -> u32 {
    let part = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u32;
    part(value.x) | (part(value.y) << 16)
}

/// `unpackHalf2x16`: two IEEE half floats, low half first. Exact.
pub fn unpack_half2x16(word: u32) -> Vec2 {
    let part = |bits: u32| half::f16::from_bits(bits as u16).to_f32();
    Vec2::new(part(word & 0xffff), part(word >> 16))
}

/// `packHalf2x16`, except that values beyond the half range saturate at ±65504 instead of
/// becoming infinite: a stored coefficient is never infinite.
pub fn pack_half2x16(value: Vec2) -> u32 {
    let part = |v: f32| half::f16::from_f32(v.clamp(-65504.0, 65504.0)).to_bits() as u32;
    part(value.x) | (part(value.y) << 16)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_stay_within_one_step() {
        for value in [Vec2::new(-1.0, 1.0), Vec2::new(0.25, -0.7), Vec2::ZERO, Vec2::new(0.999, -0.001)] {
            assert!((unpack_snorm2x16(pack_snorm2x16(value)) - value).abs().max_element() <= 0.5 / 32767.0);
            let unit = value.abs();
            assert!((unpack_unorm2x16(pack_unorm2x16(unit)) - unit).abs().max_element() <= 0.5 / 65535.0);
            let half = unpack_half2x16(pack_half2x16(value * 3.0));
            assert!((half - value * 3.0).abs().max_element() <= 3.0 / 2048.0);
        }
    }

    #[test]
    fn the_extremes_decode_to_the_glsl_values() {
        assert_eq!(unpack_snorm2x16(0x8000_8000), Vec2::splat(-1.0));
        assert_eq!(unpack_unorm2x16(0xffff_0000), Vec2::new(0.0, 1.0));
        assert_eq!(unpack_half2x16(pack_half2x16(Vec2::new(1e9, -1e9))), Vec2::new(65504.0, -65504.0));
    }
}

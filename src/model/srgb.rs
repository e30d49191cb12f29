//! The sRGB transfer functions (IEC 61966-2-1), per channel: what display colours
//! (Table 1's, exported textures and vertex colours) mean in linear light.

/// Linear to sRGB-encoded, per channel (IEC 61966-2-1).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB-encoded to linear, per channel.
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_transfer_round_trips() {
        for k in 0..=255 {
            let c = k as f32 / 255.0;
            assert!((srgb_to_linear(linear_to_srgb(c)) - c).abs() < 1e-5);
        }
        // The example: linear 0.022 is sRGB 0.16.
        assert!((linear_to_srgb(0.022) - 0.161).abs() < 0.002);
    }
}

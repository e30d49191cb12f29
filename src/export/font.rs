//! Text in the pictures sediment draws on the CPU (cross-sections, the year stamp on
//! growth GIFs, bench charts through plotters): DejaVu Sans, bundled so the pixels are
//! the same on every machine (no system font lookup), rasterised with ab_glyph.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};
use image::RgbaImage;

/// DejaVu Sans 2.37 (Bitstream Vera licence, `assets/fonts/LICENSE-DejaVu.txt`).
pub const DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

fn face() -> Option<&'static FontRef<'static>> {
    static FACE: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FACE.get_or_init(|| FontRef::try_from_slice(DEJAVU_SANS).ok())
        .as_ref()
}

/// The advance width of `label` at `size` pixels (the em height), in pixels.
pub fn text_width(label: &str, size: f32) -> f32 {
    let Some(face) = face() else { return 0.0 };
    let scaled = face.as_scaled(PxScale::from(size));
    let mut width = 0.0;
    let mut previous = None;
    for c in label.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            width += scaled.kern(p, id);
        }
        width += scaled.h_advance(id);
        previous = Some(id);
    }
    width
}

/// The height of a line of text at `size` pixels: the font's ascent to its descent.
pub fn line_height(size: f32) -> f32 {
    face().map_or(size, |face| {
        let scaled = face.as_scaled(PxScale::from(size));
        scaled.ascent() - scaled.descent()
    })
}

/// Rasterises `label` at `size` pixels, kerned, each glyph at its own bearing, the pen
/// starting at `origin` (x, and y of the font's ascent line, so the line spans
/// `origin.1..origin.1 + line_height(size)`): hands `put(x, y, coverage)` every
/// covered pixel.
pub fn coverage(label: &str, size: f32, origin: (f32, f32), put: &mut dyn FnMut(i32, i32, f32)) {
    let Some(face) = face() else { return };
    let scaled = face.as_scaled(PxScale::from(size));
    let baseline = origin.1 + scaled.ascent();
    let mut x = origin.0;
    let mut previous = None;
    for c in label.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = previous {
            x += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(PxScale::from(size), point(x, baseline));
        x += scaled.h_advance(id);
        previous = Some(id);
        let Some(outline) = face.outline_glyph(glyph) else {
            continue; // a space
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, cover| {
            if cover > 0.0 {
                put(
                    bounds.min.x as i32 + gx as i32,
                    bounds.min.y as i32 + gy as i32,
                    cover.min(1.0),
                );
            }
        });
    }
}

/// Draws `label` centred at `cx`, its top (the font's ascent) at `top`, `size` pixels
/// high, blended by coverage (anti-aliased).
pub fn text(img: &mut RgbaImage, label: &str, cx: f64, top: f64, size: f32, color: [u8; 3]) {
    let left = cx as f32 - 0.5 * text_width(label, size);
    let (w, h) = (img.width() as i32, img.height() as i32);
    coverage(label, size, (left, top as f32), &mut |px, py, cover| {
        if px < 0 || py < 0 || px >= w || py >= h {
            return;
        }
        let p = img.get_pixel_mut(px as u32, py as u32);
        for (channel, &ink) in p.0.iter_mut().zip(&color) {
            let v = f32::from(*channel) + (f32::from(ink) - f32::from(*channel)) * cover;
            *channel = v.round() as u8;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bundled_font_draws_readable_text() {
        assert!(face().is_some(), "DejaVu Sans parses");
        let width = text_width("200 mm", 16.0);
        assert!((40.0..70.0).contains(&width), "{width} px");
        let mut img = RgbaImage::from_pixel(80, 24, image::Rgba([255, 255, 255, 255]));
        text(&mut img, "200 mm", 40.0, 2.0, 16.0, [0, 0, 0]);
        let inked: Vec<(u32, u32)> = img
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] < 128)
            .map(|(x, y, _)| (x, y))
            .collect();
        assert!(inked.len() > 60, "{} dark pixels", inked.len());
        // Centred, and inside the line: the ink spans about the advance width.
        let (x0, x1) = inked
            .iter()
            .fold((u32::MAX, 0), |(a, b), &(x, _)| (a.min(x), b.max(x)));
        assert!((40 - x0 as i32 - (x1 as i32 - 40)).abs() <= 3, "{x0}..{x1}");
        assert!(f64::from(x1 - x0) > 0.8 * f64::from(width));
        // Anti-aliased: grey edge pixels, not only black and white.
        assert!(img.pixels().any(|p| (64..192).contains(&p.0[0])));
    }
}

//! The on-screen panel: lines of text in DejaVu Sans (the font every other picture's
//! text uses, `export::font`), light on an opaque dark box, rasterised on the CPU and
//! copied into the swapchain image after the scene. A text panel is all the viewer
//! needs; a GUI toolkit (egui with a Vulkan renderer) would be the largest dependency
//! of the build for it.

use crate::export::font;

/// The text's size (its em height) and the distance between baselines, in pixels:
/// 13 px reads at arm's length on any screen and fits the viewer's 30-odd lines in a
/// 720-pixel window.
const TEXT_PX: f32 = 13.0;
const LINE_H: u32 = 16;
const MARGIN: u32 = 6;

/// A rasterised panel: `width` x `height` RGBA8 (or BGRA8) pixels.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Panel {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

/// Rasterises `lines`, cropped to `max_width` x `max_height` pixels; `bgra` swaps red
/// and blue for swapchains that store blue first. `None` when nothing fits.
pub fn panel(lines: &[String], max_width: u32, max_height: u32, bgra: bool) -> Option<Panel> {
    let widest = lines
        .iter()
        .map(|l| font::text_width(l, TEXT_PX))
        .fold(0.0f32, f32::max);
    let width = (2 * MARGIN + widest.ceil() as u32).min(max_width);
    let height = (2 * MARGIN + lines.len() as u32 * LINE_H).min(max_height);
    if widest <= 0.0 || width == 0 || height == 0 {
        return None;
    }
    let background = image::Rgba([16u8, 18, 22, 255]);
    let ink = [235u8, 226, 200];
    let mut img = image::RgbaImage::from_pixel(width, height, background);
    for (row, line) in lines.iter().enumerate() {
        // `font::text` centres a line; the panel's lines start at the margin.
        let cx = f64::from(MARGIN) + 0.5 * f64::from(font::text_width(line, TEXT_PX));
        let top = f64::from(MARGIN + row as u32 * LINE_H);
        font::text(&mut img, line, cx, top, TEXT_PX, ink);
    }
    let mut pixels = img.into_raw();
    if bgra {
        for p in pixels.chunks_exact_mut(4) {
            p.swap(0, 2);
        }
    }
    Some(Panel {
        width,
        height,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_drawn_and_cropped() {
        let lines = vec!["pil 2".to_owned(), "co2 high".to_owned()];
        let p = panel(&lines, 1000, 1000, false).expect("panel");
        let widest = font::text_width("co2 high", TEXT_PX).ceil() as u32;
        assert_eq!(p.width, 2 * MARGIN + widest);
        assert_eq!(p.height, 2 * MARGIN + 2 * LINE_H);
        // Ink: pixels at least half way from the background to the text's colour.
        let ink = p.pixels.chunks_exact(4).filter(|c| c[0] >= 125).count();
        assert!(ink > 50, "{ink} ink pixels");
        // Each line's ink within its own band of rows.
        let rows_with_ink = |band: std::ops::Range<u32>| {
            band.filter(|&y| {
                (0..p.width).any(|x| p.pixels[((y * p.width + x) * 4) as usize] >= 125)
            })
            .count()
        };
        assert!(rows_with_ink(MARGIN..MARGIN + LINE_H) >= 6);
        assert!(rows_with_ink(MARGIN + LINE_H..MARGIN + 2 * LINE_H) >= 6);
        let small = panel(&lines, 20, 10, true).expect("cropped");
        assert_eq!((small.width, small.height), (20, 10));
        assert_eq!(small.pixels.len(), 20 * 10 * 4);
        assert_eq!(&small.pixels[..4], &[22, 18, 16, 255], "blue first");
        assert!(panel(&[], 100, 100, false).is_none());
    }
}

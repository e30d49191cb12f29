//! The on-screen panel: lines of text in sediment's 3x5 pixel font (the one the
//! cross-section labels use), at 2x, light on an opaque dark box, rasterised on the
//! CPU and copied into the swapchain image after the scene. A text panel is all the
//! viewer needs; a GUI toolkit (egui with a Vulkan renderer) would be the largest
//! dependency of the build for it.

use crate::export::draw::glyph;

/// Pixels per font pixel, and a glyph cell (3 + 1 spacing columns, 5 + 2 rows).
const SCALE: u32 = 2;
const CELL_W: u32 = 4 * SCALE;
const CELL_H: u32 = 7 * SCALE;
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
    let columns = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
    let width = (2 * MARGIN + columns * CELL_W).min(max_width);
    let height = (2 * MARGIN + lines.len() as u32 * CELL_H).min(max_height);
    if columns == 0 || width == 0 || height == 0 {
        return None;
    }
    let background = [16u8, 18, 22, 255];
    let ink = [235u8, 226, 200, 255];
    let mut pixels: Vec<u8> = background
        .iter()
        .copied()
        .cycle()
        .take((width * height * 4) as usize)
        .collect();
    for (row, line) in lines.iter().enumerate() {
        for (col, c) in line.chars().enumerate() {
            let (x0, y0) = (
                MARGIN + col as u32 * CELL_W,
                MARGIN + row as u32 * CELL_H + SCALE,
            );
            for (gy, bits) in glyph(c).iter().enumerate() {
                for gx in 0..3u32 {
                    if bits >> (2 - gx) & 1 == 0 {
                        continue;
                    }
                    for (dx, dy) in (0..SCALE).flat_map(|a| (0..SCALE).map(move |b| (a, b))) {
                        let (x, y) = (x0 + gx * SCALE + dx, y0 + gy as u32 * SCALE + dy);
                        if x < width && y < height {
                            let i = ((y * width + x) * 4) as usize;
                            pixels[i..i + 4].copy_from_slice(&ink);
                        }
                    }
                }
            }
        }
    }
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
        assert_eq!(p.width, 2 * MARGIN + 8 * CELL_W);
        assert_eq!(p.height, 2 * MARGIN + 2 * CELL_H);
        let ink = p.pixels.chunks_exact(4).filter(|c| c[0] == 235).count();
        assert!(ink > 50, "{ink} ink pixels");
        let small = panel(&lines, 20, 10, true).expect("cropped");
        assert_eq!((small.width, small.height), (20, 10));
        assert_eq!(small.pixels.len(), 20 * 10 * 4);
        assert_eq!(&small.pixels[..4], &[22, 18, 16, 255], "blue first");
        assert!(panel(&[], 100, 100, false).is_none());
    }
}

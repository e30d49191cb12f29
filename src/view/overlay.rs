//! The on-screen panel: lines of text in a 3x5 pixel font, at 2x, light on an opaque
//! dark box, rasterised on the CPU and copied into the swapchain image after the
//! scene. A text panel is all the viewer needs; a GUI toolkit (egui with a Vulkan
//! renderer) would be the largest dependency of the build for it. The pixel font
//! earns its place here and only here (every other picture's text is DejaVu Sans,
//! `export::font`): the panel is redrawn every frame at any window size, and a fixed
//! pixel grid stays crisp and costs nothing at 1:1, where anti-aliased glyphs blur.

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

/// A 3x5 pixel font: digits, letters (drawn as capitals' small cousins) and a few
/// signs; anything else is a space.
fn glyph(c: char) -> [u8; 5] {
    // Rows top to bottom, 3 bits each (4 = left column).
    match c.to_ascii_lowercase() {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        'a' => [2, 5, 7, 5, 5],
        'b' => [6, 5, 6, 5, 6],
        'c' => [3, 4, 4, 4, 3],
        'd' => [6, 5, 5, 5, 6],
        'e' => [7, 4, 6, 4, 7],
        'f' => [7, 4, 6, 4, 4],
        'g' => [3, 4, 5, 5, 3],
        'h' => [5, 5, 7, 5, 5],
        'i' => [7, 2, 2, 2, 7],
        'j' => [1, 1, 1, 5, 2],
        'k' => [5, 5, 6, 5, 5],
        'l' => [4, 4, 4, 4, 7],
        'm' => [5, 7, 7, 5, 5],
        'n' => [6, 5, 5, 5, 5],
        'o' => [2, 5, 5, 5, 2],
        'p' => [6, 5, 6, 4, 4],
        'q' => [2, 5, 5, 6, 3],
        'r' => [6, 5, 6, 5, 5],
        's' => [3, 4, 2, 1, 6],
        't' => [7, 2, 2, 2, 2],
        'u' => [5, 5, 5, 5, 7],
        'v' => [5, 5, 5, 5, 2],
        'w' => [5, 5, 7, 7, 5],
        'x' => [5, 5, 2, 5, 5],
        'y' => [5, 5, 2, 2, 2],
        'z' => [7, 1, 2, 4, 7],
        '.' => [0, 0, 0, 0, 2],
        ',' => [0, 0, 0, 2, 4],
        ':' => [0, 2, 0, 2, 0],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        '/' => [1, 1, 2, 4, 4],
        '(' => [1, 2, 2, 2, 1],
        ')' => [4, 2, 2, 2, 4],
        '%' => [5, 1, 2, 4, 5],
        '=' => [0, 7, 0, 7, 0],
        '_' => [0, 0, 0, 0, 7],
        '[' => [6, 4, 4, 4, 6],
        ']' => [3, 1, 1, 1, 3],
        '<' => [1, 2, 4, 2, 1],
        '>' => [4, 2, 1, 2, 4],
        '!' => [2, 2, 2, 0, 2],
        '?' => [7, 1, 2, 0, 2],
        '\'' => [2, 2, 0, 0, 0],
        '*' => [5, 2, 7, 2, 5],
        _ => [0; 5],
    }
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

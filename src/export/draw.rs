//! Small raster drawing for pictures sediment draws on the CPU (cross-sections, bench
//! charts): anti-aliased thick segments and a 3x5 pixel font. Enough for lines and
//! labels without a rendering or font dependency.

use image::{Rgba, RgbaImage};

/// Blends an anti-aliased segment of `width` pixels (coverage from the distance to it).
pub fn segment(img: &mut RgbaImage, a: [f64; 2], b: [f64; 2], width: f64, color: [u8; 3]) {
    let r = 0.5 * width + 1.0;
    let (x0, x1) = (
        (a[0].min(b[0]) - r).floor().max(0.0),
        (a[0].max(b[0]) + r).ceil(),
    );
    let (y0, y1) = (
        (a[1].min(b[1]) - r).floor().max(0.0),
        (a[1].max(b[1]) + r).ceil(),
    );
    let (w, h) = (f64::from(img.width()), f64::from(img.height()));
    let (ab_x, ab_y) = (b[0] - a[0], b[1] - a[1]);
    let len2 = (ab_x * ab_x + ab_y * ab_y).max(1e-12);
    let mut y = y0;
    while y <= y1.min(h - 1.0) {
        let mut x = x0;
        while x <= x1.min(w - 1.0) {
            let (px, py) = (x + 0.5, y + 0.5);
            let t = (((px - a[0]) * ab_x + (py - a[1]) * ab_y) / len2).clamp(0.0, 1.0);
            let (dx, dy) = (px - (a[0] + ab_x * t), py - (a[1] + ab_y * t));
            let cover = (0.5 * width + 0.5 - (dx * dx + dy * dy).sqrt()).clamp(0.0, 1.0);
            if cover > 0.0 {
                let p = img.get_pixel_mut(x as u32, y as u32);
                for (channel, &ink) in p.0.iter_mut().zip(&color) {
                    let v = f64::from(*channel) + (f64::from(ink) - f64::from(*channel)) * cover;
                    *channel = v.round() as u8;
                }
            }
            x += 1.0;
        }
        y += 1.0;
    }
}

/// A 3x5 pixel font: digits, letters (drawn as capitals' small cousins) and a few
/// signs; anything else is a space.
pub fn glyph(c: char) -> [u8; 5] {
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

/// Draws `label` centred at `cx`, top at `top`, at 2x pixel size.
pub fn text(img: &mut RgbaImage, label: &str, cx: f64, top: f64, color: [u8; 3]) {
    let px = 2.0;
    let width = label.chars().count() as f64 * 4.0 * px;
    let mut x = cx - 0.5 * width;
    for c in label.chars() {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..3 {
                if bits >> (2 - col) & 1 == 1 {
                    for (dy, dx) in [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)] {
                        let (xx, yy) = (x + f64::from(col) * px + dx, top + row as f64 * px + dy);
                        if xx >= 0.0
                            && yy >= 0.0
                            && xx < f64::from(img.width())
                            && yy < f64::from(img.height())
                        {
                            img.put_pixel(
                                xx as u32,
                                yy as u32,
                                Rgba([color[0], color[1], color[2], 255]),
                            );
                        }
                    }
                }
            }
        }
        x += 4.0 * px;
    }
}

//! Small raster drawing for pictures sediment draws on the CPU (cross-sections):
//! anti-aliased thick segments. Text is `export::font`'s; charts are plotters'.

use image::RgbaImage;

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

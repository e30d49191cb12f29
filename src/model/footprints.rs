//! Footprints in sand after Sumner, O'Brien & Hodgins (1998), "Animating sand, mud and
//! snow", on a high-resolution detail heightfield laid over the dunes along a walked
//! path. Each print is their three steps:
//! 1. contact: the sole pushes the columns under it down to its own surface;
//! 2. compression and displacement: of the material pushed away, the fraction
//!    `compression` stays, compacted, under the sole (the column is denser; its mass
//!    is kept in `compacted`), the rest is displaced to the columns just outside the
//!    sole, shared out in proportion to how near each is to it (within `rim_cells`);
//! 3. erosion: wherever the slope between neighbouring columns exceeds the angle of
//!    repose, material slides to the lower column until no slope does (a few sweeps).
//!
//! Mass is conserved: the heights' sum plus the compacted volume equals the sum before
//! (in f64, to rounding; `tests::prints_conserve_the_sand`).

/// One walk over the dunes.
#[derive(Clone, Debug, PartialEq)]
pub struct FootprintParams {
    /// The walked path, world (x, z) metres, as a polyline of at least two points.
    pub path: Vec<[f32; 2]>,
    /// Distance between successive prints along the path (a half stride), metres.
    pub step: f32,
    /// Sole length along the path, metres.
    pub length: f32,
    /// Sole width across the path, metres.
    pub width: f32,
    /// Feet apart across the path (each print's offset to its side), metres.
    pub gait: f32,
    /// How deep the sole sinks, metres.
    pub depth: f32,
    /// Fraction of the pushed-away sand compacted under the sole, 0..1.
    pub compression: f32,
    /// How far out the displaced sand is laid, in detail cells.
    pub rim_cells: u32,
    /// Angle of repose of the loose sand, degrees.
    pub repose_degrees: f32,
    /// Detail cell size, metres (coarser if the walk needs more than
    /// `MAX_DETAIL_CELLS` a side).
    pub cell: f32,
}

impl FootprintParams {
    /// A walk along `path` with an adult's feet in dry sand.
    pub fn walk(path: Vec<[f32; 2]>) -> Self {
        Self {
            path,
            step: 0.7,
            length: 0.28,
            width: 0.11,
            gait: 0.09,
            depth: 0.05,
            compression: 0.3,
            rim_cells: 3,
            repose_degrees: 34.0,
            cell: 0.025,
        }
    }
}

/// A detail heightfield over a rectangle of the dune field: height offsets (metres)
/// from the dune surface, row-major, `width` x `height` cells of `cell` metres from
/// `origin` (world x, z).
#[derive(Clone, Debug, PartialEq)]
pub struct DetailField {
    /// World (x, z) of cell (0, 0)'s corner, metres.
    pub origin: [f32; 2],
    /// Side of a cell, metres.
    pub cell: f32,
    /// Cells along x.
    pub width: usize,
    /// Cells along z.
    pub height: usize,
    /// `width * height` height offsets from the dune surface, metres, index
    /// `j * width + i`.
    pub data: Vec<f64>,
    /// Volume (m^3 per cell area, i.e. metres summed over cells) compacted under soles.
    pub compacted: f64,
    /// 1 inside a print's sole (where the ripples were trodden flat), else 0.
    pub trodden: Vec<f32>,
}

/// Most detail cells a side (the field covers the walk's bounding box).
pub const MAX_DETAIL_CELLS: usize = 2048;

/// The walk of sediment's Fig. 18 over a field of `period` metres: across the view of
/// the default camera, from its right in the foreground toward the middle distance.
pub fn fig18_walk(period: f32) -> Vec<[f32; 2]> {
    [[0.60, 0.86], [0.52, 0.78], [0.47, 0.70], [0.50, 0.62]]
        .iter()
        .map(|p| [p[0] * period, p[1] * period])
        .collect()
}

/// `--footprints`: a walked path, or none.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Walk(pub Option<Vec<[f32; 2]>>);

impl std::str::FromStr for Walk {
    type Err = crate::Error;
    fn from_str(s: &str) -> crate::error::Result<Self> {
        parse_path(s)
            .map(Walk)
            .map_err(|m| crate::Error::invalid("--footprints", m))
    }
}

impl std::fmt::Display for Walk {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            None => f.write_str("off"),
            Some(path) => {
                let points: Vec<String> =
                    path.iter().map(|p| format!("{},{}", p[0], p[1])).collect();
                f.write_str(&points.join(";"))
            }
        }
    }
}

crate::serde_as_text!(Walk);

impl DetailField {
    /// Sum of the heights (the loose sand's volume over one cell area).
    pub fn volume(&self) -> f64 {
        self.data.iter().sum()
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.data[j * self.width + i]
    }

    /// Height offset at world (x, z), bilinear, 0 outside.
    pub fn sample(&self, x: f32, z: f32) -> f64 {
        let u = (x - self.origin[0]) / self.cell - 0.5;
        let v = (z - self.origin[1]) / self.cell - 0.5;
        if u < 0.0 || v < 0.0 {
            return 0.0;
        }
        let (i, j) = (u.floor() as usize, v.floor() as usize);
        if i + 1 >= self.width || j + 1 >= self.height {
            return 0.0;
        }
        let (fx, fz) = (f64::from(u.fract()), f64::from(v.fract()));
        let a = self.at(i, j) * (1.0 - fx) + self.at(i + 1, j) * fx;
        let b = self.at(i, j + 1) * (1.0 - fx) + self.at(i + 1, j + 1) * fx;
        a * (1.0 - fz) + b * fz
    }
}

/// The prints' centres and headings (unit direction along the walk) along `params.path`,
/// alternately left and right of it.
pub fn print_positions(params: &FootprintParams) -> Vec<([f32; 2], [f32; 2])> {
    let mut out = Vec::new();
    let step = params.step.max(1e-3);
    let mut carried = 0.0f32;
    let mut foot = 0u32;
    for seg in params.path.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let (dx, dz) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dz * dz).sqrt();
        if len < 1e-6 {
            continue;
        }
        let dir = [dx / len, dz / len];
        let side = [-dir[1], dir[0]];
        let mut t = carried;
        while t <= len {
            let s = if foot % 2 == 0 { 1.0 } else { -1.0 } * params.gait;
            out.push((
                [
                    a[0] + dir[0] * t + side[0] * s,
                    a[1] + dir[1] * t + side[1] * s,
                ],
                dir,
            ));
            foot += 1;
            t += step;
        }
        carried = t - len;
    }
    out
}

/// The walk's detail field: flat (offset 0) over the path's bounding box plus a margin,
/// every print stamped in order.
pub fn walk(params: &FootprintParams) -> DetailField {
    let margin = params.length + params.gait + params.cell * (params.rim_cells as f32 + 4.0);
    let (mut lo, mut hi) = ([f32::MAX; 2], [f32::MIN; 2]);
    for p in &params.path {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k] - margin);
            hi[k] = hi[k].max(p[k] + margin);
        }
    }
    // The requested cell, coarser where the walk would need more than the most cells.
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let cell = params.cell.max(1e-3).max(extent / MAX_DETAIL_CELLS as f32);
    let cells = |k: usize| (((hi[k] - lo[k]) / cell).ceil() as usize).clamp(8, MAX_DETAIL_CELLS);
    let (width, height) = (cells(0), cells(1));
    let mut field = DetailField {
        origin: lo,
        cell,
        width,
        height,
        data: vec![0.0; width * height],
        compacted: 0.0,
        trodden: vec![0.0; width * height],
    };
    for (centre, heading) in print_positions(params) {
        stamp(&mut field, params, centre, heading);
    }
    field
}

/// The sole's depth below the untouched surface at sole coordinates (along, across)
/// in units of its half length and half width: a rounded ellipse, deeper at the heel
/// and the ball of the foot; None outside.
fn sole_depth(along: f32, across: f32) -> Option<f32> {
    let r2 = along * along + across * across;
    if r2 > 1.0 {
        return None;
    }
    // Heel (along < 0) presses harder than the toes; the rim of the sole is shallower.
    let heel = 1.0 - 0.25 * along;
    Some(heel * (1.0 - 0.35 * r2))
}

/// One print: contact, compression and displacement, erosion (module docs).
fn stamp(field: &mut DetailField, params: &FootprintParams, centre: [f32; 2], dir: [f32; 2]) {
    let (w, h) = (field.width as i64, field.height as i64);
    let reach = params.length * 0.5 + params.cell * (params.rim_cells as f32 + 2.0);
    let ci = ((centre[0] - field.origin[0]) / field.cell) as i64;
    let cj = ((centre[1] - field.origin[1]) / field.cell) as i64;
    let r = (reach / field.cell).ceil() as i64;
    let (i0, i1) = ((ci - r).max(1), (ci + r).min(w - 2));
    let (j0, j1) = ((cj - r).max(1), (cj + r).min(h - 2));
    if i0 > i1 || j0 > j1 {
        return;
    }
    let local = |i: i64, j: i64| -> (f32, f32) {
        let x = field.origin[0] + (i as f32 + 0.5) * field.cell - centre[0];
        let z = field.origin[1] + (j as f32 + 0.5) * field.cell - centre[1];
        let along = (x * dir[0] + z * dir[1]) / (0.5 * params.length);
        let across = (-x * dir[1] + z * dir[0]) / (0.5 * params.width);
        (along, across)
    };
    // 1. Contact: columns above the sole's surface are pushed down to it.
    let mut pushed = 0.0f64;
    let mut inside = Vec::new();
    for j in j0..=j1 {
        for i in i0..=i1 {
            let (a, c) = local(i, j);
            if let Some(d) = sole_depth(a, c) {
                let k = (j * w + i) as usize;
                let floor = -f64::from(params.depth * d);
                if field.data[k] > floor {
                    pushed += field.data[k] - floor;
                    field.data[k] = floor;
                }
                field.trodden[k] = 1.0;
                inside.push(k);
            }
        }
    }
    if pushed <= 0.0 {
        return;
    }
    // 2. Compression keeps a fraction under the sole; the rest goes to the rim,
    // weighted by nearness to the sole (its elliptical distance beyond 1).
    let compression = f64::from(params.compression.clamp(0.0, 1.0));
    field.compacted += pushed * compression;
    let displaced = pushed * (1.0 - compression);
    let rim = params.rim_cells.max(1) as f32 * field.cell;
    let mut rim_cells = Vec::new();
    let mut total = 0.0f64;
    for j in j0..=j1 {
        for i in i0..=i1 {
            let (a, c) = local(i, j);
            // Distance outside the sole, in metres (approximately: the ellipse's
            // radius scaled by the smaller half axis).
            let outside = ((a * a + c * c).sqrt() - 1.0) * 0.5 * params.width;
            if outside > 0.0 && outside < rim {
                let weight = f64::from(1.0 - outside / rim);
                rim_cells.push(((j * w + i) as usize, weight));
                total += weight;
            }
        }
    }
    if total > 0.0 {
        for (k, weight) in rim_cells {
            field.data[k] += displaced * weight / total;
        }
    } else {
        // No room for a rim (a sole wider than the field): keep the sand compacted.
        field.compacted += displaced;
    }
    // 3. Erosion: slide sand down slopes steeper than the angle of repose.
    let limit = f64::from(params.repose_degrees.to_radians().tan() * field.cell);
    let (i0, i1, j0, j1) = (i0 - 2, i1 + 2, j0 - 2, j1 + 2);
    for _ in 0..12 {
        let mut moved = false;
        for j in j0.max(0)..=j1.min(h - 1) {
            for i in i0.max(0)..=i1.min(w - 1) {
                let k = (j * w + i) as usize;
                for (di, dj) in [(1i64, 0i64), (0, 1)] {
                    let (ni, nj) = (i + di, j + dj);
                    if ni >= w || nj >= h {
                        continue;
                    }
                    let n = (nj * w + ni) as usize;
                    let diff = field.data[k] - field.data[n];
                    if diff.abs() > limit {
                        // Half the excess each way: the pair ends at the limit.
                        let m = 0.5 * (diff.abs() - limit) * diff.signum();
                        field.data[k] -= m;
                        field.data[n] += m;
                        moved = true;
                    }
                }
            }
        }
        if !moved {
            break;
        }
    }
}

/// Slopes the detail texture encodes: +-1 (45 degrees), past the angle of repose.
pub const SLOPE_RANGE: f32 = 1.0;

/// The detail field as the shading samples it, RGBA8 per cell: the height's slopes
/// d/dx and d/dz (world, `128 + 127 v` of `SLOPE_RANGE`), where soles trod (1: the
/// ripples there were flattened), and the prints' own shadow for the sun toward
/// `sun` (y up; 1 lit): a march toward the sun over the detail heights, as the dune
/// shadows are marched over the dune heights.
///
/// Made again whenever the viewer's sun moves (Fig. 18's field is 1126 x 2048 cells),
/// so the march stops where the ray has risen above the highest cell it could reach
/// (the highest of the tiles around the cell's: nothing further can block it), flat
/// cells skip `round`, and rows are made in parallel; the bytes are the plain march's
/// (`tests::the_detail_texture_is_the_plain_marchs`).
pub fn detail_texture(field: &DetailField, sun: [f32; 3]) -> Vec<u8> {
    use rayon::prelude::*;
    let w = field.width;
    if w == 0 || field.height == 0 {
        return Vec::new();
    }
    let march = SunMarch::new(field, sun);
    let mut out = vec![0u8; w * field.height * 4];
    out.par_chunks_mut(w * 4).enumerate().for_each(|(j, row)| {
        for (i, texel) in row.chunks_exact_mut(4).enumerate() {
            let (i, j) = (i as i64, j as i64);
            texel.copy_from_slice(&detail_texel(field, i, j, march.lit(field, i, j)));
        }
    });
    out
}

/// Side of the square tiles whose highest cells end the sun march, cells.
const MARCH_TILE: usize = 32;

/// The march toward the sun over a detail field: its direction in cells, its rise
/// per cell, how far a print can shadow, and for each tile of `MARCH_TILE` cells the
/// highest cell a march from it can reach.
struct SunMarch {
    dx: f32,
    dz: f32,
    rise: f64,
    reach: usize,
    tiles_x: usize,
    reachable_highest: Vec<f64>,
}

impl SunMarch {
    fn new(field: &DetailField, sun: [f32; 3]) -> Self {
        let (w, tiles_x, tiles_z) = (
            field.width,
            field.width.div_ceil(MARCH_TILE),
            field.height.div_ceil(MARCH_TILE),
        );
        // One pass over the field: each tile's highest cell and the deepest offset.
        let mut tile_highest = vec![f64::NEG_INFINITY; tiles_x * tiles_z];
        let mut deepest = 0.0f64;
        for (k, &v) in field.data.iter().enumerate() {
            let t = (k / w / MARCH_TILE) * tiles_x + (k % w) / MARCH_TILE;
            tile_highest[t] = tile_highest[t].max(v);
            deepest = deepest.max(v.abs());
        }
        let horizontal = (sun[0] * sun[0] + sun[2] * sun[2]).sqrt().max(1e-6);
        let rise = f64::from(sun[1] / horizontal * field.cell);
        // A print is at most a sole's depth deep: rays climb out of it within `reach`.
        let reach = if rise > 0.0 {
            ((2.0 * deepest / rise).ceil() as usize).clamp(1, 48)
        } else {
            0
        };
        // A march samples cells at most `reach` away, rounded (or clamped toward the
        // cell): within `reach + 1` on each axis, so within `near` tiles.
        let near = (reach + 1).div_ceil(MARCH_TILE);
        let reachable_highest = (0..tiles_z)
            .flat_map(|tz| (0..tiles_x).map(move |tx| (tx, tz)))
            .map(|(tx, tz)| {
                let zs = tz.saturating_sub(near)..=(tz + near).min(tiles_z - 1);
                zs.flat_map(|z| {
                    let xs = tx.saturating_sub(near)..=(tx + near).min(tiles_x - 1);
                    xs.map(move |x| z * tiles_x + x)
                })
                .fold(f64::NEG_INFINITY, |m, t| m.max(tile_highest[t]))
            })
            .collect();
        Self {
            dx: sun[0] / horizontal,
            dz: sun[2] / horizontal,
            rise,
            reach,
            tiles_x,
            reachable_highest,
        }
    }

    /// Whether cell (i, j) sees the sun: no cell above the ray within `reach`, the
    /// march ending where the ray rises above the highest cell it could reach (none
    /// further can be above it).
    fn lit(&self, field: &DetailField, i: i64, j: i64) -> bool {
        if self.rise <= 0.0 {
            // The sun at or below the horizon: nothing of it reaches the sand.
            return false;
        }
        let highest = self.reachable_highest
            [(j as usize / MARCH_TILE) * self.tiles_x + i as usize / MARCH_TILE];
        let start = detail_at(field, i, j) + 1e-4;
        let blocked = (1..=self.reach)
            .map(|t| (t, start + self.rise * t as f64))
            .take_while(|&(_, ray)| ray < highest)
            .any(|(t, ray)| {
                let (x, z) = (i as f32 + self.dx * t as f32, j as f32 + self.dz * t as f32);
                detail_at(field, x.round() as i64, z.round() as i64) > ray
            });
        !blocked
    }
}

/// The detail height at cell (i, j), clamped to the field.
#[inline]
fn detail_at(field: &DetailField, i: i64, j: i64) -> f64 {
    let (w, h) = (field.width as i64, field.height as i64);
    let (i, j) = (i.clamp(0, w - 1), j.clamp(0, h - 1));
    field.data[(j * w + i) as usize]
}

/// Cell (i, j)'s RGBA8 texel of the detail texture, `lit` its sun visibility.
fn detail_texel(field: &DetailField, i: i64, j: i64, lit: bool) -> [u8; 4] {
    let cell = f64::from(field.cell);
    let sx = (detail_at(field, i + 1, j) - detail_at(field, i - 1, j)) / (2.0 * cell);
    let sz = (detail_at(field, i, j + 1) - detail_at(field, i, j - 1)) / (2.0 * cell);
    // 128 is exactly flat (surface.frag decodes (b - 128) / 127); flat is most of the
    // field, and `round` is a call into libm.
    let byte = |v: f32| {
        if v == 0.0 {
            128
        } else {
            (v.clamp(-1.0, 1.0) * 127.0 + 128.0).round() as u8
        }
    };
    [
        byte(sx as f32 / SLOPE_RANGE),
        byte(sz as f32 / SLOPE_RANGE),
        (field.trodden[j as usize * field.width + i as usize] * 255.0) as u8,
        if lit { 255 } else { 0 },
    ]
}

/// Largest side of a walk's bounding box (its detail field's 2048 cells at 5 cm),
/// metres.
pub const MAX_WALK_EXTENT: f32 = 100.0;
/// Longest walk, summed along the path's segments, metres.
pub const MAX_WALK_LENGTH: f32 = 1000.0;

/// Why `path` cannot be walked, if it cannot: fewer than two points, a point not
/// finite, a bounding box wider than `MAX_WALK_EXTENT` or a length beyond
/// `MAX_WALK_LENGTH`.
pub fn check_walk(path: &[[f32; 2]]) -> Result<(), String> {
    if path.len() < 2 {
        return Err("a path needs at least two points x,z;x,z".to_owned());
    }
    if path.iter().flatten().any(|v| !v.is_finite()) {
        return Err("every coordinate must be a finite number of metres".to_owned());
    }
    for k in 0..2 {
        let (lo, hi) = path
            .iter()
            .fold((f32::MAX, f32::MIN), |(a, b), p| (a.min(p[k]), b.max(p[k])));
        if hi - lo > MAX_WALK_EXTENT {
            return Err(format!(
                "the walk spans {:.0} m; at most {MAX_WALK_EXTENT} m a side (its detail field's \
                 {MAX_DETAIL_CELLS} cells at 5 cm)",
                hi - lo
            ));
        }
    }
    let length: f32 = path
        .windows(2)
        .map(|s| ((s[1][0] - s[0][0]).powi(2) + (s[1][1] - s[0][1]).powi(2)).sqrt())
        .sum();
    if length > MAX_WALK_LENGTH {
        return Err(format!(
            "the walk is {length:.0} m long; at most {MAX_WALK_LENGTH} m"
        ));
    }
    Ok(())
}

/// Parses `--footprints`: "off", or a path "x,z;x,z;..." (world metres, at least two
/// points).
pub fn parse_path(text: &str) -> Result<Option<Vec<[f32; 2]>>, String> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("off") {
        return Ok(None);
    }
    let mut path = Vec::new();
    for point in t.split(';').filter(|p| !p.trim().is_empty()) {
        let parts: Vec<&str> = point.split(',').map(str::trim).collect();
        let [x, z] = parts.as_slice() else {
            return Err(format!("\"{point}\" is not a point x,z"));
        };
        let num = |s: &str| {
            s.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("\"{s}\" is not a finite number of metres"))
        };
        path.push([num(x)?, num(z)?]);
    }
    check_walk(&path)?;
    Ok(Some(path))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The detail texture as first written: every cell marched to the full reach, one
    /// row after another (what `detail_texture` stops early and splits over threads).
    fn plain_detail_texture(field: &DetailField, sun: [f32; 3]) -> Vec<u8> {
        let (w, h) = (field.width, field.height);
        let horizontal = (sun[0] * sun[0] + sun[2] * sun[2]).sqrt().max(1e-6);
        let (dx, dz) = (sun[0] / horizontal, sun[2] / horizontal);
        let rise = f64::from(sun[1] / horizontal * field.cell);
        let deepest = field.data.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let reach = if rise > 0.0 {
            ((2.0 * deepest / rise).ceil() as usize).clamp(1, 48)
        } else {
            0
        };
        let at = |i: i64, j: i64| -> f64 {
            let (i, j) = (i.clamp(0, w as i64 - 1), j.clamp(0, h as i64 - 1));
            field.data[j as usize * w + i as usize]
        };
        let byte = |v: f32| (v.clamp(-1.0, 1.0) * 127.0 + 128.0).round() as u8;
        let mut out = Vec::with_capacity(w * h * 4);
        for j in 0..h as i64 {
            for i in 0..w as i64 {
                let sx = (at(i + 1, j) - at(i - 1, j)) / (2.0 * f64::from(field.cell));
                let sz = (at(i, j + 1) - at(i, j - 1)) / (2.0 * f64::from(field.cell));
                let lit = if rise <= 0.0 {
                    0.0
                } else {
                    let start = at(i, j) + 1e-4;
                    let blocked = (1..=reach).any(|t| {
                        let (x, z) = (i as f32 + dx * t as f32, j as f32 + dz * t as f32);
                        at(x.round() as i64, z.round() as i64) > start + rise * t as f64
                    });
                    if blocked { 0.0 } else { 1.0 }
                };
                out.extend_from_slice(&[
                    byte(sx as f32 / SLOPE_RANGE),
                    byte(sz as f32 / SLOPE_RANGE),
                    (field.trodden[(j as usize) * w + i as usize] * 255.0) as u8,
                    (lit * 255.0) as u8,
                ]);
            }
        }
        out
    }

    #[test]
    fn the_detail_texture_is_the_plain_marchs() {
        // A longer walk than `params`': many tiles of the march's bound, prints across
        // their edges.
        let field = walk(&FootprintParams::walk(vec![
            [1.0, 1.0],
            [9.0, 7.0],
            [16.0, 3.0],
        ]));
        assert!(field.width > 4 * MARCH_TILE && field.height > 4 * MARCH_TILE);
        let deg = |a: f32, e: f32| {
            let (a, e) = (a.to_radians(), e.to_radians());
            [e.cos() * a.cos(), e.sin(), e.cos() * a.sin()]
        };
        let cells = field.width * field.height;
        for (sun, low) in [
            (deg(0.0, 8.0), true),
            (deg(130.0, 3.0), true),
            (deg(250.0, 25.0), false),
            (deg(60.0, 70.0), false),
            (deg(10.0, -1.0), false),
        ] {
            let fast = detail_texture(&field, sun);
            let plain = plain_detail_texture(&field, sun);
            assert_eq!(fast.len(), cells * 4);
            let differ = fast.iter().zip(&plain).filter(|(a, b)| a != b).count();
            assert_eq!(differ, 0, "sun {sun:?}: {differ} bytes differ");
            // A low sun casts the prints' shadows on part of the field (a march that
            // never blocks, or always, fails here).
            let shadowed = fast.chunks_exact(4).filter(|t| t[3] == 0).count();
            if low {
                assert!(
                    shadowed > 0 && shadowed < cells,
                    "sun {sun:?}: {shadowed} of {cells}"
                );
            }
        }
        // An empty field (no rows to split) has an empty texture.
        let empty = DetailField {
            width: 0,
            height: 0,
            data: Vec::new(),
            trodden: Vec::new(),
            ..field
        };
        assert!(detail_texture(&empty, deg(0.0, 8.0)).is_empty());
    }

    fn params() -> FootprintParams {
        FootprintParams::walk(vec![[1.0, 1.0], [4.0, 2.0], [6.0, 5.0]])
    }

    #[test]
    fn prints_conserve_the_sand() {
        let field = walk(&params());
        let loose = field.volume();
        // Flat before: the loose sand's change plus what was compacted is zero.
        assert!(
            (loose + field.compacted).abs() < 1e-9,
            "loose {loose}, compacted {}",
            field.compacted
        );
        assert!(field.compacted > 0.0);
        // Prints are hollows with rims: both signs present, the deepest near the
        // sole's depth, no slope steeper than the angle of repose beyond rounding.
        let (min, max) = field
            .data
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        // The heel and ball press up to 4 % past the nominal depth.
        assert!((-0.05 * 1.05..-0.03).contains(&min), "deepest {min}");
        assert!(max > 0.0, "rims {max}");
        let limit = f64::from(34f32.to_radians().tan() * field.cell);
        let mut steep = 0;
        for j in 0..field.height - 1 {
            for i in 0..field.width - 1 {
                let v = field.at(i, j);
                if (v - field.at(i + 1, j)).abs() > limit * 1.5
                    || (v - field.at(i, j + 1)).abs() > limit * 1.5
                {
                    steep += 1;
                }
            }
        }
        assert!(
            steep * 100 < field.width * field.height,
            "{steep} steep cells"
        );
    }

    #[test]
    fn prints_alternate_along_the_path_a_step_apart() {
        let p = params();
        let prints = print_positions(&p);
        // Path length sqrt(10) + sqrt(13) = 6.77 m at 0.7 m steps: 10 prints.
        assert_eq!(prints.len(), 10);
        for pair in prints.windows(2) {
            let (a, b) = (pair[0].0, pair[1].0);
            let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
            assert!((0.6..=0.75).contains(&d), "{d}");
        }
        let field = walk(&p);
        // Every print's centre is trodden and lower than the untouched sand.
        for (c, _) in &prints {
            assert!(field.sample(c[0], c[1]) < -0.02, "{c:?}");
        }
        // Far from the path: untouched.
        assert_eq!(field.sample(1.0, 5.0), 0.0);
    }

    #[test]
    fn paths_parse_and_bad_ones_say_why() {
        assert_eq!(parse_path("off"), Ok(None));
        assert_eq!(
            parse_path("1,2; 3.5,4"),
            Ok(Some(vec![[1.0, 2.0], [3.5, 4.0]]))
        );
        assert!(parse_path("1,2").unwrap_err().contains("two points"));
        assert!(parse_path("1,2;x,3").unwrap_err().contains("\"x\""));
        assert!(parse_path("1,2,3;4,5").unwrap_err().contains("x,z"));
        assert!(parse_path("1,2;inf,3").is_err());
        assert!(
            parse_path("1e9,2;3,4")
                .unwrap_err()
                .contains("at most 100 m")
        );
        let zigzag: Vec<String> = (0..40).map(|i| format!("{},{}", i % 2 * 90, i)).collect();
        assert!(parse_path(&zigzag.join(";")).unwrap_err().contains("long"));
    }
}

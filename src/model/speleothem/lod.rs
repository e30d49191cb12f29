//! Fewer triangles for speleothems far away, drawn from the append-only capture itself.
//!
//! The append-only growth captures the paper's triangle soup: every pass appends, per
//! front triangle, the old front triangle and its link to the new front
//! (`ring_growth.glsl`, `EMIT_FROZEN`). On lavapipe a speleothem's cost is its
//! triangles (set up one by one on the submitting thread) more than its pixels, and in
//! the grow viewer most of them are a few pixels across. This index over the captured
//! vertices gives each speleothem either as its own triangles, as captured, or with
//! every second (fourth...) segment of each ring, where the polygon that leaves lies
//! within a fraction of a pixel of the full one (`segment_step`); the renderer draws
//! its triangles (`render::speleothem_lod`).
//!
//! Rings are found from the captured data, not from a copy of the shader's layout: a
//! frozen vertex keeps its speleothem (`normal_sp.w`), its segment (`extra.x`) and an
//! ID lowered by `2 (pass + 1)` when it froze (`put` in ring_growth.glsl), so the old
//! front's base ring of pass `p` holds ID `-2p`, its tip ring `-2p - 1`, and the link's
//! new base ring `-2p - 2` (the next pass's old base: the same ring). `-ID` orders a
//! speleothem's rings from its base; a ring seen twice under two keys (a pass with no
//! growth between) gives a band of no area, which the rasteriser drops.

use glam::Vec3;

use super::RingVertex;

/// No vertex seen for this segment of a ring.
const MISSING: u32 = u32::MAX;

/// The largest speleothem index taken from captured data (a corrupt capture must not
/// allocate without bound).
const MAX_SPELEOTHEMS: usize = 1 << 16;

/// What the index knows of one speleothem.
#[derive(Debug, Default)]
struct Speleothem {
    /// The first vertex of each of its captured triangles.
    triangles: Vec<u32>,
    /// Its rings from the base: `-ID` and a captured vertex per segment.
    rings: Vec<(u32, Vec<u32>)>,
    /// Bounds of its captured vertices (as captured: less the later thickening).
    bounds: Option<(Vec3, Vec3)>,
    /// The sign of (triangle normal . radial normal) its captured triangles show:
    /// the winding that faces out (None: no triangle with both yet).
    outward: Option<f32>,
}

/// One speleothem's triangles as last drawn, brought up to date by
/// [`CaptureIndex::refresh`] as the capture grows: only what changed is rewritten.
#[derive(Clone, Debug, Default)]
pub struct Part {
    /// Captured vertex indices, three a triangle.
    pub indices: Vec<u32>,
    /// The step asked for and the one drawn (1 where the rings cannot be simplified).
    asked: u32,
    drawn: u32,
    /// Step 1: triangles taken; else: the bands below the last one in `indices`.
    done: usize,
    /// Indices before the last band (its fan, rewritten as the capture grows).
    regular: usize,
    /// Rings when last refreshed.
    rings: usize,
    /// The cells' winding is reversed to face out.
    flip: bool,
}

/// An index over the frozen vertices of an append-only capture, taken in as they are
/// appended.
#[derive(Debug)]
pub struct CaptureIndex {
    segments: u32,
    /// Every vertex taken in, by capture index.
    captured: Vec<RingVertex>,
    speleothems: Vec<Speleothem>,
}

impl CaptureIndex {
    /// An empty index for rings of `segments` segments.
    pub fn new(segments: u32) -> Self {
        Self {
            segments: segments.max(3),
            captured: Vec::new(),
            speleothems: Vec::new(),
        }
    }

    /// Vertices of the capture taken in so far (the next `extend` starts there).
    pub fn vertices(&self) -> u32 {
        self.captured.len() as u32
    }

    /// The captured vertex `i` (taken in).
    pub fn vertex(&self, i: u32) -> Option<&RingVertex> {
        self.captured.get(i as usize)
    }

    /// Every vertex taken in, as captured.
    pub fn captured(&self) -> &[RingVertex] {
        &self.captured
    }

    /// Speleothems seen so far (the highest index + 1).
    pub fn speleothems(&self) -> usize {
        self.speleothems.len()
    }

    /// Bounds of speleothem `i`'s captured vertices, if it has any.
    pub fn bounds(&self, i: usize) -> Option<(Vec3, Vec3)> {
        self.speleothems.get(i).and_then(|s| s.bounds)
    }

    /// Takes in the capture's next vertices, which start at vertex `self.vertices()`
    /// (whole triangles; a trailing part of one is dropped).
    pub fn extend(&mut self, vertices: &[RingVertex]) {
        let whole = vertices.len() / 3 * 3;
        for triangle in vertices[..whole].chunks_exact(3) {
            let first = self.vertices();
            self.captured.extend_from_slice(triangle);
            let sp = triangle[0].speleothem();
            if sp >= MAX_SPELEOTHEMS || triangle.iter().any(|v| v.speleothem() != sp) {
                continue;
            }
            if self.speleothems.len() <= sp {
                self.speleothems.resize_with(sp + 1, Speleothem::default);
            }
            let s = &mut self.speleothems[sp];
            for (k, v) in triangle.iter().enumerate() {
                let p = v.position();
                s.bounds = Some(match s.bounds {
                    Some((lo, hi)) => (lo.min(p), hi.max(p)),
                    None => (p, p),
                });
                let ring = (-v.id()).round();
                let segment = v.segment() as usize;
                if !(0.0..u32::MAX as f32).contains(&ring) || segment >= self.segments as usize {
                    continue;
                }
                let ring = ring as u32;
                // Rings come in order across passes: look from the end.
                let at = match s.rings.iter().rposition(|(q, _)| *q <= ring) {
                    Some(i) if s.rings[i].0 == ring => i,
                    Some(i) => {
                        s.rings
                            .insert(i + 1, (ring, vec![MISSING; self.segments as usize]));
                        i + 1
                    }
                    None => {
                        s.rings
                            .insert(0, (ring, vec![MISSING; self.segments as usize]));
                        0
                    }
                };
                let slot = &mut s.rings[at].1[segment];
                if *slot == MISSING {
                    *slot = first + k as u32;
                }
            }
            if s.outward.is_none() {
                s.outward = facing(&self.captured, [first, first + 1, first + 2]);
            }
            s.triangles.push(first);
        }
    }

    /// Brings `part` up to speleothem `i` drawn with every `step`-th segment (1: its
    /// own triangles, as captured); returns the first index of `part.indices` that
    /// changed (its length where nothing did). The last band keeps every segment on
    /// its top ring, where the next pass's triangles or the front join it at full
    /// detail, so nothing cracks; it is rewritten as rings are added.
    pub fn refresh(&self, i: usize, step: u32, part: &mut Part) -> usize {
        let Some(s) = self.speleothems.get(i) else {
            part.indices.clear();
            return 0;
        };
        let step = step.max(1);
        let rings_now = s.rings.len();
        let wants_retry = part.drawn == 1 && step > 1 && rings_now != part.rings;
        if part.asked != step || wants_retry {
            let flip = (step > 1).then(|| self.winding(s, step)).flatten();
            let drawn = if flip.is_some() { step } else { 1 };
            // Asked again and still not simplifiable: carry on with its own triangles.
            if part.asked != step || drawn != part.drawn {
                *part = Part {
                    asked: step,
                    drawn,
                    flip: flip.unwrap_or(false),
                    ..Part::default()
                };
            }
        }
        part.rings = rings_now;
        if part.drawn == 1 {
            let from = part.indices.len();
            for &t in &s.triangles[part.done..] {
                part.indices.extend([t, t + 1, t + 2]);
            }
            part.done = s.triangles.len();
            return from;
        }
        if rings_now < 2 {
            return part.indices.len();
        }
        let last = rings_now - 2;
        if part.done == last && part.indices.len() > part.regular {
            return part.indices.len();
        }
        let from = part.regular;
        part.indices.truncate(from);
        for band in part.done..last {
            self.band(s, band, part, false);
        }
        part.done = last;
        part.regular = part.indices.len();
        self.band(s, last, part, true);
        from
    }

    /// Whether the cells of `step` segments need their winding reversed to face out
    /// (from the first with an area); None where the rings are not whole or none has.
    fn winding(&self, s: &Speleothem, step: u32) -> Option<bool> {
        let outward = s.outward?;
        if s.rings.len() < 2 || s.rings.iter().any(|(_, r)| r.contains(&MISSING)) {
            return None;
        }
        let n = self.segments as usize;
        for pair in s.rings.windows(2) {
            for j in (0..n).step_by(step as usize) {
                let k = (j + step as usize).min(n) % n;
                let tri = [pair[0].1[j], pair[0].1[k], pair[1].1[k]];
                if let Some(sign) = facing(&self.captured, tri) {
                    return Some(sign != outward);
                }
            }
        }
        None
    }

    /// Band `band` (between rings `band` and `band + 1`) of `s` into `part`, with
    /// every `part.drawn`-th segment; `last`: a fan over every segment of the top ring.
    fn band(&self, s: &Speleothem, band: usize, part: &mut Part, last: bool) {
        let n = self.segments as usize;
        let step = part.drawn as usize;
        let (lower, upper) = (&s.rings[band].1, &s.rings[band + 1].1);
        let flip = part.flip;
        let out = &mut part.indices;
        let mut put = |a: u32, b: u32, c: u32| {
            if flip {
                out.extend([a, c, b]);
            } else {
                out.extend([a, b, c]);
            }
        };
        // Cells of `step` segments around the ring (the last one shorter if `step`
        // does not divide the segments).
        for j in (0..n).step_by(step) {
            let k = (j + step).min(n);
            let (a, b) = (lower[j], lower[k % n]);
            put(a, b, upper[k % n]);
            if last {
                for m in (j..k).rev() {
                    put(a, upper[(m + 1) % n], upper[m]);
                }
            } else {
                put(a, upper[k % n], upper[j]);
            }
        }
    }
}

/// The sign of (normal of triangle `ids` . sum of its radial normals), where both are
/// clearly non-zero.
fn facing(captured: &[RingVertex], ids: [u32; 3]) -> Option<f32> {
    let [a, b, c] = ids.map(|i| captured.get(i as usize).map(|v| (v.position(), v.normal())));
    let ((pa, na), (pb, nb), (pc, nc)) = (a?, b?, c?);
    let normal = (pb - pa).cross(pc - pa);
    let radial = na + nb + nc;
    let d = normal.dot(radial);
    (normal.length() > 1e-12 && radial.length() > 0.5 && d.abs() > 1e-3 * normal.length())
        .then(|| d.signum())
}

/// The most segments a speleothem of `radius_px` pixels (on screen) may skip, as a
/// step of 1, 2, 4 ... at most `segments / 8` (an octagon at the coarsest): the largest
/// whose polygon's sides lie within `max_error_px` of the ring's circle (the sagitta
/// r (1 - cos(pi step / segments))). 1 (every segment) where `max_error_px` <= 0.
pub fn segment_step(radius_px: f32, segments: u32, max_error_px: f32) -> u32 {
    if max_error_px.is_nan() || max_error_px <= 0.0 || !radius_px.is_finite() {
        return 1;
    }
    let mut step = 1;
    while step * 2 <= segments / 8 {
        let next = step * 2;
        let angle = std::f32::consts::PI * next as f32 / segments as f32;
        if radius_px.max(0.0) * (1.0 - angle.cos()) > max_error_px {
            break;
        }
        step = next;
    }
    step
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A capture like the shader's: `rings` rings of a cylinder along +y, frozen IDs
    /// `-q`, each band two triangles a segment, wound to face out.
    fn cylinder(segments: u32, rings: u32) -> Vec<RingVertex> {
        let vertex = |q: u32, j: u32| {
            let angle = std::f32::consts::TAU * (j % segments) as f32 / segments as f32;
            let n = Vec3::new(angle.cos(), 0.0, angle.sin());
            let p = n * 0.1 + Vec3::Y * (0.02 * q as f32);
            RingVertex {
                pos_id: [p.x, p.y, p.z, -(q as f32)],
                normal_sp: [n.x, n.y, n.z, 0.0],
                extra: [(j % segments) as f32, p.y, 0.0, q as f32],
            }
        };
        let mut out = Vec::new();
        for q in 0..rings - 1 {
            for j in 0..segments {
                // Out-facing: (q j, q+1 j+1, q j+1) has normal . radial > 0 here.
                out.extend([vertex(q, j), vertex(q + 1, j + 1), vertex(q, j + 1)]);
                out.extend([vertex(q, j), vertex(q + 1, j), vertex(q + 1, j + 1)]);
            }
        }
        out
    }

    fn triangles<'a>(index: &'a [u32], capture: &'a [RingVertex]) -> Vec<[&'a RingVertex; 3]> {
        index
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| &capture[t[k] as usize]))
            .collect()
    }

    #[test]
    fn every_segment_draws_the_capture_as_it_is() {
        let capture = cylinder(16, 5);
        let mut index = CaptureIndex::new(16);
        // Taken in as passes append, refreshed between.
        let mut part = Part::default();
        index.extend(&capture[..96]);
        assert_eq!(index.refresh(0, 1, &mut part), 0);
        index.extend(&capture[96..]);
        assert_eq!(index.refresh(0, 1, &mut part), 96);
        assert_eq!(index.vertices() as usize, capture.len());
        let identity: Vec<u32> = (0..capture.len() as u32).collect();
        assert_eq!(part.indices, identity);
        assert_eq!(index.refresh(0, 1, &mut part), capture.len(), "nothing new");
    }

    #[test]
    fn every_second_segment_is_closed_faces_out_and_ends_on_the_whole_last_ring() {
        let capture = cylinder(16, 5);
        let mut index = CaptureIndex::new(16);
        index.extend(&capture);
        let mut part = Part::default();
        index.refresh(0, 2, &mut part);
        let out = part.indices.clone();
        // 3 bands of 8 cells at two triangles, the last band 8 fans of 3.
        assert_eq!(out.len() / 3, 3 * 8 * 2 + 8 * 3);
        for t in triangles(&out, &capture) {
            let [a, b, c] = t.map(|v| v.position());
            let radial = t[0].normal() + t[1].normal() + t[2].normal();
            assert!(
                (b - a).cross(c - a).dot(radial) > 0.0,
                "a triangle faces in"
            );
        }
        // Every edge is shared by two triangles except on the first and last rings
        // (edges by position: the capture repeats a ring's vertices).
        let key = |i: u32| {
            let v = &capture[i as usize];
            (-v.id() as u32, v.segment())
        };
        type Edge = ((u32, u32), (u32, u32));
        let mut edges: std::collections::HashMap<Edge, i32> = std::collections::HashMap::new();
        for t in out.chunks_exact(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (a, b) = (key(a), key(b));
                *edges.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        for ((a, b), n) in edges {
            if n != 2 {
                assert_eq!(n, 1);
                assert!(
                    a.0 == b.0 && (a.0 == 0 || a.0 == 4),
                    "open edge off the end rings"
                );
            }
        }
        // The last ring keeps all 16 vertices, the others 8.
        let on_ring = |q: u32| {
            out.iter()
                .filter(|&&i| key(i).0 == q)
                .map(|&i| key(i))
                .collect::<std::collections::HashSet<_>>()
                .len()
        };
        assert_eq!((on_ring(0), on_ring(2), on_ring(4)), (8, 8, 16));
    }

    #[test]
    fn a_part_kept_up_to_date_pass_by_pass_is_the_part_built_at_once() {
        let capture = cylinder(16, 7);
        let mut whole = CaptureIndex::new(16);
        whole.extend(&capture);
        let mut at_once = Part::default();
        whole.refresh(0, 4, &mut at_once);
        let mut index = CaptureIndex::new(16);
        let mut part = Part::default();
        // One band (16 segments x 2 triangles x 3 vertices) at a time.
        for band in capture.chunks(96) {
            index.extend(band);
            let from = index.refresh(0, 4, &mut part);
            assert!(from <= part.indices.len());
        }
        assert_eq!(part.indices, at_once.indices);
        // Another step starts over.
        assert_eq!(index.refresh(0, 2, &mut part), 0);
    }

    #[test]
    fn the_step_keeps_the_polygon_within_the_error() {
        assert_eq!(segment_step(100.0, 32, 0.5), 1);
        assert_eq!(segment_step(20.0, 32, 0.5), 2);
        assert_eq!(segment_step(5.0, 32, 0.5), 4);
        assert_eq!(segment_step(0.1, 32, 0.5), 4, "at most an octagon");
        assert_eq!(segment_step(5.0, 32, 0.0), 1, "0 turns it off");
        assert_eq!(segment_step(f32::NAN, 32, 0.5), 1);
        for r in [1.0, 7.0, 30.0] {
            let s = segment_step(r, 32, 0.5);
            let sagitta = r * (1.0 - (std::f32::consts::PI * s as f32 / 32.0).cos());
            assert!(sagitta <= 0.5);
        }
    }
}

//! The grow viewer's far speleothems with fewer segments (`render::speleothem_lod`,
//! `sediment view grow --speleothem-lod`), on Fig. 9g at the viewer's size: fewer
//! triangles, the same picture within the Figure 9 goldens' tolerance, and a surface
//! that stays closed and faces out on the real capture (stalactites, stalagmites,
//! wind, closed tips).

use crate::common;

use std::collections::HashMap;

use common::Tolerance;
use sediment::Size;
use sediment::frame::{FrameRunner, Time};
use sediment::model::speleothem::RingVertex;
use sediment::render::growth::GrowthPath;
use sediment::scene::grow;

/// Fig. 9g grown and drawn under temporal anti-aliasing with the error bound `lod`
/// (0: off): its picture (the mean of 16 frames) and the frame.
fn fig9g(lod: f32) -> (image::RgbaImage, grow::GrowthFrame) {
    let scene = grow::preset("fig9g")
        .expect("preset")
        .growth_scene()
        .expect("growth");
    let ctx = common::gpu_temporal();
    let camera = grow::default_camera(&scene);
    let mut frame = grow::GrowthFrame::new(&ctx, scene, GrowthPath::XfbAppend).expect("scene");
    frame.set_speleothem_lod(&ctx, lod);
    let passes = frame.plan().passes;
    let mut runner = FrameRunner::new(&ctx, Size::new(720, 480)).expect("runner");
    // A pass a frame, as the viewer grows, then two more: the last passes copied out,
    // taken in and drawn simplified.
    for time in (0..=passes).chain([passes, passes]) {
        runner
            .frame(&mut frame, &camera, Time::At(time), false)
            .expect("frame");
    }
    let (picture, _) = runner
        .render(&mut frame, &camera, Time::At(passes))
        .expect("render");
    common::assert_no_validation_errors(&ctx);
    (picture, frame)
}

/// A vertex's position, to the micrometre (the capture repeats a ring's vertices in
/// the triangles on either side of it).
fn at(v: &RingVertex) -> [i64; 3] {
    let p = v.position();
    [p.x, p.y, p.z].map(|c| (f64::from(c) * 1e6).round() as i64)
}

/// Edges used by one triangle only, by position, of each speleothem.
fn open_edges(triangles: &[RingVertex]) -> Vec<(usize, [i64; 3], [i64; 3])> {
    let mut edges: HashMap<(usize, [i64; 3], [i64; 3]), i32> = HashMap::new();
    for t in triangles.chunks_exact(3) {
        for (a, b) in [(0, 1), (1, 2), (2, 0)] {
            let (a, b) = (at(&t[a]), at(&t[b]));
            if a != b {
                *edges
                    .entry((t[0].speleothem(), a.min(b), a.max(b)))
                    .or_default() += 1;
            }
        }
    }
    edges
        .into_iter()
        .filter(|&(_, n)| n == 1)
        .map(|(e, _)| e)
        .collect()
}

#[test]
fn far_speleothems_with_fewer_segments_look_the_same_and_stay_closed() {
    let (full, frame) = fig9g(0.0);
    assert!(frame.speleothem_lod().is_none(), "0 turns it off");
    let (simplified, frame) = fig9g(sediment::render::speleothem_lod::DEFAULT_MAX_ERROR_PX);
    let lod = frame.speleothem_lod().expect("on");
    let captured = lod.captured();
    let drawn = lod.simplified();
    let (before, after) = (captured.len() / 3, drawn.len() / 3);
    eprintln!("fig9g: {after} triangles drawn for {before} captured");
    assert!(
        before > 30_000,
        "the whole growth taken in: {before} triangles"
    );
    // Measured: 48 %.
    assert!(
        after * 10 < before * 6,
        "{after} of {before} triangles drawn"
    );

    // Closed as the capture is: every edge the simplified surface leaves open lies on
    // an edge of the capture's own open rings (its base in the rock, its last ring
    // where the front joins), and each speleothem faces out as its capture does.
    let open_rings: std::collections::HashSet<(usize, [i64; 3])> = open_edges(captured)
        .into_iter()
        .flat_map(|(s, a, b)| [(s, a), (s, b)])
        .collect();
    let drawn_open: std::collections::HashSet<(usize, [i64; 3], [i64; 3])> =
        open_edges(&drawn).into_iter().collect();
    for &(s, a, b) in &drawn_open {
        assert!(
            open_rings.contains(&(s, a)) && open_rings.contains(&(s, b)),
            "speleothem {s}: an edge {a:?}-{b:?} opened off the capture's open rings"
        );
    }
    // Above the base ring (in the rock) the open edges are the capture's own, segment
    // for segment: the front's band joins the last ring without a crack.
    let base: std::collections::HashSet<(usize, [i64; 3])> = captured
        .iter()
        .filter(|v| v.id() == 0.0)
        .map(|v| (v.speleothem(), at(v)))
        .collect();
    for (s, a, b) in open_edges(captured) {
        if !(base.contains(&(s, a)) && base.contains(&(s, b))) {
            assert!(
                drawn_open.contains(&(s, a, b)),
                "speleothem {s}: the capture's open edge {a:?}-{b:?} is not the simplified \
                 surface's (a crack where the front joins)"
            );
        }
    }
    let facing = |triangles: &[RingVertex]| {
        let mut out: HashMap<usize, (usize, usize)> = HashMap::new();
        for t in triangles.chunks_exact(3) {
            let [a, b, c] = [t[0].position(), t[1].position(), t[2].position()];
            let n = (b - a).cross(c - a);
            let radial = t[0].normal() + t[1].normal() + t[2].normal();
            let d = n.dot(radial);
            if n.length() > 1e-10 && d.abs() > 1e-3 * n.length() * radial.length() {
                let e = out.entry(t[0].speleothem()).or_default();
                if d > 0.0 { e.0 += 1 } else { e.1 += 1 }
            }
        }
        out
    };
    let (was, now) = (facing(captured), facing(&drawn));
    for (s, &(out_now, in_now)) in &now {
        let (out_was, in_was) = was.get(s).copied().unwrap_or_default();
        assert_eq!(
            out_was > in_was,
            out_now > in_now,
            "speleothem {s} turned inside out ({out_was}/{in_was} -> {out_now}/{in_now})"
        );
        assert!(
            out_now.min(in_now) * 50 <= out_now.max(in_now),
            "speleothem {s}: triangles facing both ways ({out_now}/{in_now})"
        );
    }

    // The picture: within the Figure 9 goldens' tolerance of the full capture's.
    let tolerance = Tolerance { mean: 1.0, p99: 16 };
    let (_, d) = common::difference(&simplified, &full);
    eprintln!("simplified vs full: mean {:.3}, p99 {}", d.mean, d.p99);
    assert!(
        d.mean <= tolerance.mean && d.p99 <= tolerance.p99,
        "simplified vs full: mean {:.3}, p99 {}",
        d.mean,
        d.p99
    );
}

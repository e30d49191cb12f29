use super::*;

/// A periodic field of transverse ridges: crests across x (the wind), 3-6 to a
/// period along it and long along z, the pattern a shift along the crests keeps;
/// their relief about 7 % of the period, as the desert presets' (18.6 m in 256).
fn ridges(n: usize, cell: f32) -> Vec<f32> {
    let scale = 0.07 * n as f32 * cell / 19.0;
    let tau = std::f32::consts::TAU;
    let modes = [
        (3.0, 0.0, 4.0, 0.3),
        (5.0, 1.0, 2.0, 1.9),
        (4.0, -1.0, 2.5, 4.1),
        (6.0, 2.0, 1.0, 0.8),
    ];
    (0..n * n)
        .map(|k| {
            let (x, z) = ((k % n) as f32 / n as f32, (k / n) as f32 / n as f32);
            modes
                .iter()
                .map(|&(a, b, amp, phase)| scale * amp * (tau * (a * x + b * z) + phase).sin())
                .sum()
        })
        .collect()
}

fn correlation(a: &[f32], b: &[f32]) -> f32 {
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (ma, mb) = (mean(a), mean(b));
    let (mut ab, mut aa, mut bb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += (x - ma) * (y - mb);
        aa += (x - ma) * (x - ma);
        bb += (y - mb) * (y - mb);
    }
    ab / (aa * bb).sqrt()
}

/// The steepest slope (as a tangent) between neighbouring samples `step` apart over
/// the square from `from` of `count` samples a side.
fn steepest(height: impl Fn(Vec2) -> f32, from: Vec2, count: usize, step: f32) -> f32 {
    let mut out = 0.0f32;
    for j in 0..count {
        for i in 0..count {
            let p = from + Vec2::new(i as f32, j as f32) * step;
            let h = height(p);
            let dx = (height(p + Vec2::X * step) - h).abs();
            let dz = (height(p + Vec2::Y * step) - h).abs();
            out = out.max(dx.max(dz) / step);
        }
    }
    out
}

#[test]
fn the_middle_copy_is_the_simulated_field_and_the_world_around_it_as_steep_as_its_dunes() {
    let (n, cell) = (32, 2.0);
    let heights = ridges(n, cell);
    let world = DesertWorld::new(n as f32 * cell, &heights);
    let tiles = world_tiles(n, cell, &heights, &world);
    let side = 3 * n + 1;
    for j in 0..=n {
        for i in 0..=n {
            assert_eq!(tiles[(n + j) * side + n + i], heights[(j % n) * n + i % n]);
        }
    }
    // Outside it the copies differ from the field...
    let moved = (0..side * side)
        .filter(|&k| {
            let (i, j) = (k % side, k / side);
            (tiles[k] - heights[(j % n) * n + i % n]).abs() > 0.5
        })
        .count();
    assert!(
        moved > side * side / 3,
        "{moved} of {} vertices moved",
        side * side
    );
    // ... and, the highest of copies of it, hardly steeper than it anywhere (the
    // copies' sinking and the warp's stretch add a little), and without a jump.
    let pyramid = HeightPyramid::new(n, cell, &heights);
    let field = |p: Vec2| pyramid.sample(p, 0);
    let own = steepest(field, Vec2::ZERO, 64, 1.0);
    let period = n as f32 * cell;
    let around = steepest(
        |p| world.height(p, field),
        Vec2::splat(-2.0 * period),
        300,
        1.0,
    );
    eprintln!("steepest: the field {own:.3}, the world {around:.3}");
    assert!(
        around <= 1.3 * own,
        "the world's steepest slope {around:.3}, the field's {own:.3}"
    );
}

#[test]
fn a_copy_one_period_over_no_longer_matches() {
    // Heights over 5 x 5 periods of ridges, each against the one a period over along
    // the wind and across it: the same field repeated would correlate at 1.
    let (n, cell) = (64, 4.0);
    let period = n as f32 * cell;
    let heights = ridges(n, cell);
    let world = DesertWorld::new(period, &heights);
    let pyramid = HeightPyramid::new(n, cell, &heights);
    let samples = 200;
    let at = |x: usize, z: usize| {
        let p = Vec2::splat(-2.0 * period)
            + Vec2::new(x as f32, z as f32) * 5.0 * period / samples as f32;
        world.height(p, |q| pyramid.sample(q, 0))
    };
    let grid: Vec<Vec<f32>> = (0..samples)
        .map(|z| (0..samples).map(|x| at(x, z)).collect())
        .collect();
    let shift = samples / 5;
    for (name, dx, dz) in [("along x", shift, 0), ("along z", 0, shift)] {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for z in 0..samples - dz {
            for x in 0..samples - dx {
                a.push(grid[z][x]);
                b.push(grid[z + dz][x + dx]);
            }
        }
        let r = correlation(&a, &b);
        eprintln!("heights one period over {name}: correlation {r:.3}");
        assert!(
            r < 0.5,
            "one period over {name} the field correlates at {r:.3}"
        );
    }
    // The ripple tile's copies do the same to the tile, a tile over: ripples a
    // metre apart (the default: 16 to a tile), crests a few metres long, their
    // contrast (what a defect breaks) over a metre and a half.
    let tile = 16.0;
    let ripple = |p: Vec2| {
        world
            .ripple_copies(world.warped(p), tile)
            .iter()
            .map(|&(offset, w)| {
                let q = (p / tile + offset) * std::f32::consts::TAU;
                w * ((16.0 * q.x).sin()
                    + 0.5 * (16.0 * q.x + 3.0 * q.y).sin()
                    + (q.x + 2.0 * q.y).sin())
            })
            .sum::<f32>()
    };
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for z in 0..160 {
        for x in 0..160 {
            let p = Vec2::new(x as f32, z as f32) * 0.4;
            a.push(ripple(p));
            b.push(ripple(p + Vec2::X * tile));
        }
    }
    let r = correlation(&a, &b);
    eprintln!("ripples one tile over: correlation {r:.3}");
    assert!(r < 0.5, "one tile over the ripples correlate at {r:.3}");
}

#[test]
fn some_copy_always_weighs_and_the_hash_spreads_the_offsets() {
    for j in 0..200 {
        for i in 0..200 {
            let u = Vec2::new(i as f32, j as f32) * 0.037 - Vec2::splat(3.0);
            let corners = simplex_corners(u);
            let heaviest = corners.iter().fold(0.0f32, |m, c| m.max(c.1));
            assert!(heaviest > 0.07, "at {u}: {corners:?}");
        }
    }
    // Offsets over the lattice fill the unit square evenly.
    let mut bins = [0usize; 16];
    for j in -20..20 {
        for i in -20..20 {
            let h = hash2(IVec2::new(i, j));
            assert!((0.0..1.0).contains(&h.x) && (0.0..1.0).contains(&h.y));
            bins[(h.x * 4.0) as usize * 4 + (h.y * 4.0) as usize] += 1;
        }
    }
    assert!(bins.iter().all(|&b| (60..=140).contains(&b)), "{bins:?}");
}

#[test]
fn the_pyramid_keeps_the_mean_and_levels_average_their_blocks() {
    let (n, cell) = (16, 2.0);
    let heights = ridges(n, cell);
    let pyramid = HeightPyramid::new(n, cell, &heights);
    assert_eq!(pyramid.levels.len(), 5);
    let mean = heights.iter().sum::<f32>() / (n * n) as f32;
    assert!((pyramid.levels[4][0] - mean).abs() < 1e-4);
    // At a vertex, level 0 is the field; at a level-2 texel's centre, its 4x4 block.
    assert_eq!(
        pyramid.sample(Vec2::new(3.0, 5.0) * cell, 0),
        heights[5 * n + 3]
    );
    let block: f32 = (0..4)
        .flat_map(|j| (0..4).map(move |i| (i, j)))
        .map(|(i, j)| heights[(4 + j) * n + 8 + i])
        .sum::<f32>()
        / 16.0;
    let centre = Vec2::new(8.0 + 1.5, 4.0 + 1.5) * cell;
    assert!((pyramid.sample(centre, 2) - block).abs() < 1e-4);
    // It wraps.
    let p = Vec2::new(1.3, 7.7);
    assert!(
        (pyramid.sample(p, 1) - pyramid.sample(p + Vec2::splat(n as f32 * cell), 1)).abs() < 1e-4
    );
}

#[test]
fn the_far_rings_cover_the_annulus_and_meet_without_cracks() {
    let (n, cell) = (32, 2.0);
    let heights = ridges(n, cell);
    let period = n as f32 * cell;
    let world = DesertWorld::new(period, &heights);
    let rings = 4;
    let far = far_field(n, cell, &heights, &world, rings);
    // The flat area of the upward quads: the square to the last ring's edge less the
    // 3 x 3 copies (the skirt is vertical: no area).
    let mut area = 0.0;
    for t in far.mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| far.mesh.positions[i as usize]);
        let cross = (b - a).cross(c - a);
        assert!(
            cross.y >= -1e-3 * cross.length(),
            "a far triangle faces down"
        );
        area += 0.5 * cross.y;
    }
    let outer = 3.0 * period * (1 << rings) as f32;
    let expected = outer * outer - (3.0 * period).powi(2);
    assert!(
        (area - expected).abs() < 1e-3 * expected,
        "area {area}, expected {expected}"
    );
    // No cracks: every edge only one triangle has, but for the outermost edge and
    // the first ring's inner edge (under its skirt), lies along an edge of the
    // triangles on its other side (where a finer ring or a ring's corner meets
    // coarser quads, the fine vertices lie on the coarse edge).
    use std::collections::HashMap;
    let mut count: HashMap<(u32, u32), u32> = HashMap::new();
    for t in far.mesh.indices.chunks_exact(3) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let centre = Vec2::splat(0.5 * period);
    let half = |p: Vec3| (p.x - centre.x).abs().max((p.z - centre.y).abs());
    let p = |i: u32| far.mesh.positions[i as usize];
    let open: Vec<(Vec3, Vec3)> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|((a, b), _)| (p(a), p(b)))
        .filter(|&(a, b)| {
            let boundary = |h: f32| (half(a) - h).abs() < 1e-2 && (half(b) - h).abs() < 1e-2;
            let skirt = half(a) <= 1.5 * period + 1e-2 && half(b) <= 1.5 * period + 1e-2;
            !boundary(0.5 * outer) && !skirt
        })
        .collect();
    let on = |q: Vec3, (a, b): (Vec3, Vec3)| {
        let ab = b - a;
        let t = (q - a).dot(ab) / ab.length_squared();
        (-1e-4..=1.0 + 1e-4).contains(&t) && (a + t * ab).distance(q) < 1e-3
    };
    let mut seams = 0;
    for &e in &open {
        let covered = open.iter().any(|&f| {
            f != e && (f.1 - f.0).length() > (e.1 - e.0).length() + 1e-3 && on(e.0, f) && on(e.1, f)
        });
        let covers = open.iter().any(|&f| {
            f != e && (f.1 - f.0).length() + 1e-3 < (e.1 - e.0).length() && on(f.0, e) && on(f.1, e)
        });
        assert!(covered || covers, "a crack along {e:?}");
        seams += 1;
    }
    assert!(seams > 0, "no seams between rings");
}

#[test]
fn one_ripple_copy_holds_most_of_the_sand_and_the_weights_sum_to_one() {
    let world = DesertWorld::new(256.0, &[0.0, 10.0]);
    let (mut single, mut total) = (0, 0);
    for j in 0..150 {
        for i in 0..150 {
            let p = Vec2::new(i as f32, j as f32) * 0.77;
            let copies = world.ripple_copies(p, 16.0);
            let sum: f32 = copies.iter().map(|c| c.1).sum();
            assert!((sum - 1.0).abs() < 1e-5, "at {p}: {copies:?}");
            if copies.iter().any(|c| c.1 >= 0.98) {
                single += 1;
            }
            total += 1;
        }
    }
    let share = single as f32 / total as f32;
    eprintln!(
        "one ripple copy alone on {:.0} % of the sand",
        100.0 * share
    );
    assert!(share > 0.3, "one copy alone on {share}");
}

//! Caves: the octree against brute force, the wall mesh's invariants at every depth
//! 5..9, Table 1's bound on the split, determinism.

use glam::Vec3;

use super::*;
use crate::model::noise::gradient_noise;
use octree::Octree;
use surface::{ambiguous_block, t_junctions};

fn cave(depth: u32, seed: u64) -> Cave {
    let params = CaveParams {
        depth,
        volume: VolumeParams {
            seed,
            ..VolumeParams::default()
        },
        ..CaveParams::default()
    };
    generate(&params, &|_| {}).expect("cave")
}

#[test]
fn walls_are_closed_manifold_crack_free_and_non_degenerate_at_every_depth() {
    for depth in 5..=9 {
        let c = cave(depth, 1);
        let (before, after) = (c.triangles_before_split, c.triangles_after_split());
        eprintln!(
            "depth {depth}: {before} -> {after} triangles (+{:.1} %), {} voxels carved, {:?}",
            100.0 * (after - before) as f64 / before as f64,
            c.carved_voxels,
            c.timings
        );
        c.mesh
            .check_closed_manifold()
            .unwrap_or_else(|e| panic!("depth {depth}: {e}"));
        assert_eq!(
            t_junctions(&c.lattice),
            0,
            "depth {depth}: T-junctions left"
        );
        let area = c.mesh.min_triangle_area();
        assert!(
            area > 0.0,
            "depth {depth}: degenerate triangle (area {area})"
        );
        // The paper's Table 1: the split adds under 10 %, and it does add some (leaves
        // of different sizes meet on the floor).
        assert!(after > before, "depth {depth}: nothing split");
        assert!(
            (after - before) * 10 < before,
            "depth {depth}: {before} -> {after}"
        );
    }
}

#[test]
fn the_fast_octree_equals_sampling_every_voxel() {
    for seed in [1, 2] {
        let volume = VolumeParams {
            seed,
            ..VolumeParams::default()
        };
        let depth = 6;
        let n = 1u32 << depth;
        let fast = Octree::build(&volume, depth);
        let full = Octree::from_voxels(depth, &|i, j, k| {
            if [i, j, k].iter().any(|&c| c == 0 || c == n - 1) {
                return true;
            }
            let p = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) / n as f32;
            !volume.is_empty(p)
        });
        assert_eq!(fast, full, "seed {seed}");
        // Leaves of several sizes: the collapse happened.
        let per_level = fast.leaves_per_level();
        assert!(
            per_level.iter().filter(|&&c| c > 0).count() >= 4,
            "{per_level:?}"
        );
    }
}

#[test]
fn noise_and_density_slopes_stay_under_their_bounds() {
    let e = 1e-3f32;
    let mut steepest = 0.0f32;
    for i in 0..20_000 {
        let p = Vec3::new(
            (i as f32 * 0.1373).fract() * 9.0,
            (i as f32 * 0.0711).fract() * 9.0,
            (i as f32 * 0.2917).fract() * 9.0,
        );
        let g = Vec3::new(
            gradient_noise(3, p + Vec3::X * e) - gradient_noise(3, p - Vec3::X * e),
            gradient_noise(3, p + Vec3::Y * e) - gradient_noise(3, p - Vec3::Y * e),
            gradient_noise(3, p + Vec3::Z * e) - gradient_noise(3, p - Vec3::Z * e),
        ) / (2.0 * e);
        steepest = steepest.max(g.length());
    }
    assert!(
        steepest * 1.25 < volume::NOISE_GRADIENT_BOUND,
        "noise slope {steepest}"
    );
    let volume = VolumeParams::default();
    let bound = volume.lipschitz();
    let mut steepest = 0.0f32;
    for i in 0..20_000 {
        let p = Vec3::new(
            (i as f32 * 0.1373).fract(),
            (i as f32 * 0.0711).fract(),
            (i as f32 * 0.2917).fract(),
        );
        let q = p + Vec3::new(0.3, -0.7, 0.5).normalize() * 1e-3;
        steepest = steepest.max((volume.density(q) - volume.density(p)).abs() / 1e-3);
    }
    assert!(
        steepest < bound,
        "density slope {steepest} vs bound {bound}"
    );
}

#[test]
fn ambiguous_blocks_are_the_edge_and_corner_contacts() {
    let bits = |cells: &[u8]| cells.iter().fold(0u8, |b, &c| b | 1 << c);
    // Voxel index x | y << 1 | z << 2.
    assert!(!ambiguous_block(0), "all cave");
    assert!(!ambiguous_block(0xFF), "all rock");
    assert!(!ambiguous_block(bits(&[0])), "one rock voxel");
    assert!(!ambiguous_block(bits(&[0, 1, 2, 3])), "a floor");
    assert!(!ambiguous_block(bits(&[0, 1, 2])), "an inner corner");
    assert!(
        ambiguous_block(bits(&[0, 3])),
        "rock touching along an edge"
    );
    assert!(ambiguous_block(bits(&[0, 3, 4, 7])), "a full diagonal edge");
    assert!(ambiguous_block(bits(&[0, 7])), "rock touching at a corner");
    assert!(ambiguous_block(!bits(&[0, 7])), "cave touching at a corner");
    assert!(ambiguous_block(bits(&[0, 3, 5, 6])), "checkerboard");
}

#[test]
fn a_large_leaf_beside_small_ones_is_split_in_the_papers_order() {
    // Rock below y = 4 of an 8^3 cube with one rock voxel bump on the floor: the floor
    // squares around the bump are small, the rest large, so large squares carry the
    // corners of small ones.
    let tree = Octree::from_voxels(3, &|i, j, k| {
        [i, j, k].iter().any(|&c| c == 0 || c == 7) || j < 4 || (i, j, k) == (2, 4, 2)
    });
    let blocky = surface::extract(&tree);
    assert!(t_junctions(&blocky) > 0, "the blocky wall has T-junctions");
    let split = surface::split_t_junctions(&blocky);
    assert_eq!(t_junctions(&split), 0);
    assert!(split.triangles.len() > blocky.triangles.len());
    let mut mesh = crate::model::mesh::Mesh {
        positions: split
            .vertices
            .iter()
            .map(|v| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
            .collect(),
        normals: Vec::new(),
        indices: split.triangles.iter().flatten().copied().collect(),
    };
    mesh.check_closed_manifold()
        .expect("closed after the split");
    // The winding is kept: the floor faces up into the cave.
    mesh.recompute_normals();
    let up = split
        .triangles
        .iter()
        .filter(|t| t.iter().all(|&v| split.vertices[v as usize][1] == 4))
        .all(|t| {
            let p = t.map(|v| mesh.positions[v as usize]);
            (p[1] - p[0]).cross(p[2] - p[0]).y > 0.0
        });
    assert!(up, "floor triangles face the cave");
}

#[test]
fn same_seed_same_mesh_and_bad_input_is_named() {
    let (a, b) = (cave(6, 4), cave(6, 4));
    assert_eq!(a.mesh, b.mesh);
    assert_ne!(a.mesh, cave(6, 5).mesh);
    let err = |p: CaveParams| generate(&p, &|_| {}).err().expect("refused").to_string();
    let e = err(CaveParams {
        depth: 12,
        ..CaveParams::default()
    });
    assert!(e.contains("--depth"), "{e}");
    let e = err(CaveParams {
        lambda: 1.5,
        ..CaveParams::default()
    });
    assert!(e.contains("--lambda"), "{e}");
    let e = err(CaveParams {
        depth: 5,
        volume: VolumeParams {
            threshold: -0.1,
            half_height: 0.04,
            half_width: 0.04,
            ..VolumeParams::default()
        },
        ..CaveParams::default()
    });
    assert!(e.contains("carves nothing"), "{e}");
}

mod short {
    use super::super::short_profile::*;
    use glam::Vec3;

    #[test]
    fn the_exact_profile_tends_to_the_corrected_series() {
        // zeta(p(rho)) - series(rho) -> const, with the difference shrinking like
        // rho^(-2/3).
        let diff = |r: f64| zeta(slope_at(r)) - series(r);
        let (d3, d5, d7) = (diff(1e3), diff(1e5), diff(1e7));
        assert!((d5 - d7).abs() < (d3 - d5).abs(), "{d3} {d5} {d7}");
        assert!((d5 - d7).abs() < 0.02, "{d5} vs {d7}");
        // The printed exponent 3/4 would not: its series falls behind by ~rho^(4/3).
        let printed = |r: f64| 0.75 * r.powf(0.75) - r.powf(2.0 / 3.0) - r.ln() / 3.0;
        assert!((zeta(slope_at(1e5)) - printed(1e5)) > 1e5);
    }

    #[test]
    fn the_profile_solves_the_growth_law() {
        // Independently of the closed form: solve cos(theta)^3 rho sin(theta) = 1 for
        // theta at each rho (bisection) and integrate d zeta = tan(theta) d rho
        // (Simpson), from rho_min.
        let theta_at = |r: f64| {
            let (mut lo, mut hi) = (std::f64::consts::FRAC_PI_6, std::f64::consts::FRAC_PI_2);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                // cos^3 sin rho decreases in theta above 30 degrees.
                if mid.cos().powi(3) * mid.sin() * r > 1.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        let r0 = rho_min();
        assert!((r0 - 16.0 * 3f64.sqrt() / 9.0).abs() < 1e-12);
        let mut integral = 0.0;
        let n = 20_000;
        let r_end = 60.0;
        let h = (r_end - r0) / n as f64;
        for i in 0..n {
            let (a, b) = (r0 + i as f64 * h, r0 + (i + 1) as f64 * h);
            let f = |r: f64| theta_at(r.max(r0)).tan();
            integral += h / 6.0 * (f(a) + 4.0 * f(0.5 * (a + b)) + f(b));
        }
        let exact = zeta(slope_at(r_end)) - zeta(P_MIN);
        assert!(
            (integral - exact).abs() < 1e-3 * exact,
            "{integral} vs {exact}"
        );
    }

    #[test]
    fn speleothem_meshes_are_closed_with_a_round_tip_and_outward_normals() {
        for (r, s) in [(7.0, 10.0), (15.0, 1.0), (35.0, 0.5)] {
            let shape = ShortShape { r, s };
            // A stalactite: the body rises from the tip to the ceiling.
            let m = mesh(shape, 0.02, shape.length() * 0.02, 0.3, Vec3::Y, 24);
            m.check_closed_manifold().expect("closed");
            assert!(m.min_triangle_area() > 0.0);
            // Normals point away from the axis on the body.
            let outward = m
                .positions
                .iter()
                .zip(&m.normals)
                .filter(|(p, _)| p.x.hypot(p.z) > 1e-3)
                .all(|(p, n)| Vec3::new(p.x, 0.0, p.z).dot(*n) > 0.0);
            assert!(outward, "r {r} s {s}");
            // The tip hangs lowest, the base ring (at the body's length) is r units
            // wide, and the part in the rock flares by at most half of that.
            let lowest = m.positions.iter().map(|p| p.y).fold(f32::MAX, f32::min);
            assert!(lowest.abs() < 1e-6, "{lowest}");
            let length = shape.length() * 0.02;
            let widest_below = |y: f32| {
                m.positions
                    .iter()
                    .filter(|p| p.y <= y + 1e-5)
                    .map(|p| p.x.hypot(p.z))
                    .fold(0.0, f32::max)
            };
            assert!(
                (widest_below(length) - r * 0.02).abs() < 1e-3 * r,
                "r {r} s {s}"
            );
            let widest = widest_below(f32::MAX);
            assert!(widest <= 1.5 * r * 0.02 + 1e-5, "r {r} s {s}: {widest}");
        }
        // Slender, medium, stocky: length over base radius falls with the class.
        let ratio = |r: f32, s: f32| ShortShape { r, s }.length() / r;
        assert!(ratio(7.0, 10.0) > ratio(15.0, 1.0) && ratio(15.0, 1.0) > ratio(35.0, 0.5));
    }
}

#[test]
fn speleothems_hang_from_the_ceiling_over_their_stalagmites_with_bases_in_rock() {
    use placement::*;
    let c = cave(7, 1);
    let rays = VerticalRays::new(&c.mesh, 4.0 * c.params.voxel_m());
    // Larger units make longer speleothems: columns.
    let mut columns = 0;
    for unit_m in [0.02, 0.06] {
        let params = PlacementParams {
            seed: 3,
            count: 16,
            unit_m,
            growth_ratio: 1.5,
            clear_path: vec![Vec3::new(0.0, 0.0, 32.0), Vec3::new(64.0, 0.0, 32.0)],
            clear_radius_m: 1.0,
        };
        let sites = place(&c.mesh, &rays, &params);
        assert!(
            sites.iter().all(|s| (s.ceiling.z - 32.0).abs() > 1.0),
            "walkway kept clear"
        );
        assert!(sites.len() >= 8, "{} sites", sites.len());
        columns += sites.iter().filter(|s| s.column).count();
        assert_eq!(sites, place(&c.mesh, &rays, &params), "deterministic");
        for (i, s) in sites.iter().enumerate() {
            assert!(s.ceiling.y > s.floor.y);
            assert_eq!((s.ceiling.x, s.ceiling.z), (s.floor.x, s.floor.z));
            if s.column {
                let reach = s.stalactite_m + s.stalagmite_m;
                assert!(
                    reach >= s.ceiling.y - s.floor.y,
                    "site {i}: the column meets"
                );
            } else {
                assert!(
                    (s.stalagmite_m / s.stalactite_m - 1.5).abs() < 1e-4,
                    "site {i}"
                );
            }
            // Stalagmites are blunt (Franke's stationary shape, not an upturned
            // stalactite): at a tenth of the base radius below the apex a third as wide
            // as the base. Columns nowhere narrower than half the base radius.
            let [hanging, standing] = site_profiles(s, params.unit_m);
            let radius = s.base_radius_m(params.unit_m);
            if standing.length() > radius {
                assert!(
                    standing.radius_at(0.1 * radius) > 0.3 * radius,
                    "site {i}: a needle"
                );
            }
            if s.column {
                let (tip_down, tip_up) = (s.ceiling.y - s.stalactite_m, s.floor.y + s.stalagmite_m);
                // Strictly between floor and ceiling (the ends meet the base rings).
                let narrowest = (1..400)
                    .map(|k| s.floor.y + (s.ceiling.y - s.floor.y) * k as f32 / 400.0)
                    .map(|y| {
                        hanging
                            .radius_at(y - tip_down)
                            .max(standing.radius_at(tip_up - y))
                    })
                    .fold(f32::MAX, f32::min);
                assert!(
                    narrowest >= 0.5 * radius - 1e-5,
                    "site {i}: column waist {narrowest} of base radius {radius}"
                );
            }
            for (mesh, (centre, radius)) in site_meshes(s, params.unit_m)
                .iter()
                .zip(base_rings(s, params.unit_m))
            {
                mesh.check_closed_manifold().expect("closed speleothem");
                // The base ring as the mesh has it: the vertices at the base height.
                let ring: Vec<Vec3> = mesh
                    .positions
                    .iter()
                    .copied()
                    .filter(|p| {
                        (p.y - centre.y).abs() < 1e-4
                            && (p.with_y(0.0) - centre.with_y(0.0)).length() > 0.5 * radius
                    })
                    .collect();
                assert_eq!(ring.len(), placement::SEGMENTS as usize, "site {i}");
                for p in ring {
                    assert!(rays.in_rock(p), "site {i}: base vertex {p} is in the cave");
                }
            }
        }
    }
    assert!(columns > 0, "some sites are columns");
}

#[test]
fn octree_progress_counts_every_subtree_once() {
    let seen = std::sync::Mutex::new(Vec::new());
    let tree = Octree::build_with_progress(&VolumeParams::default(), 6, &|done, total| {
        seen.lock().expect("lock").push((done, total));
    });
    assert_eq!(tree, Octree::build(&VolumeParams::default(), 6));
    let seen = seen.into_inner().expect("lock");
    assert!(seen.iter().all(|&(_, t)| t == 64));
    assert_eq!(seen.iter().map(|&(d, _)| d).max(), Some(64));
    // Counts only grow: no subtree is counted twice (the last report is the 64th).
    let mut dones: Vec<u32> = seen.iter().map(|&(d, _)| d).collect();
    dones.sort_unstable();
    dones.dedup();
    assert_eq!(dones.len(), seen.len(), "{seen:?}");
}

/// After smoothing, how far (in voxels) each T-junction's vertex E' lies from the edge
/// A'C' it sat on (the paper's Fig. 2b): the width of the crack there.
fn crack_widths(c: &Cave) -> Vec<f32> {
    let lattice = &c.lattice;
    let index: std::collections::HashMap<[u32; 3], usize> = lattice
        .vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (*v, i))
        .collect();
    let voxel = c.params.voxel_m();
    let mut widths = Vec::new();
    for t in &lattice.triangles {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let (pa, pb) = (lattice.vertices[a as usize], lattice.vertices[b as usize]);
            let d = [0, 1, 2].map(|i| i64::from(pb[i]) - i64::from(pa[i]));
            // Voxel-face edges run along one axis: step through the lattice points.
            let steps = d.iter().map(|x| x.unsigned_abs()).max().unwrap_or(0) as i64;
            if d.iter().filter(|&&x| x != 0).count() != 1 {
                continue;
            }
            for s in 1..steps {
                let p = [0, 1, 2].map(|i| (i64::from(pa[i]) + d[i] / steps * s) as u32);
                if let Some(&e) = index.get(&p) {
                    let (ma, mb, me) = (
                        c.mesh.positions[a as usize],
                        c.mesh.positions[b as usize],
                        c.mesh.positions[e],
                    );
                    let ab = mb - ma;
                    let u = ((me - ma).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                    widths.push((ma + ab * u - me).length() / voxel);
                }
            }
        }
    }
    widths
}

#[test]
fn smoothing_without_the_split_opens_cracks_and_with_it_none() {
    let naive = generate(
        &CaveParams {
            depth: 6,
            split: false,
            ..CaveParams::default()
        },
        &|_| {},
    )
    .expect("cave");
    let widths = crack_widths(&naive);
    let open = widths.iter().filter(|&&w| w > 0.05).count();
    let widest = widths.iter().copied().fold(0.0, f32::max);
    eprintln!(
        "{} T-junctions, {open} open, widest {widest:.2} voxels",
        widths.len()
    );
    assert!(open > 100 && widest > 0.2, "{open} cracks, widest {widest}");
    assert!(
        naive.mesh.check_closed_manifold().is_err(),
        "T-junctions are open edges"
    );
    // The split leaves no T-junction to open.
    assert!(crack_widths(&cave(6, 1)).is_empty());
}

#[test]
fn voxel_speleothems_join_the_walls_where_the_meshes_were() {
    use placement::*;
    let c = cave(7, 1);
    let rays = VerticalRays::new(&c.mesh, 4.0 * c.params.voxel_m());
    let params = PlacementParams {
        seed: 3,
        count: 30,
        unit_m: 0.06,
        growth_ratio: 1.5,
        clear_path: vec![Vec3::new(0.0, 0.0, 32.0), Vec3::new(64.0, 0.0, 32.0)],
        clear_radius_m: 1.0,
    };
    let sites = place(&c.mesh, &rays, &params);
    let solids: Vec<SiteSolid> = sites
        .iter()
        .map(|s| SiteSolid::new(s, params.unit_m))
        .collect();
    let with = with_rock(&c, &solids, &|_| {});
    with.mesh.check_closed_manifold().expect("closed");
    assert_eq!(t_junctions(&with.lattice), 0);
    // On the blocky wall, each wide enough speleothem ends where its outline does: the
    // wall crosses its axis near the stalactite's tip (where the outline is a voxel
    // wide) and near the stalagmite's top.
    let voxel = c.params.voxel_m();
    let blocky = with.blocky_mesh();
    let new_rays = VerticalRays::new(&blocky, 4.0 * voxel);
    let mut checked = 0;
    for s in sites
        .iter()
        .filter(|s| !s.column && s.base_radius_m(params.unit_m) > 2.0 * voxel)
    {
        let [hanging, standing] = site_profiles(s, params.unit_m);
        let crossings = new_rays.crossings(s.ceiling.x + 0.01 * voxel, s.ceiling.z + 0.01 * voxel);
        let tip = s.ceiling.y - s.stalactite_m;
        let thick = tip + hanging.distance_at_radius(voxel);
        let top = s.floor.y + s.stalagmite_m;
        let near = |lo: f32, hi: f32| crossings.iter().any(|&y| (lo..=hi).contains(&y));
        assert!(
            near(tip - voxel, thick + voxel),
            "stalactite end near {tip}..{thick}: {crossings:?}"
        );
        assert!(
            near(top - 1.5 * standing.length().min(voxel), top + voxel),
            "stalagmite top {top}: {crossings:?}"
        );
        checked += 1;
    }
    assert!(checked >= 3, "{checked} speleothems checked");
}

/// A speck of rock floating in a cave is not part of its wall: of a box-shaped cave
/// with a 2-voxel cube of rock in the middle, the wall keeps the box (closed, facing
/// inward: one piece) and drops the cube; without the cube nothing is dropped.
#[test]
fn rock_floating_in_the_cave_is_dropped_from_the_wall() {
    let speck =
        |x: u32, y: u32, z: u32| (7..9).contains(&x) && (7..9).contains(&y) && (7..9).contains(&z);
    let inside = |x: u32, y: u32, z: u32| [x, y, z].iter().all(|c| (3..13).contains(c));
    for with_speck in [true, false] {
        let tree = Octree::from_voxels(4, &|x, y, z| {
            !inside(x, y, z) || with_speck && speck(x, y, z)
        });
        let wall = surface::extract(&tree);
        assert_eq!(surface::pieces(&wall).1, if with_speck { 2 } else { 1 });
        let (kept, dropped) = surface::drop_rock_islands(wall);
        assert_eq!(dropped, usize::from(with_speck));
        assert_eq!(surface::pieces(&kept).1, 1);
        // The box's six faces of 10 x 10 squares, two triangles each.
        assert_eq!(kept.triangles.len(), 6 * 100 * 2);
        assert!(
            kept.triangles
                .iter()
                .flatten()
                .all(|&i| (i as usize) < kept.vertices.len())
        );
    }
}

/// The default cave's wall is one piece at every depth: the 14 cm speck of rock the
/// depth-9 wall had (108 faces, a second component in an exported mesh) is gone.
#[test]
fn the_default_wall_is_one_piece_at_every_depth() {
    for depth in 5..=9 {
        let c = generate(
            &CaveParams {
                depth,
                ..CaveParams::default()
            },
            &|_| {},
        )
        .expect("cave");
        assert_eq!(surface::pieces(&c.lattice).1, 1, "depth {depth}");
    }
}

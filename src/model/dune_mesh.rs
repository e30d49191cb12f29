//! The dune heightfield as a mesh of quads, and the per-quad culling Onoue & Nishita
//! use before bump mapping (3.3.1): quads facing away from the eye and quads outside
//! the view frustum are not drawn.

use glam::{Mat4, Vec3, Vec4};

use super::mesh::Mesh;

/// An `n` x `n` vertex grid over [0, (n-1) cell] in x and z, `heights` in world units.
pub fn dune_mesh(n: usize, cell: f32, heights: &[f32]) -> Mesh {
    let mut mesh = Mesh::height_grid(
        0.5 * (n - 1) as f32 * cell,
        0.0,
        (n - 1) as u32,
        true,
        |_, _| 0.0,
    );
    for (p, &h) in mesh.positions.iter_mut().zip(heights) {
        // height_grid is centred; move it to start at the origin.
        p.x += 0.5 * (n - 1) as f32 * cell;
        p.z += 0.5 * (n - 1) as f32 * cell;
        p.y = h;
    }
    mesh.recompute_normals();
    mesh
}

/// The periodic field repeated `tiles` x `tiles` times (odd; the middle copy covers
/// [0, n cell]): `tiles * n + 1` vertices per side, heights wrapping every `n` samples,
/// so the seam is invisible and the field reaches toward the horizon.
pub fn dune_mesh_tiled(n: usize, cell: f32, heights: &[f32], tiles: usize) -> Mesh {
    let side = tiles * n;
    let half = 0.5 * side as f32 * cell;
    let origin = -(((tiles / 2) * n) as f32) * cell;
    let mut mesh = Mesh::height_grid(half, 0.0, side as u32, true, |_, _| 0.0);
    for (k, p) in mesh.positions.iter_mut().enumerate() {
        let (i, j) = (k % (side + 1), k / (side + 1));
        p.x = origin + i as f32 * cell;
        p.z = origin + j as f32 * cell;
        p.y = heights[(j % n) * n + i % n];
    }
    mesh.recompute_normals();
    mesh
}

/// Indices of the quads to draw (6 per quad, as `Mesh::height_grid` lays them out):
/// with `cull`, a quad is dropped when both its triangles face away from `eye` or all
/// four corners lie outside one plane of the frustum of `view_proj`.
pub fn visible_quads(mesh: &Mesh, eye: Vec3, view_proj: Mat4, cull: bool) -> Vec<u32> {
    if !cull {
        return mesh.indices.clone();
    }
    let mut out = Vec::with_capacity(mesh.indices.len());
    for quad in mesh.indices.chunks_exact(6) {
        let p = |i: u32| mesh.positions[i as usize];
        let facing = |t: &[u32]| {
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            (b - a).cross(c - a).dot(eye - a) > 0.0
        };
        if !facing(&quad[0..3]) && !facing(&quad[3..6]) {
            continue;
        }
        let clip: Vec<Vec4> = quad.iter().map(|&i| view_proj * p(i).extend(1.0)).collect();
        let outside = |f: &dyn Fn(Vec4) -> bool| clip.iter().all(|&c| f(c));
        if outside(&|c| c.x < -c.w)
            || outside(&|c| c.x > c.w)
            || outside(&|c| c.y < -c.w)
            || outside(&|c| c.y > c.w)
            || outside(&|c| c.z < 0.0)
            || outside(&|c| c.z > c.w)
        {
            continue;
        }
        out.extend_from_slice(quad);
    }
    out
}

/// The paper's level of detail (3.3.2), one level per quad of a `side` x `side` grid
/// laid out as `dune_mesh_tiled` lays it (row-major, x fastest): the ripple map level
/// whose texels best match the quad's projected area — `0.5 log2(texels / pixels)`,
/// rounded, clamped to the four levels (0..=3) — where `texels_per_side` ripple
/// texels span a quad's side and `size` is the image in pixels. Quads reaching
/// behind the eye take level 0.
pub fn quad_levels(
    mesh: &Mesh,
    side: usize,
    view_proj: Mat4,
    size: (u32, u32),
    texels_per_side: f32,
) -> Vec<f32> {
    let (w, h) = (size.0 as f32, size.1 as f32);
    let texels = texels_per_side * texels_per_side;
    let mut out = Vec::with_capacity(side * side);
    for j in 0..side {
        for i in 0..side {
            let corner = |a: usize, b: usize| {
                let c = view_proj * mesh.positions[(j + b) * (side + 1) + i + a].extend(1.0);
                (c.w > 1e-6).then(|| {
                    glam::Vec2::new((c.x / c.w + 1.0) * 0.5 * w, (c.y / c.w + 1.0) * 0.5 * h)
                })
            };
            let level = match (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)) {
                (Some(a), Some(b), Some(c), Some(d)) => {
                    // The shoelace area of the projected quad.
                    let area = 0.5
                        * ((a.x * b.y - b.x * a.y)
                            + (b.x * c.y - c.x * b.y)
                            + (c.x * d.y - d.x * c.y)
                            + (d.x * a.y - a.x * d.y))
                            .abs();
                    (0.5 * (texels / area.max(1e-6)).log2())
                        .round()
                        .clamp(0.0, 3.0)
                }
                _ => 0.0,
            };
            out.push(level);
        }
    }
    out
}

/// The dune field's normals at the `res` x `res` texel centres of one period (texel
/// `k` at cell coordinate `(k + 0.5) n / res`, as the dune shadow map's), bilinear
/// between the vertex normals of the periodic mesh: what the dune shading reads
/// instead of the drawn triangles' normals, so that a mesh simplified far away
/// (`lod_quads`) shades as the full one.
pub fn normal_texels(n: usize, cell: f32, heights: &[f32], res: usize) -> Vec<Vec3> {
    let tiled = dune_mesh_tiled(n, cell, heights, 3);
    // The middle copy's vertices: their neighbours on every side are the field's.
    let side = 3 * n + 1;
    let vertex = |i: usize, j: usize| tiled.normals[(n + j % n) * side + n + i % n];
    let mut out = Vec::with_capacity(res * res);
    for k in 0..res {
        for l in 0..res {
            let (u, v) = (
                (l as f32 + 0.5) * n as f32 / res as f32,
                (k as f32 + 0.5) * n as f32 / res as f32,
            );
            let (i, j) = (u.floor() as usize, v.floor() as usize);
            let (fu, fv) = (u - u.floor(), v - v.floor());
            let a = vertex(i, j).lerp(vertex(i + 1, j), fu);
            let b = vertex(i, j + 1).lerp(vertex(i + 1, j + 1), fu);
            out.push(a.lerp(b, fv).normalize_or(Vec3::Y));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_texels_follow_the_vertex_normals_and_wrap() {
        let n = 8;
        let heights: Vec<f32> = (0..n * n)
            .map(|k| (std::f32::consts::TAU * (k % n) as f32 / n as f32).sin())
            .collect();
        let tiled = dune_mesh_tiled(n, 2.0, &heights, 3);
        // Four texels a cell: texel 4i + 2 sits half way between vertices i and i + 1.
        let texels = normal_texels(n, 2.0, &heights, 4 * n);
        let side = 3 * n + 1;
        for i in 0..n {
            let (a, b) = (
                tiled.normals[n * side + n + i],
                tiled.normals[n * side + n + i + 1],
            );
            let expected = a.lerp(b, 0.625).normalize();
            let got = texels[4 * i + 2];
            assert!(
                (got - expected).length() < 1e-5,
                "texel {i}: {got} vs {expected}"
            );
        }
        // Waves along x: the normals lean in x only, and the last texel wraps to the first.
        assert!(texels.iter().all(|t| t.z.abs() < 1e-5 && t.y > 0.0));
        let last = texels[4 * n - 1];
        let wrap = tiled.normals[n * side + 2 * n - 1].lerp(tiled.normals[n * side + n], 0.875);
        assert!((last - wrap.normalize()).length() < 1e-5);
    }

    fn camera(eye: Vec3, target: Vec3) -> Mat4 {
        glam::camera::rh::proj::vulkan::perspective(1.0, 1.5, 0.1, 500.0)
            * glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y)
    }

    #[test]
    fn quads_take_coarser_levels_the_smaller_they_look() {
        // A flat 3x3-tiled field of 8 quads a period, seen low over one edge.
        let n = 8;
        let mesh = dune_mesh_tiled(n, 4.0, &vec![0.0; n * n], 3);
        let side = 3 * n;
        let vp = camera(Vec3::new(16.0, 3.0, 60.0), Vec3::new(16.0, 0.0, 0.0));
        let levels = quad_levels(&mesh, side, vp, (720, 480), 64.0);
        assert_eq!(levels.len(), side * side);
        assert!(
            levels
                .iter()
                .all(|&l| (0.0..=3.0).contains(&l) && l.fract() == 0.0)
        );
        // Along the view (z falling from the eye at 60), levels never get finer with
        // distance, and they span the chain.
        let column = |z: usize| levels[z * side + 10];
        let near = column(side - 2);
        let far = column(1);
        assert!(near < far, "near {near}, far {far}");
        for z in 1..side - 1 {
            assert!(
                column(z) >= column(z + 1),
                "{z}: {} < {}",
                column(z),
                column(z + 1)
            );
        }
        assert_eq!(far, 3.0);
    }

    #[test]
    fn culling_drops_back_faces_and_quads_outside_the_view() {
        let n = 16;
        // A ridge along z at x = 7.5: its +x flank faces +x.
        let heights: Vec<f32> = (0..n * n)
            .map(|i| (6.0 - 1.5 * ((i % n) as f32 - 7.5).abs()).max(0.0))
            .collect();
        let mesh = dune_mesh(n, 1.0, &heights);
        assert_eq!(
            mesh.positions[n * 3 + 2],
            Vec3::new(2.0, heights[n * 3 + 2], 3.0)
        );
        // Everything in view, eye low on the -x side: the +x flank faces away.
        let eye = Vec3::new(-30.0, 2.0, 7.5);
        let vp = camera(eye, Vec3::new(7.5, 0.0, 7.5));
        let all = visible_quads(&mesh, eye, vp, false);
        assert_eq!(all.len(), mesh.indices.len());
        let kept = visible_quads(&mesh, eye, vp, true);
        assert!(kept.len() < all.len(), "back faces culled");
        let back_flank = (n - 1) * 9 + 9; // a quad on the +x flank (x = 9)
        let tiled = dune_mesh_tiled(n, 1.0, &heights, 3);
        assert_eq!(tiled.positions.len(), (3 * n + 1) * (3 * n + 1));
        // Periodic: the same height one period apart, and the middle copy at the origin.
        let at = |i: usize, j: usize| tiled.positions[j * (3 * n + 1) + i];
        assert_eq!(at(n + 3, n + 5), Vec3::new(3.0, heights[5 * n + 3], 5.0));
        assert_eq!(at(3, 5).y, at(2 * n + 3, 5).y);
        let quad = &mesh.indices[back_flank * 6..back_flank * 6 + 6];
        assert!(
            !kept.windows(6).step_by(6).any(|w| w == quad),
            "back-facing flank quad kept"
        );
        // Looking away from the field: nothing survives the frustum test.
        let away = camera(Vec3::new(-30.0, 10.0, 7.5), Vec3::new(-60.0, 10.0, 7.5));
        assert!(visible_quads(&mesh, Vec3::new(-30.0, 10.0, 7.5), away, true).is_empty());
    }
}

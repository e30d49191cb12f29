//! Cave-wall polygons from the octree (the paper's Fig. 1b / 5a-b) and the
//! crack-free triangle split (section 4.1, Figs. 2-4), on integer lattice
//! coordinates (voxels of the finest level) so every test of "lies on" is exact.

use std::collections::HashMap;

use rayon::prelude::*;

use super::octree::{Leaf, Node, Octree};

/// A triangle mesh on the voxel lattice: corners in voxels of the finest level.
/// Triangles wind counter-clockwise seen from the cave (the empty side).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LatticeMesh {
    /// Lattice points (x, y, z), each once, in voxels of the finest level.
    pub vertices: Vec<[u32; 3]>,
    /// Vertex indices of each triangle, counter-clockwise seen from the cave.
    pub triangles: Vec<[u32; 3]>,
}

/// The boundary between rock and cave leaves, two triangles per square. Where leaves
/// of different sizes meet, the square is the smaller leaf's face, so a large
/// square's edge can carry the corners of smaller squares beside it: T-junctions.
pub fn extract(tree: &Octree) -> LatticeMesh {
    let leaves = tree.leaves();
    let quads: Vec<[[u32; 3]; 4]> = leaves
        .par_iter()
        .flat_map_iter(|leaf| leaf_faces(tree, leaf))
        .collect();
    let mut index: HashMap<[u32; 3], u32> = HashMap::with_capacity(quads.len());
    let mut mesh = LatticeMesh::default();
    let mut vertex = |p: [u32; 3], mesh: &mut LatticeMesh| {
        *index.entry(p).or_insert_with(|| {
            mesh.vertices.push(p);
            (mesh.vertices.len() - 1) as u32
        })
    };
    mesh.triangles.reserve(quads.len() * 2);
    for q in quads {
        let v = q.map(|p| vertex(p, &mut mesh));
        mesh.triangles.push([v[0], v[1], v[2]]);
        mesh.triangles.push([v[0], v[2], v[3]]);
    }
    mesh
}

/// The faces of `leaf` that this leaf emits (see [`extract`]): against a larger leaf
/// of the other kind, and against an equal one when this leaf is rock (so a face
/// between equals is emitted once). A subdivided neighbour emits its own.
fn leaf_faces(tree: &Octree, leaf: &Leaf) -> Vec<[[u32; 3]; 4]> {
    let n = tree.resolution();
    let size = leaf.size(tree.depth);
    let o = leaf.origin;
    let mut out = Vec::new();
    for axis in 0..3 {
        for positive in [false, true] {
            let mut nb = o;
            if positive {
                if o[axis] + size >= n {
                    continue;
                }
                nb[axis] += size;
            } else {
                if o[axis] == 0 {
                    continue;
                }
                nb[axis] -= size;
            }
            let (node, level) = tree.find(leaf.level, nb);
            let other_solid = match node {
                Node::Branch(_) => continue,
                Node::Solid => true,
                Node::Empty => false,
            };
            let emit = other_solid != leaf.solid
                && (level < leaf.level || (level == leaf.level && leaf.solid));
            if !emit {
                continue;
            }
            // The square on the plane between the two, normal from rock into cave.
            let (b, c) = ((axis + 1) % 3, (axis + 2) % 3);
            let plane = if positive { o[axis] + size } else { o[axis] };
            let corner = |db: u32, dc: u32| {
                let mut p = [0; 3];
                p[axis] = plane;
                p[b] = o[b] + db;
                p[c] = o[c] + dc;
                p
            };
            // (b, c, axis) is right-handed: this order is counter-clockwise seen from
            // +axis.
            let ccw = [
                corner(0, 0),
                corner(size, 0),
                corner(size, size),
                corner(0, size),
            ];
            let normal_positive = positive == leaf.solid;
            out.push(if normal_positive {
                ccw
            } else {
                [ccw[0], ccw[3], ccw[2], ccw[1]]
            });
        }
    }
    out
}

/// Whether the 2x2x2 voxels around a lattice vertex (bit `x | y << 1 | z << 2` set
/// for rock) would make the boundary there non-manifold: the rock voxels, or the
/// cave voxels, fall apart into more than one face-connected piece within the block
/// (two cubes touching only along an edge or at a corner).
pub fn ambiguous_block(solid: u8) -> bool {
    fn pieces(set: u8) -> u32 {
        let mut seen = 0u8;
        let mut count = 0;
        for start in 0..8 {
            if set >> start & 1 == 0 || seen >> start & 1 == 1 {
                continue;
            }
            count += 1;
            let mut stack = vec![start];
            seen |= 1 << start;
            while let Some(c) = stack.pop() {
                for flip in [1, 2, 4] {
                    let d = c ^ flip;
                    if set >> d & 1 == 1 && seen >> d & 1 == 0 {
                        seen |= 1 << d;
                        stack.push(d);
                    }
                }
            }
        }
        count
    }
    pieces(solid) > 1 || pieces(!solid) > 1
}

/// The 2x2x2 voxels around lattice vertex `v`, as in [`ambiguous_block`].
pub fn block_around(tree: &Octree, v: [u32; 3]) -> u8 {
    let mut bits = 0u8;
    for c in 0..8u32 {
        let voxel = [
            i64::from(v[0]) - 1 + i64::from(c & 1),
            i64::from(v[1]) - 1 + i64::from(c >> 1 & 1),
            i64::from(v[2]) - 1 + i64::from(c >> 2 & 1),
        ];
        if tree.is_solid(voxel) {
            bits |= 1 << c;
        }
    }
    bits
}

/// Removes the configurations that make the voxel boundary non-manifold: every
/// ambiguous block around a wall vertex has its rock voxels carved away (the cave
/// only grows, so this ends), until none is left. Returns the voxels carved and the
/// wall of the final tree (the extraction that found nothing left to carve).
pub fn carve_ambiguities(tree: &mut Octree) -> (usize, LatticeMesh) {
    let n = tree.resolution();
    let mut carved = 0;
    loop {
        let mesh = extract(tree);
        let fixes: Vec<[u32; 3]> = mesh
            .vertices
            .par_iter()
            .filter(|&&v| ambiguous_block(block_around(tree, v)))
            .copied()
            .collect();
        if fixes.is_empty() {
            return (carved, mesh);
        }
        for v in fixes {
            for c in 0..8u32 {
                let voxel = [
                    i64::from(v[0]) + i64::from(c & 1) - 1,
                    i64::from(v[1]) + i64::from(c >> 1 & 1) - 1,
                    i64::from(v[2]) + i64::from(c >> 2 & 1) - 1,
                ];
                // The outer layer stays rock so the cave stays enclosed.
                let inner = voxel.iter().all(|&x| x > 0 && x < i64::from(n) - 1);
                if inner && tree.is_solid(voxel) {
                    tree.carve(voxel.map(|x| x as u32));
                    carved += 1;
                }
            }
        }
        tree.compact();
    }
}

/// The connected piece each vertex of `mesh` belongs to (pieces joined by triangles),
/// numbered from 0 in the order of their first vertex, and the number of pieces.
pub fn pieces(mesh: &LatticeMesh) -> (Vec<u32>, usize) {
    fn root(parent: &mut [u32], mut v: u32) -> u32 {
        while parent[v as usize] != v {
            let up = parent[parent[v as usize] as usize];
            parent[v as usize] = up;
            v = up;
        }
        v
    }
    let mut parent: Vec<u32> = (0..mesh.vertices.len() as u32).collect();
    for t in &mesh.triangles {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            if a != b {
                parent[a.max(b) as usize] = a.min(b);
            }
        }
    }
    let mut label = vec![u32::MAX; mesh.vertices.len()];
    let mut count = 0;
    for v in 0..mesh.vertices.len() as u32 {
        let r = root(&mut parent, v) as usize;
        if label[r] == u32::MAX {
            label[r] = count;
            count += 1;
        }
        label[v as usize] = label[r];
    }
    (label, count as usize)
}

/// The wall without its rock islands: closed pieces that enclose rock rather than
/// cave — specks of rock floating in a passage, where the noise crosses the threshold
/// in a few voxels away from the walls (a 14 cm one at depth 9 with the default
/// seed). The wall's triangles face the cave, so such a piece's signed volume is
/// positive, where the wall round the cave (which the outer layer of rock keeps
/// closed) has a negative one. Returns the wall and the islands dropped.
pub fn drop_rock_islands(mesh: LatticeMesh) -> (LatticeMesh, usize) {
    let (label, count) = pieces(&mesh);
    let mut volume = vec![0i128; count];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize].map(i128::from));
        // Six times the signed volume of the tetrahedron (origin, a, b, c).
        let cross = [
            b[1] * c[2] - b[2] * c[1],
            b[2] * c[0] - b[0] * c[2],
            b[0] * c[1] - b[1] * c[0],
        ];
        volume[label[t[0] as usize] as usize] +=
            a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2];
    }
    let island: Vec<bool> = volume.iter().map(|&v| v > 0).collect();
    let dropped = island.iter().filter(|&&i| i).count();
    if dropped == 0 {
        return (mesh, 0);
    }
    let mut index = vec![u32::MAX; mesh.vertices.len()];
    let mut vertices = Vec::new();
    for (v, p) in mesh.vertices.iter().enumerate() {
        if !island[label[v] as usize] {
            index[v] = vertices.len() as u32;
            vertices.push(*p);
        }
    }
    let triangles = mesh
        .triangles
        .iter()
        .filter(|t| !island[label[t[0] as usize] as usize])
        .map(|t| t.map(|i| index[i as usize]))
        .collect();
    (
        LatticeMesh {
            vertices,
            triangles,
        },
        dropped,
    )
}

fn midpoint(a: [u32; 3], b: [u32; 3]) -> Option<[u32; 3]> {
    let s = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
    s.iter().all(|c| c % 2 == 0).then(|| s.map(|c| c / 2))
}

/// Splits every triangle that has a vertex at the midpoint of one of its edges, in
/// the paper's order (edge BC, then AB, then AC, Fig. 4), keeping the winding, and
/// again on the halves until no edge has one: afterwards every edge is shared by
/// exactly two triangles, so moving vertices (smoothing) cannot open cracks.
/// Octree corners along an edge are dyadic, so a corner anywhere on an edge implies
/// one at its midpoint and halving finds them all.
pub fn split_t_junctions(mesh: &LatticeMesh) -> LatticeMesh {
    let index: HashMap<[u32; 3], u32> = mesh
        .vertices
        .iter()
        .enumerate()
        .map(|(i, &p)| (p, i as u32))
        .collect();
    let at = |a: u32, b: u32| {
        midpoint(mesh.vertices[a as usize], mesh.vertices[b as usize])
            .and_then(|m| index.get(&m).copied())
    };
    let triangles = mesh
        .triangles
        .par_iter()
        .flat_map_iter(|&t| {
            let mut out = Vec::new();
            let mut stack = vec![t];
            while let Some([a, b, c]) = stack.pop() {
                if let Some(m) = at(b, c) {
                    stack.push([a, m, c]);
                    stack.push([a, b, m]);
                } else if let Some(m) = at(a, b) {
                    stack.push([m, b, c]);
                    stack.push([a, m, c]);
                } else if let Some(m) = at(a, c) {
                    stack.push([m, b, c]);
                    stack.push([a, b, m]);
                } else {
                    out.push([a, b, c]);
                }
            }
            out
        })
        .collect();
    LatticeMesh {
        vertices: mesh.vertices.clone(),
        triangles,
    }
}

/// Triangle edges with a mesh vertex strictly inside them (T-junctions).
pub fn t_junctions(mesh: &LatticeMesh) -> usize {
    let index: std::collections::HashSet<[u32; 3]> = mesh.vertices.iter().copied().collect();
    let gcd = |mut a: u32, mut b: u32| {
        while b != 0 {
            (a, b) = (b, a % b);
        }
        a
    };
    mesh.triangles
        .par_iter()
        .map(|t| {
            let mut found = 0;
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (pa, pb) = (mesh.vertices[a as usize], mesh.vertices[b as usize]);
                let d = [0, 1, 2].map(|i| i64::from(pb[i]) - i64::from(pa[i]));
                let g = gcd(
                    gcd(d[0].unsigned_abs() as u32, d[1].unsigned_abs() as u32),
                    d[2].unsigned_abs() as u32,
                );
                for s in 1..g {
                    let p = [0, 1, 2]
                        .map(|i| (i64::from(pa[i]) + d[i] / i64::from(g) * i64::from(s)) as u32);
                    if index.contains(&p) {
                        found += 1;
                    }
                }
            }
            found
        })
        .sum()
}

//! Laplacian smoothing (the paper's eq. 1): `v' = lambda v + (1 - lambda)/n sum v_i`
//! over the n edge-neighbours of each vertex, all vertices at once (Jacobi), k times.

use glam::Vec3;
use rayon::prelude::*;

/// Each vertex's edge-neighbours, sorted and unique, in compressed rows.
pub struct Neighbours {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Neighbours {
    /// The neighbours of vertices `0..vertex_count` along the edges of `triangles`.
    pub fn of(vertex_count: usize, triangles: &[[u32; 3]]) -> Self {
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 6);
        for t in triangles {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                pairs.push((a, b));
                pairs.push((b, a));
            }
        }
        pairs.par_sort_unstable();
        pairs.dedup();
        let mut start = vec![0u32; vertex_count + 1];
        for &(a, _) in &pairs {
            start[a as usize + 1] += 1;
        }
        for i in 0..vertex_count {
            start[i + 1] += start[i];
        }
        Self {
            start,
            list: pairs.into_iter().map(|(_, b)| b).collect(),
        }
    }

    /// Vertex `v`'s edge-neighbours, ascending (empty for a vertex on no triangle).
    pub fn of_vertex(&self, v: usize) -> &[u32] {
        &self.list[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// `iterations` rounds of eq. (1) with weight `lambda` (0..=1; 1 leaves the mesh as
/// it is).
pub fn laplacian(positions: &mut Vec<Vec3>, neighbours: &Neighbours, lambda: f32, iterations: u32) {
    let mut next = positions.clone();
    for _ in 0..iterations {
        next.par_iter_mut().enumerate().for_each(|(v, out)| {
            let ring = neighbours.of_vertex(v);
            if ring.is_empty() {
                *out = positions[v];
                return;
            }
            let sum: Vec3 = ring.iter().map(|&u| positions[u as usize]).sum();
            *out = lambda * positions[v] + (1.0 - lambda) / ring.len() as f32 * sum;
        });
        std::mem::swap(positions, &mut next);
    }
}

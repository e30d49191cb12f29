//! The cave stored in a voxel octree (the paper's previous work, \[8\]): the unit cube
//! split to a maximum depth, every voxel of the finest level classified by the
//! density at its centre, and every node whose voxels all agree collapsed into one
//! leaf — so leaves of different sizes meet along the cave wall.
//!
//! The build is top-down: a node whose centre density lies further from the
//! threshold than the density's Lipschitz bound allows to change across the node is
//! uniform without sampling its voxels. The result is the same tree a full sampling
//! of every voxel followed by bottom-up collapsing gives (tested), at a fraction of
//! the samples. The outermost voxel layer is always rock, so the cave is enclosed.

use std::sync::atomic::{AtomicU32, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use super::volume::VolumeParams;

/// One node: a uniform leaf, or a branch whose 8 children are stored contiguously
/// from the given index (child `c` covers the half `c & 1` in x, `c >> 1 & 1` in y,
/// `c >> 2` in z).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    /// A uniform leaf of rock.
    Solid,
    /// A uniform leaf of cave (air).
    Empty,
    /// A branch; the index of its first child in the node array.
    Branch(u32),
}

/// A leaf of the octree: its level (0 = the whole cube), its corner in voxels of the
/// finest level, and whether it is rock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leaf {
    /// Depth of the leaf, 0 (the whole cube) to the tree's `depth` (one voxel).
    pub level: u32,
    /// Its minimum corner (x, y, z), in voxels of the finest level.
    pub origin: [u32; 3],
    /// True for rock, false for cave.
    pub solid: bool,
}

impl Leaf {
    /// Side in voxels of the finest level.
    pub fn size(&self, depth: u32) -> u32 {
        1 << (depth - self.level)
    }
}

/// The cave's voxel octree, nodes stored breadth-first so siblings are contiguous;
/// node 0 is the root covering the whole cube.
#[derive(Clone, Debug, PartialEq)]
pub struct Octree {
    /// Maximum depth: the finest level has 2^depth voxels a side.
    pub depth: u32,
    nodes: Vec<Node>,
}

/// What the build produces before flattening.
enum Tmp {
    Leaf(bool),
    Branch(Box<[Tmp; 8]>),
}

/// Levels built in parallel (8^2 = 64 subtrees: enough for any core count here).
const PARALLEL_LEVELS: u32 = 2;
const SUBTREES: u32 = 64;

impl Octree {
    /// Builds the octree of `volume` to `depth` (the cube has 2^depth voxels a side).
    pub fn build(volume: &VolumeParams, depth: u32) -> Self {
        Self::build_with_progress(volume, depth, &|_, _| {})
    }

    /// As [`Octree::build`], calling `progress(done, total)` (from any thread) as the
    /// 64 subtrees below level 2 finish.
    pub fn build_with_progress(
        volume: &VolumeParams,
        depth: u32,
        progress: &(dyn Fn(u32, u32) + Sync),
    ) -> Self {
        let builder = Builder {
            volume,
            depth,
            n: 1 << depth,
            lipschitz: volume.lipschitz(),
            progress,
            done: AtomicU32::new(0),
        };
        progress(0, SUBTREES);
        let tmp = builder.node(0, [0, 0, 0]);
        Self::flatten(depth, tmp)
    }

    /// The octree of an explicit voxel grid (`solid(i, j, k)` for every voxel of the
    /// finest level), collapsed bottom-up: the reference the fast build is tested
    /// against, and a way to build small trees by hand.
    pub fn from_voxels(depth: u32, solid: &dyn Fn(u32, u32, u32) -> bool) -> Self {
        fn node(depth: u32, level: u32, o: [u32; 3], solid: &dyn Fn(u32, u32, u32) -> bool) -> Tmp {
            if level == depth {
                return Tmp::Leaf(solid(o[0], o[1], o[2]));
            }
            let half = 1 << (depth - level - 1);
            collapse(std::array::from_fn(|c| {
                node(depth, level + 1, child_origin(o, c, half), solid)
            }))
        }
        Self::flatten(depth, node(depth, 0, [0, 0, 0], solid))
    }

    fn flatten(depth: u32, root: Tmp) -> Self {
        let mut nodes = vec![Node::Solid];
        // Breadth-first so siblings are contiguous.
        let mut queue = std::collections::VecDeque::from([(0usize, root)]);
        while let Some((at, tmp)) = queue.pop_front() {
            nodes[at] = match tmp {
                Tmp::Leaf(true) => Node::Solid,
                Tmp::Leaf(false) => Node::Empty,
                Tmp::Branch(children) => {
                    let first = nodes.len();
                    nodes.resize(first + 8, Node::Solid);
                    for (c, child) in children.into_iter().enumerate() {
                        queue.push_back((first + c, child));
                    }
                    Node::Branch(first as u32)
                }
            };
        }
        Self { depth, nodes }
    }

    /// Voxels a side at the finest level.
    pub fn resolution(&self) -> u32 {
        1 << self.depth
    }

    /// Nodes stored, branches and leaves together (the tree's size, as reported).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Whether voxel (i, j, k) of the finest level is rock; outside the cube is rock.
    pub fn is_solid(&self, v: [i64; 3]) -> bool {
        let n = i64::from(self.resolution());
        if v.iter().any(|&c| c < 0 || c >= n) {
            return true;
        }
        let v = v.map(|c| c as u32);
        matches!(self.find(self.depth, v).0, Node::Solid)
    }

    /// The node covering voxel `v` at `level`, or the leaf above it, and its level.
    pub fn find(&self, level: u32, v: [u32; 3]) -> (Node, u32) {
        let mut node = self.nodes[0];
        let mut at = 0;
        while at < level {
            let Node::Branch(first) = node else {
                break;
            };
            let shift = self.depth - at - 1;
            let c = ((v[0] >> shift) & 1) | ((v[1] >> shift) & 1) << 1 | ((v[2] >> shift) & 1) << 2;
            node = self.nodes[(first + c) as usize];
            at += 1;
        }
        (node, at)
    }

    /// Every leaf, depth-first in child order.
    pub fn leaves(&self) -> Vec<Leaf> {
        let mut out = Vec::new();
        let mut stack = vec![(0usize, 0u32, [0u32; 3])];
        while let Some((at, level, o)) = stack.pop() {
            match self.nodes[at] {
                Node::Solid | Node::Empty => out.push(Leaf {
                    level,
                    origin: o,
                    solid: self.nodes[at] == Node::Solid,
                }),
                Node::Branch(first) => {
                    let half = 1 << (self.depth - level - 1);
                    for c in (0..8).rev() {
                        stack.push((first as usize + c, level + 1, child_origin(o, c, half)));
                    }
                }
            }
        }
        out
    }

    /// Makes voxel `v` of the finest level empty, splitting a larger rock leaf around
    /// it as needed. Call [`Octree::compact`] after a batch of edits.
    pub fn carve(&mut self, v: [u32; 3]) {
        self.set(v, false);
    }

    /// Makes voxel `v` of the finest level rock (the voxel speleothems), splitting a
    /// larger empty leaf around it as needed. Call [`Octree::compact`] after a batch.
    pub fn fill(&mut self, v: [u32; 3]) {
        self.set(v, true);
    }

    fn set(&mut self, v: [u32; 3], solid: bool) {
        let (same, other) = if solid {
            (Node::Solid, Node::Empty)
        } else {
            (Node::Empty, Node::Solid)
        };
        let mut at = 0usize;
        for level in 0..self.depth {
            match self.nodes[at] {
                n if n == same => return,
                n if n == other => {
                    let first = self.nodes.len();
                    self.nodes.resize(first + 8, other);
                    self.nodes[at] = Node::Branch(first as u32);
                }
                _ => {}
            }
            let Node::Branch(first) = self.nodes[at] else {
                unreachable!("just made a branch")
            };
            let shift = self.depth - level - 1;
            let c = ((v[0] >> shift) & 1) | ((v[1] >> shift) & 1) << 1 | ((v[2] >> shift) & 1) << 2;
            at = (first + c) as usize;
        }
        self.nodes[at] = same;
    }

    /// Collapses branches whose children became uniform and drops unused nodes.
    pub fn compact(&mut self) {
        fn rebuild(nodes: &[Node], at: usize) -> Tmp {
            match nodes[at] {
                Node::Solid => Tmp::Leaf(true),
                Node::Empty => Tmp::Leaf(false),
                Node::Branch(first) => {
                    collapse(std::array::from_fn(|c| rebuild(nodes, first as usize + c)))
                }
            }
        }
        *self = Self::flatten(self.depth, rebuild(&self.nodes, 0));
    }

    /// Leaves per level (index = level).
    pub fn leaves_per_level(&self) -> Vec<usize> {
        let mut count = vec![0; self.depth as usize + 1];
        for leaf in self.leaves() {
            count[leaf.level as usize] += 1;
        }
        count
    }
}

fn child_origin(o: [u32; 3], c: usize, half: u32) -> [u32; 3] {
    [
        o[0] + (c as u32 & 1) * half,
        o[1] + (c as u32 >> 1 & 1) * half,
        o[2] + (c as u32 >> 2 & 1) * half,
    ]
}

/// A branch of 8 children, or one leaf if they are all the same leaf.
fn collapse(children: [Tmp; 8]) -> Tmp {
    let first = match children[0] {
        Tmp::Leaf(s) => Some(s),
        Tmp::Branch(_) => None,
    };
    if let Some(s) = first {
        if children
            .iter()
            .all(|c| matches!(c, Tmp::Leaf(t) if *t == s))
        {
            return Tmp::Leaf(s);
        }
    }
    Tmp::Branch(Box::new(children))
}

struct Builder<'a> {
    volume: &'a VolumeParams,
    depth: u32,
    n: u32,
    lipschitz: f32,
    progress: &'a (dyn Fn(u32, u32) + Sync),
    done: AtomicU32,
}

impl Builder<'_> {
    fn voxel_is_solid(&self, v: [u32; 3]) -> bool {
        if v.iter().any(|&c| c == 0 || c == self.n - 1) {
            return true;
        }
        let h = 1.0 / self.n as f32;
        let p = Vec3::new(v[0] as f32 + 0.5, v[1] as f32 + 0.5, v[2] as f32 + 0.5) * h;
        !self.volume.is_empty(p)
    }

    /// Counts the subtrees below `level` as finished.
    fn finished(&self, level: u32) {
        if level <= PARALLEL_LEVELS {
            let n = 8u32.pow(PARALLEL_LEVELS - level);
            let done = self.done.fetch_add(n, Ordering::Relaxed) + n;
            (self.progress)(done, SUBTREES);
        }
    }

    fn node(&self, level: u32, o: [u32; 3]) -> Tmp {
        let tmp = self.node_inner(level, o);
        if level == PARALLEL_LEVELS {
            self.finished(level);
        }
        tmp
    }

    fn node_inner(&self, level: u32, o: [u32; 3]) -> Tmp {
        let size = 1u32 << (self.depth - level);
        if size == 1 {
            return Tmp::Leaf(self.voxel_is_solid(o));
        }
        // The farthest voxel centre is (size - 1) / 2 voxels from the node centre along
        // each axis.
        let h = 1.0 / self.n as f32;
        let centre = (Vec3::new(o[0] as f32, o[1] as f32, o[2] as f32) + size as f32 * 0.5) * h;
        let reach = 3f32.sqrt() * (size - 1) as f32 * 0.5 * h;
        // 1 % slack for f32 rounding in the density.
        let margin = self.lipschitz * reach * 1.01 + 1e-6;
        let d = self.volume.density(centre) - self.volume.threshold;
        let touches_border = o.iter().any(|&c| c == 0 || c + size == self.n);
        let uniform = if d > margin {
            Some(true)
        } else if d < -margin && !touches_border {
            Some(false)
        } else {
            None
        };
        if let Some(solid) = uniform {
            // Above the parallel level, the subtrees this node stands for are done.
            if level < PARALLEL_LEVELS {
                self.finished(level);
            }
            return Tmp::Leaf(solid);
        }
        let half = size / 2;
        let child = |c: usize| self.node(level + 1, child_origin(o, c, half));
        let children: [Tmp; 8] = if level < PARALLEL_LEVELS {
            let v: Vec<Tmp> = (0..8).into_par_iter().map(child).collect();
            let mut it = v.into_iter();
            std::array::from_fn(|_| it.next().expect("8 children"))
        } else {
            std::array::from_fn(child)
        };
        collapse(children)
    }
}

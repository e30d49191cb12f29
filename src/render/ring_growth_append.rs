//! Append-only ring growth on the geometry-shader / transform-feedback pipeline: the
//! paper's pass (`ring_growth.geom`, the same shader) fed only the growth front, so a
//! pass costs O(one ring) instead of O(mesh).
//!
//! Each pass draws the current front band twice. `EmitMode::Frozen` captures what
//! leaves the front (the old band and its link to the new one) into one growing buffer,
//! resuming the transform-feedback counter where the previous pass stopped;
//! `EmitMode::Front` captures the next front band into a small ping-pong buffer. A
//! vertex is written once: the re-streaming pass would thicken it (stopped speleothems)
//! and raise its ID every later pass, so it is stored less the accumulated thickening
//! and ID of its pass and brought up to date when drawn (`model::speleothem::unfreeze`
//! and `surface.vert`). `tests/gpu/ring_growth.rs` holds the result against the CPU
//! reference, triangle for triangle.

use std::sync::Arc;

use super::growth::{Growth, GrowthCounts, GrowthPath, MeshSource};
use super::ring_growth::{EmitMode, XfbCore};
use crate::error::Result;
use crate::gpu::{CaptureMode, Commands, Context, StreamCounts, XfbStream};
use crate::model::speleothem::{
    GrowthPlan, RingVertex, VERTEX_STRIDE, accumulated_thickening, unfreeze, vertex_counts,
};

/// An append-only growth in progress on the GPU.
pub struct AppendGrowth {
    /// Ping-pong: pass `p` writes the next front into `fronts[p % 2]`.
    fronts: [XfbStream; 2],
    /// Every pass appends what left the front here, resuming its counter.
    frozen: XfbStream,
    /// Two stream queries per pass: frozen, then front.
    core: XfbCore,
    frozen_capacity: u64,
    front_capacity: u64,
}

impl AppendGrowth {
    /// Uploads the plan and the base primitives; the frozen buffer holds the plan's
    /// final vertex count, each front buffer the base primitives' (a front band never
    /// has more triangles than the base band).
    pub fn new(ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Self> {
        let core = XfbCore::new(ctx, "append growth", plan, 2)?;
        let front_capacity = core.base_vertices().max(3);
        let frozen_capacity = vertex_counts(plan).last().copied().unwrap_or(0).max(3);
        let stride = u64::from(VERTEX_STRIDE);
        Ok(Self {
            fronts: [
                XfbStream::new(ctx, "append growth front A", front_capacity * stride)?,
                XfbStream::new(ctx, "append growth front B", front_capacity * stride)?,
            ],
            frozen: XfbStream::new(ctx, "append growth frozen", frozen_capacity * stride)?,
            core,
            frozen_capacity,
            front_capacity,
        })
    }

    /// After the submission: every pass's (frozen, front) stream counts, or an error
    /// for the first capture that ran out of room.
    pub fn check_counts(&self) -> Result<Vec<(StreamCounts, StreamCounts)>> {
        let counts = self.core.counts(|i| {
            if i % 2 == 0 {
                self.frozen_capacity
            } else {
                self.front_capacity
            }
        })?;
        Ok(counts.chunks_exact(2).map(|c| (c[0], c[1])).collect())
    }

    /// The front stream pass `pass` captures into.
    fn front(&self, pass: u32) -> &XfbStream {
        &self.fronts[(pass % 2) as usize]
    }
}

impl Growth for AppendGrowth {
    fn path(&self) -> GrowthPath {
        GrowthPath::XfbAppend
    }

    fn passes_done(&self) -> u32 {
        self.core.passes_done
    }

    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let needed = vertex_counts(plan).last().copied().unwrap_or(0);
        self.core.write_plan(plan, needed, self.frozen_capacity)
    }

    fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()> {
        let range = self.core.begin(cmd, passes)?;
        for pass in range.clone() {
            let dst = self.front(pass);
            // The frozen stream appends (from zero on its first pass; after its own
            // last capture: the write-after-write chain runs through its barriers);
            // `dst` was the input of the previous pass.
            XfbStream::prepare_captures(
                cmd,
                &[
                    (&self.frozen, CaptureMode::Append),
                    (dst, CaptureMode::Restart),
                ],
            );
            cmd.begin_rendering_without_attachments(1, 1);
            for (mode, stream, capture) in [
                (EmitMode::Frozen, &self.frozen, CaptureMode::Append),
                (EmitMode::Front, dst, CaptureMode::Restart),
            ] {
                self.core.bind(cmd, pass, mode)?;
                let query = 2 * pass + u32::from(mode == EmitMode::Front);
                self.core.queries.begin(cmd, query)?;
                stream.begin(cmd, capture)?;
                self.core.draw_input(cmd, pass, self.front(pass + 1))?;
                stream.end(cmd)?;
                self.core.queries.end(cmd, query)?;
            }
            cmd.end_rendering();
            XfbStream::finish_captures(cmd, &[&self.frozen, dst]);
        }
        self.core.passes_done = range.end.max(self.core.passes_done);
        Ok(())
    }

    fn counts(&self) -> Result<GrowthCounts> {
        let counts = self.check_counts()?;
        let frozen = frozen_of(&counts);
        Ok(GrowthCounts {
            vertices: match counts.last() {
                Some((_, front)) => frozen + front.written * 3,
                None => self.core.base_vertices(),
            },
            // Each pass emits the front's share only: what froze and the next front.
            emitted: counts
                .iter()
                .map(|(f, front)| (f.written + front.written) * 3)
                .sum(),
        })
    }

    fn frozen_vertices(&self) -> Result<u64> {
        Ok(frozen_of(&self.check_counts()?))
    }

    fn source(&self) -> MeshSource<'_> {
        match self.core.passes_done {
            0 => self.core.base_source(),
            done => MeshSource::Appended {
                frozen: &self.frozen,
                front: self.front(done - 1),
            },
        }
    }

    /// The frozen vertices brought up to date (as the surface shader draws them), then
    /// the front.
    fn read_back(&self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        let done = self.core.passes_done;
        if done == 0 {
            return self.core.base_mesh();
        }
        let thickening = accumulated_thickening(plan, done);
        let mut mesh: Vec<RingVertex> = self
            .frozen
            .read_back::<RingVertex>(ctx)?
            .iter()
            .map(|v| unfreeze(v, &thickening, done))
            .collect();
        mesh.extend(self.front(done - 1).read_back::<RingVertex>(ctx)?);
        Ok(mesh)
    }
}

/// Vertices frozen over the passes of `counts` (each pass's (frozen, front) counts).
fn frozen_of(counts: &[(StreamCounts, StreamCounts)]) -> u64 {
    counts.iter().map(|(f, _)| f.written * 3).sum()
}

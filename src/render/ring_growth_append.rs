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
//! and `surface.vert`). `tests/ring_growth.rs` holds the result against the CPU
//! reference, triangle for triangle.

use std::sync::Arc;

use super::growth::{Growth, GrowthCounts, GrowthPath, MeshSource};
use super::ring_growth::{EmitMode, GrowthPipeline};
use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, CaptureMode, Commands, Context, StreamCounts, StreamQueries, XfbStream, vk,
};
use crate::model::speleothem::{
    GrowthPlan, RingVertex, VERTEX_STRIDE, accumulated_thickening, initial_rings, unfreeze,
    vertex_counts,
};

/// An append-only growth in progress on the GPU.
pub struct AppendGrowth {
    growth: GrowthPipeline,
    /// Two stream queries per pass: frozen, then front.
    queries: StreamQueries,
    /// Ping-pong: pass `p` writes the next front into `fronts[p % 2]`.
    fronts: [XfbStream; 2],
    /// Every pass appends what left the front here, resuming its counter.
    frozen: XfbStream,
    input: Buffer,
    initial_vertices: u32,
    passes_done: u32,
    total_passes: u32,
    frozen_capacity: u64,
    front_capacity: u64,
}

impl AppendGrowth {
    /// Uploads the plan and the base primitives; the frozen buffer holds the plan's
    /// final vertex count, each front buffer the base primitives' (a front band never
    /// has more triangles than the base band).
    pub fn new(ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Self> {
        let growth = GrowthPipeline::new(ctx, plan)?;
        let initial = initial_rings(plan);
        let input = Buffer::with_data(
            ctx,
            "append growth base primitives",
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &initial,
        )?;
        let front_capacity = (initial.len() as u64).max(3);
        let frozen_capacity = vertex_counts(plan).last().copied().unwrap_or(0).max(3);
        let stride = u64::from(VERTEX_STRIDE);
        let fronts = [
            XfbStream::new(ctx, "append growth front A", front_capacity * stride)?,
            XfbStream::new(ctx, "append growth front B", front_capacity * stride)?,
        ];
        let frozen = XfbStream::new(ctx, "append growth frozen", frozen_capacity * stride)?;
        let queries = StreamQueries::new(ctx, "append growth stream queries", 2 * plan.passes)?;
        Ok(Self {
            growth,
            queries,
            fronts,
            frozen,
            input,
            initial_vertices: initial.len() as u32,
            passes_done: 0,
            total_passes: plan.passes,
            frozen_capacity,
            front_capacity,
        })
    }

    /// After the submission: every pass's (frozen, front) stream counts, or an error
    /// for the first capture that ran out of room.
    pub fn check_counts(&self) -> Result<Vec<(StreamCounts, StreamCounts)>> {
        let counts = self.queries.results(2 * self.passes_done)?;
        if let Some((i, c)) = counts.iter().enumerate().find(|(_, c)| c.overflowed()) {
            return Err(Error::CaptureOverflow {
                pass: i as u32 / 2,
                written: c.written,
                needed: c.needed,
                capacity_vertices: if i % 2 == 0 {
                    self.frozen_capacity
                } else {
                    self.front_capacity
                },
            });
        }
        Ok(counts.chunks_exact(2).map(|c| (c[0], c[1])).collect())
    }

    fn front(&self) -> &XfbStream {
        &self.fronts[((self.passes_done.max(1) - 1) % 2) as usize]
    }
}

impl Growth for AppendGrowth {
    fn path(&self) -> GrowthPath {
        GrowthPath::XfbAppend
    }

    fn passes_done(&self) -> u32 {
        self.passes_done
    }

    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let needed = vertex_counts(plan).last().copied().unwrap_or(0);
        if needed > self.frozen_capacity {
            return Ok(false);
        }
        self.growth.write_plan(plan)
    }

    fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()> {
        let first = self.passes_done;
        let last = (first + passes).min(self.total_passes);
        if last == first {
            return Ok(());
        }
        self.queries
            .reset_range(cmd, 2 * first, 2 * (last - first))?;
        for pass in first..last {
            let dst = &self.fronts[(pass % 2) as usize];
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
                self.growth.bind(cmd, pass, mode)?;
                let query = 2 * pass + u32::from(mode == EmitMode::Front);
                self.queries.begin(cmd, query)?;
                stream.begin(cmd, capture)?;
                if pass == 0 {
                    cmd.bind_vertex_buffer(&self.input, 0);
                    cmd.draw(self.initial_vertices, 1);
                } else {
                    self.fronts[((pass + 1) % 2) as usize].draw(cmd, VERTEX_STRIDE, 1)?;
                }
                stream.end(cmd)?;
                self.queries.end(cmd, query)?;
            }
            cmd.end_rendering();
            XfbStream::finish_captures(cmd, &[&self.frozen, dst]);
        }
        self.passes_done = last;
        Ok(())
    }

    fn counts(&self) -> Result<GrowthCounts> {
        let counts = self.check_counts()?;
        let frozen: u64 = counts.iter().map(|(f, _)| f.written * 3).sum();
        Ok(GrowthCounts {
            vertices: match counts.last() {
                Some((_, front)) => frozen + front.written * 3,
                None => u64::from(self.initial_vertices),
            },
            // Each pass emits the front's share only: what froze and the next front.
            emitted: counts
                .iter()
                .map(|(f, front)| (f.written + front.written) * 3)
                .sum(),
        })
    }

    fn source(&self) -> MeshSource<'_> {
        if self.passes_done == 0 {
            MeshSource::Counted {
                buffer: &self.input,
                vertices: self.initial_vertices,
            }
        } else {
            MeshSource::Appended {
                frozen: &self.frozen,
                front: self.front(),
            }
        }
    }

    /// The frozen vertices brought up to date (as the surface shader draws them), then
    /// the front.
    fn read_back(&self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        if self.passes_done == 0 {
            let mut base: Vec<RingVertex> = self.input.read()?;
            base.truncate(self.initial_vertices as usize);
            return Ok(base);
        }
        let thickening = accumulated_thickening(plan, self.passes_done);
        let mut mesh: Vec<RingVertex> = self
            .frozen
            .read_back::<RingVertex>(ctx)?
            .iter()
            .map(|v| unfreeze(v, &thickening, self.passes_done))
            .collect();
        mesh.extend(self.front().read_back::<RingVertex>(ctx)?);
        Ok(mesh)
    }
}

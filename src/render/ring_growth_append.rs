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

use super::ring_growth::{Captured, EmitMode, GrowthPipeline, MeshSource};
use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, Commands, Context, StreamCounts, StreamQueries, capture_buffer, counter_buffer, vk,
};
use crate::model::speleothem::{
    GrowthPlan, RingVertex, VERTEX_STRIDE, accumulated_thickening, initial_rings, unfreeze,
    vertex_counts,
};

/// Counter slots: the two front buffers, then the frozen buffer.
const FROZEN_COUNTER: u64 = 8;

/// An append-only growth in progress on the GPU.
pub struct AppendGrowth {
    growth: GrowthPipeline,
    /// Two stream queries per pass: frozen, then front.
    queries: StreamQueries,
    counters: Buffer,
    fronts: [Buffer; 2],
    frozen: Buffer,
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
            capture_buffer(ctx, "append growth front A", front_capacity * stride)?,
            capture_buffer(ctx, "append growth front B", front_capacity * stride)?,
        ];
        let frozen = capture_buffer(ctx, "append growth frozen", frozen_capacity * stride)?;
        let counters = counter_buffer(ctx, "append growth counters", 3)?;
        let queries = StreamQueries::new(ctx, "append growth stream queries", 2 * plan.passes)?;
        Ok(Self {
            growth,
            queries,
            counters,
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

    pub fn passes_done(&self) -> u32 {
        self.passes_done
    }

    /// Continues with `plan` (the same scene re-planned after a parameter change, whose
    /// passes so far are unchanged); false when it does not fit this growth's buffers.
    pub fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let needed = vertex_counts(plan).last().copied().unwrap_or(0);
        if needed > self.frozen_capacity {
            return Ok(false);
        }
        self.growth.write_plan(plan)
    }

    /// Records the next `passes` growth passes (clamped to the plan) into `cmd`.
    pub fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()> {
        let first = self.passes_done;
        let last = (first + passes).min(self.total_passes);
        if last == first {
            return Ok(());
        }
        self.queries
            .reset_range(cmd, 2 * first, 2 * (last - first))?;
        if first == 0 {
            // The frozen buffer starts empty: its first capture resumes at byte 0.
            cmd.fill_buffer(&self.counters, FROZEN_COUNTER, 4, 0);
            // Read by the resumed capture, then overwritten by its end: read and write.
            cmd.full_barrier();
        }
        cmd.capture_to_vertex_read_barrier();
        cmd.counter_write_to_read_barrier();
        for pass in first..last {
            let dst = (pass % 2) as usize;
            if pass >= 1 {
                // `dst` was the vertex input of the previous pass (write-after-read).
                cmd.vertex_read_to_capture_barrier();
            }
            cmd.begin_rendering_without_attachments(1, 1);
            for mode in [EmitMode::Frozen, EmitMode::Front] {
                self.growth.bind(cmd, pass, mode)?;
                let query = 2 * pass + u32::from(mode == EmitMode::Front);
                let counter = if mode == EmitMode::Frozen {
                    cmd.bind_capture_buffer(0, &self.frozen, 0, None);
                    self.queries.begin(cmd, query)?;
                    cmd.begin_capture(Some((&self.counters, FROZEN_COUNTER)));
                    FROZEN_COUNTER
                } else {
                    cmd.bind_capture_buffer(0, &self.fronts[dst], 0, None);
                    self.queries.begin(cmd, query)?;
                    cmd.begin_capture(None);
                    dst as u64 * 4
                };
                if pass == 0 {
                    cmd.bind_vertex_buffer(&self.input, 0);
                    cmd.draw(self.initial_vertices, 1);
                } else {
                    let src = 1 - dst;
                    cmd.bind_vertex_buffer(&self.fronts[src], 0);
                    cmd.draw_indirect_byte_count(&self.counters, src as u64 * 4, VERTEX_STRIDE, 1);
                }
                cmd.end_capture(Some((&self.counters, counter)));
                self.queries.end(cmd, query)?;
            }
            cmd.end_rendering();
            cmd.capture_to_vertex_read_barrier();
            cmd.counter_write_to_read_barrier();
        }
        self.passes_done = last;
        Ok(())
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

    fn front(&self) -> Captured<'_> {
        let last = ((self.passes_done.max(1) - 1) % 2) as usize;
        Captured {
            buffer: &self.fronts[last],
            counter: &self.counters,
            counter_offset: last as u64 * 4,
        }
    }

    fn frozen(&self) -> Captured<'_> {
        Captured {
            buffer: &self.frozen,
            counter: &self.counters,
            counter_offset: FROZEN_COUNTER,
        }
    }

    /// The current mesh, for drawing.
    pub fn source(&self) -> MeshSource<'_> {
        if self.passes_done == 0 {
            MeshSource::Counted {
                buffer: &self.input,
                vertices: self.initial_vertices,
            }
        } else {
            MeshSource::Appended {
                frozen: self.frozen(),
                front: self.front(),
            }
        }
    }

    /// Reads the current mesh back as the re-streaming pass would hold it: the frozen
    /// vertices brought up to date (as the surface shader draws them), then the front.
    pub fn read_back(&self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        if self.passes_done == 0 {
            let mut base: Vec<RingVertex> = self.input.read()?;
            base.truncate(self.initial_vertices as usize);
            return Ok(base);
        }
        let thickening = accumulated_thickening(plan, self.passes_done);
        let mut mesh: Vec<RingVertex> = self
            .frozen()
            .read_back(ctx)?
            .iter()
            .map(|v| unfreeze(v, &thickening, self.passes_done))
            .collect();
        mesh.extend(self.front().read_back(ctx)?);
        Ok(mesh)
    }
}

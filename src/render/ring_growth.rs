//! The ring-growth pass (Tortelli & Walter 2009) on the geometry-shader /
//! transform-feedback pipeline: `shaders-glsl/speleothem/ring_growth.geom`, whose CPU
//! twin is `model::speleothem::grow_pass`; `tests/gpu/ring_growth.rs` compares them.
//!
//! Ping-pong between two capture buffers; pass 0 draws the base primitives with a CPU
//! vertex count, every later pass draws the previous capture with
//! `vkCmdDrawIndirectByteCountEXT`, so the CPU never reads a count between passes, and
//! any number of passes can go in one command buffer. Each pass's stream query is read
//! afterwards: a pass that needed more room than it had is an error, never a silent
//! truncation.

use std::ops::Range;
use std::sync::Arc;

use super::growth::{Growth, GrowthCounts, GrowthPath, MeshSource};
use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, CaptureMode, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Pipeline,
    PipelineLayout, Pod, StreamCounts, StreamQueries, VertexLayout, XfbStream, vk,
};
use crate::model::speleothem::{
    GrowthPlan, RingVertex, VERTEX_STRIDE, initial_rings, vertex_counts,
};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of `ring_growth.geom`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassPush {
    /// The pass being grown, from 0; selects the plan's steps for this pass.
    pub pass_index: u32,
    /// Speleothems in the plan (its steps are `pass_index * speleothem_count + sp`).
    pub speleothem_count: u32,
    /// Segments around each axis (the plan's); segment indices wrap modulo it.
    pub segments: u32,
    /// An [`EmitMode`].
    pub mode: u32,
}
// SAFETY: repr(C), four u32.
unsafe impl Pod for PassPush {}

/// `ring_growth.vert`: no resources; hands each captured vertex to the geometry shader.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_RING_GROWTH_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// Declared by hand (naga has no geometry stage); exercised by `tests/gpu/ring_growth.rs`.
pub static GEOMETRY_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_RING_GROWTH_GEOM,
    bindings: &[DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer)],
    push_constant_bytes: size_of::<PassPush>() as u32,
};

/// The vertex layout of captured rings (shared with the surface pass).
pub fn ring_vertex_layout() -> VertexLayout {
    VertexLayout {
        stride: VERTEX_STRIDE,
        attributes: vec![
            (0, vk::Format::R32G32B32A32_SFLOAT, 0),
            (1, vk::Format::R32G32B32A32_SFLOAT, 16),
            (2, vk::Format::R32G32B32A32_SFLOAT, 32),
        ],
    }
}

/// What `ring_growth.glsl` emits in a draw (`EMIT_*` there).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EmitMode {
    /// The paper's pass: the whole next mesh.
    All = 0,
    /// Append-only: the next front band only.
    Front = 1,
    /// Append-only: what leaves the front this pass, to be appended.
    Frozen = 2,
}

/// What both GS/XFB paths share: the growth pipeline and its plan, the base
/// primitives, the stream queries (`queries_per_pass` a pass) and the passes done.
pub(crate) struct XfbCore {
    plan_set: DescriptorSet,
    // Read by the shader every pass; rewritten when the plan is steered.
    plan_buffer: Buffer,
    pipeline: Pipeline,
    layout: PipelineLayout,
    pub(crate) queries: StreamQueries,
    queries_per_pass: u32,
    base: Buffer,
    base_vertices: u32,
    speleothem_count: u32,
    segments: u32,
    pub(crate) passes_done: u32,
    total_passes: u32,
}

impl XfbCore {
    pub(crate) fn new(
        ctx: &Arc<Context>,
        name: &str,
        plan: &GrowthPlan,
        queries_per_pass: u32,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "ring growth layout",
            &[&VERTEX_INTERFACE, &GEOMETRY_INTERFACE],
        )?;
        let pipeline = GraphicsPipelineDesc::new("ring growth", VERTEX_INTERFACE.shader)
            .geometry(GEOMETRY_INTERFACE.shader)
            .vertex_layout(ring_vertex_layout())
            .rasterizer_discard(true)
            .build(ctx, &layout)?;
        let plan_buffer = Buffer::with_data(
            ctx,
            "ring growth plan",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &plan.gpu_steps(),
        )?;
        let plan_set = layout.allocate_set("ring growth plan set", 0)?;
        plan_set.write_buffer(0, &plan_buffer)?;
        let initial = initial_rings(plan);
        let base = Buffer::with_data(
            ctx,
            &format!("{name} base primitives"),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &initial,
        )?;
        let queries = StreamQueries::new(
            ctx,
            &format!("{name} stream queries"),
            queries_per_pass * plan.passes,
        )?;
        Ok(Self {
            plan_set,
            plan_buffer,
            pipeline,
            layout,
            queries,
            queries_per_pass,
            base,
            base_vertices: initial.len() as u32,
            speleothem_count: plan.speleothems.len() as u32,
            segments: plan.segments,
            passes_done: 0,
            total_passes: plan.passes,
        })
    }

    /// Vertices of the base primitives.
    pub(crate) fn base_vertices(&self) -> u64 {
        u64::from(self.base_vertices)
    }

    /// Replaces the plan with one of the same shape (speleothems, passes) whose
    /// largest mesh, `needed` vertices, fits `capacity`; false (and nothing changed)
    /// otherwise. No submission may be reading the plan.
    pub(crate) fn write_plan(
        &mut self,
        plan: &GrowthPlan,
        needed: u64,
        capacity: u64,
    ) -> Result<bool> {
        let steps = plan.gpu_steps();
        if needed > capacity
            || plan.speleothems.len() as u32 != self.speleothem_count
            || std::mem::size_of_val(steps.as_slice()) as u64 != self.plan_buffer.size()
        {
            return Ok(false);
        }
        self.plan_buffer.write(0, &steps)?;
        Ok(true)
    }

    /// The passes the next `record(passes)` grows (clamped to the plan), with their
    /// stream queries reset; empty when there is nothing to grow.
    pub(crate) fn begin(&self, cmd: &Commands<'_>, passes: u32) -> Result<Range<u32>> {
        let first = self.passes_done;
        let last = (first + passes).min(self.total_passes);
        if last > first {
            let k = self.queries_per_pass;
            self.queries
                .reset_range(cmd, k * first, k * (last - first))?;
        }
        Ok(first..last)
    }

    /// Binds the pipeline for pass `pass` emitting `mode` (inside a rendering scope).
    pub(crate) fn bind(&self, cmd: &Commands<'_>, pass: u32, mode: EmitMode) -> Result<()> {
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.plan_set]);
        cmd.push_constants(
            &self.layout,
            &PassPush {
                pass_index: pass,
                speleothem_count: self.speleothem_count,
                segments: self.segments,
                mode: mode as u32,
            },
        )
    }

    /// Draws pass `pass`'s input: the base primitives (a CPU vertex count) for the
    /// first pass, else what `previous` captured (DrawAuto).
    pub(crate) fn draw_input(
        &self,
        cmd: &Commands<'_>,
        pass: u32,
        previous: &XfbStream,
    ) -> Result<()> {
        if pass == 0 {
            cmd.bind_vertex_buffer(&self.base, 0);
            cmd.draw(self.base_vertices, 1);
            Ok(())
        } else {
            previous.draw(cmd, VERTEX_STRIDE, 1)
        }
    }

    /// Every pass's stream counts so far, or the error of the first capture that ran
    /// out of room (`capacity(i)`: the vertices query `i`'s buffer holds).
    pub(crate) fn counts(&self, capacity: impl Fn(u32) -> u64) -> Result<Vec<StreamCounts>> {
        let k = self.queries_per_pass;
        let counts = self.queries.results(k * self.passes_done)?;
        if let Some((i, c)) = counts.iter().enumerate().find(|(_, c)| c.overflowed()) {
            return Err(Error::CaptureOverflow {
                pass: i as u32 / k,
                written: c.written,
                needed: c.needed,
                capacity_vertices: capacity(i as u32),
            });
        }
        Ok(counts)
    }

    /// Before the first pass: the base primitives.
    pub(crate) fn base_source(&self) -> MeshSource<'_> {
        MeshSource::Counted {
            buffer: &self.base,
            vertices: self.base_vertices,
        }
    }

    /// The base primitives, read back.
    pub(crate) fn base_mesh(&self) -> Result<Vec<RingVertex>> {
        let mut base: Vec<RingVertex> = self.base.read()?;
        base.truncate(self.base_vertices as usize);
        Ok(base)
    }
}

/// A growth in progress on the GPU, re-streaming the whole mesh every pass.
pub struct RingGrowth {
    /// Ping-pong: pass `p` captures into `captures[p % 2]` from the other one.
    captures: [XfbStream; 2],
    core: XfbCore,
    capacity_vertices: u64,
}

impl RingGrowth {
    /// Uploads the plan and the base primitives. Capture buffers hold
    /// `capacity_vertices` (default: exactly what the plan predicts for the last pass).
    pub fn new(
        ctx: &Arc<Context>,
        plan: &GrowthPlan,
        capacity_vertices: Option<u64>,
    ) -> Result<Self> {
        let core = XfbCore::new(ctx, "ring growth", plan, 1)?;
        let predicted = vertex_counts(plan)
            .last()
            .copied()
            .unwrap_or(core.base_vertices());
        let capacity_vertices = capacity_vertices.unwrap_or(predicted).max(3);
        let bytes = capacity_vertices * u64::from(VERTEX_STRIDE);
        Ok(Self {
            captures: [
                XfbStream::new(ctx, "ring growth capture A", bytes)?,
                XfbStream::new(ctx, "ring growth capture B", bytes)?,
            ],
            core,
            capacity_vertices,
        })
    }

    /// Vertices each of the two capture buffers holds (at least 3).
    pub fn capacity_vertices(&self) -> u64 {
        self.capacity_vertices
    }

    /// After the submission: every pass's stream counts, or an error for the first
    /// pass whose capture buffer was too small.
    pub fn check_counts(&self) -> Result<Vec<StreamCounts>> {
        self.core.counts(|_| self.capacity_vertices)
    }

    /// The stream pass `pass` captures into.
    fn capture(&self, pass: u32) -> &XfbStream {
        &self.captures[(pass % 2) as usize]
    }
}

impl Growth for RingGrowth {
    fn path(&self) -> GrowthPath {
        GrowthPath::XfbRestream
    }

    fn passes_done(&self) -> u32 {
        self.core.passes_done
    }

    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let needed = vertex_counts(plan).into_iter().max().unwrap_or(0);
        self.core.write_plan(plan, needed, self.capacity_vertices)
    }

    fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()> {
        let range = self.core.begin(cmd, passes)?;
        for pass in range.clone() {
            let dst = self.capture(pass);
            // `dst` was the input of the previous pass: its stream orders the reads.
            XfbStream::prepare_captures(cmd, &[(dst, CaptureMode::Restart)]);
            cmd.begin_rendering_without_attachments(1, 1);
            self.core.bind(cmd, pass, EmitMode::All)?;
            self.core.queries.begin(cmd, pass)?;
            dst.begin(cmd, CaptureMode::Restart)?;
            self.core.draw_input(cmd, pass, self.capture(pass + 1))?;
            dst.end(cmd)?;
            self.core.queries.end(cmd, pass)?;
            cmd.end_rendering();
            XfbStream::finish_captures(cmd, &[dst]);
        }
        self.core.passes_done = range.end.max(self.core.passes_done);
        Ok(())
    }

    fn counts(&self) -> Result<GrowthCounts> {
        let counts = self.check_counts()?;
        Ok(GrowthCounts {
            vertices: counts
                .last()
                .map_or(self.core.base_vertices(), |c| c.written * 3),
            emitted: counts.iter().map(|c| c.written * 3).sum(),
        })
    }

    fn source(&self) -> MeshSource<'_> {
        match self.core.passes_done {
            0 => self.core.base_source(),
            done => MeshSource::Captured(self.capture(done - 1)),
        }
    }

    fn read_back(&self, ctx: &Arc<Context>, _plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        match self.core.passes_done {
            0 => self.core.base_mesh(),
            done => self.capture(done - 1).read_back(ctx),
        }
    }
}

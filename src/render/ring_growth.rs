//! The ring-growth pass (Tortelli & Walter 2009) on the geometry-shader /
//! transform-feedback pipeline: `shaders-glsl/speleothem/ring_growth.geom`, whose CPU
//! twin is `model::speleothem::grow_pass`; `tests/ring_growth.rs` compares them.
//!
//! Ping-pong between two capture buffers; pass 0 draws the base primitives with a CPU
//! vertex count, every later pass draws the previous capture with
//! `vkCmdDrawIndirectByteCountEXT`, so the CPU never reads a count between passes, and
//! any number of passes can go in one command buffer. Each pass's stream query is read
//! afterwards: a pass that needed more room than it had is an error, never a silent
//! truncation.

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
    pub pass_index: u32,
    pub speleothem_count: u32,
    pub segments: u32,
    /// An [`EmitMode`].
    pub mode: u32,
}
// SAFETY: repr(C), four u32.
unsafe impl Pod for PassPush {}

pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_RING_GROWTH_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// Declared by hand (naga has no geometry stage); exercised by `tests/ring_growth.rs`.
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

/// The growth pipeline and its plan, shared by the re-streaming and the append-only
/// paths.
pub(crate) struct GrowthPipeline {
    plan_set: DescriptorSet,
    // Read by the shader every pass; rewritten when the plan is steered.
    plan_buffer: Buffer,
    pipeline: Pipeline,
    layout: PipelineLayout,
    speleothem_count: u32,
    segments: u32,
}

impl GrowthPipeline {
    pub(crate) fn new(ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Self> {
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
        Ok(Self {
            plan_set,
            plan_buffer,
            pipeline,
            layout,
            speleothem_count: plan.speleothems.len() as u32,
            segments: plan.segments,
        })
    }

    /// Replaces the plan with one of the same shape (speleothems, passes), e.g. the same
    /// scene re-planned after a parameter change; false (and nothing changed) otherwise.
    /// No submission may be reading the plan.
    pub(crate) fn write_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let steps = plan.gpu_steps();
        if plan.speleothems.len() as u32 != self.speleothem_count
            || std::mem::size_of_val(steps.as_slice()) as u64 != self.plan_buffer.size()
        {
            return Ok(false);
        }
        self.plan_buffer.write(0, &steps)?;
        Ok(true)
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
}

/// A growth in progress on the GPU, re-streaming the whole mesh every pass.
pub struct RingGrowth {
    queries: StreamQueries,
    /// Ping-pong: pass `p` captures into `captures[p % 2]` from the other one.
    captures: [XfbStream; 2],
    input: Buffer,
    growth: GrowthPipeline,
    initial_vertices: u32,
    passes_done: u32,
    total_passes: u32,
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
        let growth = GrowthPipeline::new(ctx, plan)?;
        let initial = initial_rings(plan);
        let input = Buffer::with_data(
            ctx,
            "ring growth base primitives",
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &initial,
        )?;
        let predicted = vertex_counts(plan)
            .last()
            .copied()
            .unwrap_or(initial.len() as u64);
        let capacity_vertices = capacity_vertices.unwrap_or(predicted).max(3);
        let bytes = capacity_vertices * u64::from(VERTEX_STRIDE);
        let captures = [
            XfbStream::new(ctx, "ring growth capture A", bytes)?,
            XfbStream::new(ctx, "ring growth capture B", bytes)?,
        ];
        let queries = StreamQueries::new(ctx, "ring growth stream queries", plan.passes)?;
        Ok(Self {
            queries,
            captures,
            input,
            growth,
            initial_vertices: initial.len() as u32,
            passes_done: 0,
            total_passes: plan.passes,
            capacity_vertices,
        })
    }

    pub fn capacity_vertices(&self) -> u64 {
        self.capacity_vertices
    }

    /// After the submission: every pass's stream counts, or an error for the first
    /// pass whose capture buffer was too small.
    pub fn check_counts(&self) -> Result<Vec<StreamCounts>> {
        let counts = self.queries.results(self.passes_done)?;
        if let Some((pass, c)) = counts.iter().enumerate().find(|(_, c)| c.overflowed()) {
            return Err(Error::CaptureOverflow {
                pass: pass as u32,
                written: c.written,
                needed: c.needed,
                capacity_vertices: self.capacity_vertices,
            });
        }
        Ok(counts)
    }

    /// The stream the last pass captured into.
    fn last(&self) -> &XfbStream {
        &self.captures[((self.passes_done.max(1) - 1) % 2) as usize]
    }
}

impl Growth for RingGrowth {
    fn path(&self) -> GrowthPath {
        GrowthPath::XfbRestream
    }

    fn passes_done(&self) -> u32 {
        self.passes_done
    }

    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let needed = vertex_counts(plan).into_iter().max().unwrap_or(0);
        if needed > self.capacity_vertices {
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
        self.queries.reset_range(cmd, first, last - first)?;
        for pass in first..last {
            let dst = &self.captures[(pass % 2) as usize];
            // `dst` was the input of the previous pass: its stream orders the reads.
            XfbStream::prepare_captures(cmd, &[(dst, CaptureMode::Restart)]);
            cmd.begin_rendering_without_attachments(1, 1);
            self.growth.bind(cmd, pass, EmitMode::All)?;
            self.queries.begin(cmd, pass)?;
            dst.begin(cmd, CaptureMode::Restart)?;
            if pass == 0 {
                cmd.bind_vertex_buffer(&self.input, 0);
                cmd.draw(self.initial_vertices, 1);
            } else {
                self.captures[((pass + 1) % 2) as usize].draw(cmd, VERTEX_STRIDE, 1)?;
            }
            dst.end(cmd)?;
            self.queries.end(cmd, pass)?;
            cmd.end_rendering();
            XfbStream::finish_captures(cmd, &[dst]);
        }
        self.passes_done = last;
        Ok(())
    }

    fn counts(&self) -> Result<GrowthCounts> {
        let counts = self.check_counts()?;
        Ok(GrowthCounts {
            vertices: counts
                .last()
                .map_or(u64::from(self.initial_vertices), |c| c.written * 3),
            emitted: counts.iter().map(|c| c.written * 3).sum(),
        })
    }

    fn source(&self) -> MeshSource<'_> {
        if self.passes_done == 0 {
            MeshSource::Counted {
                buffer: &self.input,
                vertices: self.initial_vertices,
            }
        } else {
            MeshSource::Captured(self.last())
        }
    }

    fn read_back(&self, ctx: &Arc<Context>, _plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        if self.passes_done == 0 {
            let mut base: Vec<RingVertex> = self.input.read()?;
            base.truncate(self.initial_vertices as usize);
            return Ok(base);
        }
        self.last().read_back(ctx)
    }
}

//! The compute growth path: `shaders-glsl/speleothem/ring_growth.comp` runs the same
//! per-triangle pass as the geometry shader (both include `ring_growth.glsl`), each
//! invocation over a run of consecutive triangles, and writes the output compactly, in
//! input order, into a storage buffer the surface pass
//! then draws — so its mesh equals the GS capture and the CPU reference vertex for
//! vertex (`tests/gpu/ring_growth.rs`). Like the paper's path it re-streams the whole mesh
//! each pass; unlike it, lavapipe runs it on every core.

use std::sync::Arc;

use super::growth::{Growth, GrowthCounts, GrowthPath, MeshSource};
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, Pipeline, PipelineLayout, Pod, TexelView,
    vk,
};
use crate::model::speleothem::{GrowthPlan, RingVertex, initial_rings, vertex_counts};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of `ring_growth.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ComputePush {
    pass_index: u32,
    speleothem_count: u32,
    segments: u32,
    triangles: u32,
}
// SAFETY: repr(C), four u32.
unsafe impl Pod for ComputePush {}

const fn texels(binding: u32) -> DescriptorBinding {
    DescriptorBinding::new(0, binding, DescriptorKind::UniformTexelBuffer)
}

const fn storage(binding: u32) -> DescriptorBinding {
    DescriptorBinding::new(0, binding, DescriptorKind::StorageBuffer)
}

/// `ring_growth.comp`: the plan and the input mesh as texel buffers (RGBA32F), three
/// storage buffers (output mesh, per-run sums, the indirect draw command) and the
/// private `ComputePush`. naga cannot read texel buffers: the GPU tests, with the
/// validation layers checking the layout against the module, hold this declaration.
pub static INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SPELEOTHEM_RING_GROWTH_COMP,
    bindings: &[texels(0), texels(1), storage(2), storage(3), storage(4)],
    push_constant_bytes: size_of::<ComputePush>() as u32,
};

const GROUP: u32 = 256;
/// Triangles per invocation (`CHUNK` in the shader).
const CHUNK: u32 = 32;

/// A growth in progress on the compute path.
pub struct ComputeGrowth {
    /// One per stage (`SUMS`, `OFFSETS` specialized: each compiles only its own code).
    pipelines: [Pipeline; 3],
    layout: PipelineLayout,
    /// `sets[i]` reads `meshes[i]` and writes `meshes[1 - i]`.
    sets: [DescriptorSet; 2],
    meshes: [Buffer; 2],
    draw: Buffer,
    /// Read by the shader every pass; rewritten when the plan is steered.
    plan: Buffer,
    _runs: Buffer,
    /// What the sets read the plan and the meshes through.
    _views: [TexelView; 3],
    counts: Vec<u64>,
    /// Vertices each mesh buffer holds.
    capacity: u64,
    initial: u64,
    speleothems: u32,
    segments: u32,
    passes: u32,
    done: u32,
}

impl ComputeGrowth {
    /// Uploads the plan and the base rings into the first of two host-visible mesh
    /// buffers, each sized for the plan's largest predicted mesh, and builds the pipeline
    /// with one descriptor set per ping-pong direction.
    pub fn new(ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Self> {
        let base = initial_rings(plan);
        let counts = vertex_counts(plan);
        let most = counts
            .iter()
            .copied()
            .max()
            .unwrap_or(0)
            .max(base.len() as u64);
        let stride = size_of::<RingVertex>() as u64;
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::VERTEX_BUFFER
            | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let mesh = |name: &str| {
            Buffer::new(
                ctx,
                name,
                BufferDesc::upload((most * stride).max(stride), usage),
            )
        };
        let mut meshes = [
            mesh("compute growth mesh a")?,
            mesh("compute growth mesh b")?,
        ];
        meshes[0].write(0, &base)?;
        let triangles = most / 3;
        let run_count = triangles.div_ceil(u64::from(CHUNK)).max(1);
        let storage_only = vk::BufferUsageFlags::STORAGE_BUFFER;
        let runs = Buffer::new(
            ctx,
            "compute growth run sums",
            BufferDesc::gpu_only(run_count * 4, storage_only),
        )?;
        let draw = Buffer::new(
            ctx,
            "compute growth draw",
            BufferDesc::readback(16, storage_only | vk::BufferUsageFlags::INDIRECT_BUFFER),
        )?;
        let plan_buffer = Buffer::with_data(
            ctx,
            "compute growth plan",
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &plan.gpu_steps(),
        )?;
        let views = [
            TexelView::rgba32f(ctx, "compute growth plan", &plan_buffer)?,
            TexelView::rgba32f(ctx, "compute growth mesh a", &meshes[0])?,
            TexelView::rgba32f(ctx, "compute growth mesh b", &meshes[1])?,
        ];
        let layout = PipelineLayout::new(ctx, "compute growth layout", &[&INTERFACE])?;
        let stage = |name: &str, sums: bool, offsets: bool| {
            Pipeline::compute_specialized(
                ctx,
                name,
                INTERFACE.shader,
                &layout,
                &[(0, u32::from(sums)), (1, u32::from(offsets))],
            )
        };
        let pipelines = [
            stage("compute growth sums", true, false)?,
            stage("compute growth offsets", false, true)?,
            stage("compute growth writes", false, false)?,
        ];
        let make_set = |from: usize| -> Result<DescriptorSet> {
            let set = layout.allocate_set("compute growth set", 0)?;
            set.write_texel_buffer(0, &views[0])?;
            set.write_texel_buffer(1, &views[1 + from])?;
            set.write_buffer(2, &meshes[1 - from])?;
            set.write_buffer(3, &runs)?;
            set.write_buffer(4, &draw)?;
            Ok(set)
        };
        let sets = [make_set(0)?, make_set(1)?];
        Ok(Self {
            pipelines,
            layout,
            sets,
            meshes,
            draw,
            plan: plan_buffer,
            _views: views,
            _runs: runs,
            counts,
            capacity: most,
            initial: base.len() as u64,
            speleothems: plan.speleothems.len() as u32,
            segments: plan.segments,
            passes: plan.passes,
            done: 0,
        })
    }

    /// Vertices of the current mesh (the plan's prediction; the GPU's own count is
    /// [`ComputeGrowth::gpu_vertex_count`]).
    fn current_vertices(&self) -> u64 {
        if self.done == 0 {
            self.initial
        } else {
            self.counts[self.done as usize - 1]
        }
    }

    /// The vertex count the GPU computed for the last pass (its draw command).
    pub fn gpu_vertex_count(&self) -> Result<u32> {
        let words: Vec<u32> = self.draw.read()?;
        Ok(words.first().copied().unwrap_or(0))
    }
}

impl Growth for ComputeGrowth {
    fn path(&self) -> GrowthPath {
        GrowthPath::ComputeRestream
    }

    fn passes_done(&self) -> u32 {
        self.done
    }

    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        let steps = plan.gpu_steps();
        let counts = vertex_counts(plan);
        let fits = plan.speleothems.len() as u32 == self.speleothems
            && plan.passes == self.passes
            && std::mem::size_of_val(steps.as_slice()) as u64 == self.plan.size()
            && counts.iter().all(|&c| c <= self.capacity);
        if !fits {
            return Ok(false);
        }
        self.plan.write(0, &steps)?;
        self.counts = counts;
        Ok(true)
    }

    fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()> {
        let last = (self.done + passes).min(self.passes);
        while self.done < last {
            let from = (self.done % 2) as usize;
            let triangles = (self.current_vertices() / 3) as u32;
            let groups = triangles.div_ceil(CHUNK).div_ceil(GROUP).max(1);
            for (pipeline, dispatch) in self.pipelines.iter().zip([groups, 1, groups]) {
                cmd.bind_pipeline(pipeline, &self.layout, &[&self.sets[from]]);
                cmd.push_constants(
                    &self.layout,
                    &ComputePush {
                        pass_index: self.done,
                        speleothem_count: self.speleothems,
                        segments: self.segments,
                        triangles,
                    },
                )?;
                // Each stage reads what the one before wrote; the last one's output is
                // the next pass's input and the draw's vertex buffer.
                cmd.dispatch_then_sync(dispatch, 1, 1);
            }
            self.done += 1;
        }
        Ok(())
    }

    fn counts(&self) -> Result<GrowthCounts> {
        Ok(GrowthCounts {
            vertices: if self.done == 0 {
                self.initial
            } else {
                u64::from(self.gpu_vertex_count()?)
            },
            emitted: self.counts[..self.done as usize].iter().sum(),
        })
    }

    fn source(&self) -> MeshSource<'_> {
        MeshSource::Counted {
            buffer: &self.meshes[(self.done % 2) as usize],
            vertices: self.current_vertices() as u32,
        }
    }

    fn read_back(&self, _ctx: &Arc<Context>, _plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        let mut all: Vec<RingVertex> = self.meshes[(self.done % 2) as usize].read()?;
        all.truncate(self.current_vertices() as usize);
        Ok(all)
    }
}

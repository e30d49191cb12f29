//! The dune shadow map, computed on the GPU whenever the light changes
//! (`shaders-glsl/dunes/dune_shadow.comp`; CPU twin `model::dune_shadow`).

use std::sync::Arc;

use glam::Vec4;

use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, FloatTexels, Pipeline, PipelineLayout,
    Pod, Usage, vk,
};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of `dune_shadow.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct ShadowPush {
    /// xy: horizontal unit direction toward the sun (x, z); z: rise per unit distance;
    /// w: the margins' range (`model::dune_shadow::MARGIN_RANGE`, radians).
    pub sun: Vec4,
    /// Height-grid vertices per side (the field is periodic with this period).
    pub n: u32,
    /// Shadow-map texels per side.
    pub res: u32,
    /// Padding to a 16-byte multiple; write zeros.
    pub unused: [u32; 2],
}
// SAFETY: repr(C), a Vec4 and four u32, no padding.
unsafe impl Pod for ShadowPush {}

/// `dune_shadow.comp`: heights (binding 0) and sun margins (binding 1) as storage
/// buffers, the heights again as an R32F texel buffer (binding 2), and `ShadowPush`.
pub static INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_DUNE_SHADOW_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 2, DescriptorKind::UniformTexelBuffer),
    ],
    push_constant_bytes: size_of::<ShadowPush>() as u32,
};

/// `dune_shadow.comp`'s `HEIGHTS_AS_TEXELS`: the heights read through binding 2.
const HEIGHTS_AS_TEXELS: u32 = 0;

/// The shadow-map compute pass and its buffers.
pub struct DuneShadowPass {
    set: DescriptorSet,
    // The texel view before the buffer it views.
    _texels: FloatTexels,
    /// `res` x `res` sun margins, radians (`model::dune_shadow::sun_margin`).
    pub margin: Buffer,
    /// The heights it marches over (cell units), also sampled by the per-pixel variant.
    pub heights: Buffer,
    pipeline: Pipeline,
    layout: PipelineLayout,
    /// Grid side (vertices per period) and shadow-map side.
    pub n: u32,
    /// Shadow-map side in texels (`margin` holds `res` x `res` f32).
    pub res: u32,
}

impl DuneShadowPass {
    /// For an `n` x `n` grid of heights (in cell units) and a `res` x `res` map.
    pub fn new(ctx: &Arc<Context>, n: u32, heights: &[f32], res: u32) -> Result<Self> {
        Self::with_reads(ctx, n, heights, res, false)
    }

    /// [`DuneShadowPass::new`], reading the heights as a storage buffer where
    /// `storage_reads` even if the device's texel buffers would hold them (the path of
    /// devices whose `maxTexelBufferElements` is below `n` x `n`; llvmpipe reads a
    /// texel buffer faster).
    pub fn with_reads(
        ctx: &Arc<Context>,
        n: u32,
        heights: &[f32],
        res: u32,
        storage_reads: bool,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(ctx, "dune shadow layout", &[&INTERFACE])?;
        let heights_buffer = Buffer::with_data(
            ctx,
            "dune heights",
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_SRC
                | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            heights,
        )?;
        let texels = FloatTexels::new(ctx, "dune heights", &heights_buffer, storage_reads)?;
        let pipeline = Pipeline::compute_specialized(
            ctx,
            "dune shadow",
            INTERFACE.shader,
            &layout,
            &[(HEIGHTS_AS_TEXELS, u32::from(texels.readable()))],
        )?;
        let margin = Buffer::new(
            ctx,
            "dune shadow map",
            BufferDesc::readback(
                u64::from(res * res) * 4,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            ),
        )?;
        let set = layout.allocate_set("dune shadow set", 0)?;
        set.write_buffer(0, &heights_buffer)?;
        set.write_buffer(1, &margin)?;
        set.write_texel_buffer(2, texels.view())?;
        Ok(Self {
            set,
            _texels: texels,
            margin,
            heights: heights_buffer,
            pipeline,
            layout,
            n,
            res,
        })
    }

    /// Records the map for the sun at horizontal direction `dir` (unit, toward the sun)
    /// rising `rise` per unit distance, with the barriers that make it visible to the
    /// host.
    pub fn record(&self, cmd: &Commands<'_>, dir: [f32; 2], rise: f32) -> Result<()> {
        self.margin.use_as(cmd, Usage::ComputeWrite);
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        cmd.push_constants(
            &self.layout,
            &ShadowPush {
                sun: Vec4::new(
                    dir[0],
                    dir[1],
                    rise,
                    crate::model::dune_shadow::MARGIN_RANGE,
                ),
                n: self.n,
                res: self.res,
                unused: [0; 2],
            },
        )?;
        cmd.dispatch(self.res.div_ceil(8), self.res.div_ceil(8), 1);
        self.margin.use_as(cmd, Usage::HostRead);
        Ok(())
    }
}

//! The ripple tile's normal-map chain and horizon map, built on the GPU in compute
//! passes (`shaders-glsl/dunes/normal_mip.comp`, `horizon.comp`) from a ripple
//! heightfield; their CPU twins are in `model::ripple_maps`, compared in
//! `tests/ripple_maps.rs`.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::gpu::{Buffer, BufferDesc, Context, GpuTimer, Pipeline, PipelineLayout, Pod, Span, vk};
use crate::model::ripple_maps::normal_level0;
use crate::model::sand::Heightfield;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of `normal_mip.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct MipPush {
    /// Texel offset in the chain buffer of the level read (twice `dst_size` a side).
    pub src_offset: u32,
    /// Texel offset in the chain buffer of the level written.
    pub dst_offset: u32,
    /// Side in texels of the level written.
    pub dst_size: u32,
    /// Padding to 16 bytes; write zero.
    pub unused: u32,
}
// SAFETY: repr(C), four u32.
unsafe impl Pod for MipPush {}

/// Push constants of `horizon.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct HorizonPush {
    /// Side of the periodic ripple tile in texels.
    pub size: u32,
    /// Texels marched along each of the 8 directions.
    pub steps: u32,
    /// Factor on the stored heights before slopes are taken.
    pub height_scale: f32,
    /// Padding to 16 bytes; write zero.
    pub unused: u32,
}
// SAFETY: repr(C), four 4-byte fields.
unsafe impl Pod for HorizonPush {}

/// `normal_mip.comp`: the whole chain as one storage buffer (binding 0) and `MipPush`.
pub static NORMAL_MIP_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_NORMAL_MIP_COMP,
    bindings: &[DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer)],
    push_constant_bytes: size_of::<MipPush>() as u32,
};

/// `horizon.comp`: heights (binding 0) and the two-plane horizon map (binding 1) as
/// storage buffers, and `HorizonPush`.
pub static HORIZON_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_HORIZON_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer),
    ],
    push_constant_bytes: size_of::<HorizonPush>() as u32,
};

/// `horizon_linear.comp`: heights (binding 0), the two-plane horizon map (binding 1)
/// and the hull stacks (binding 2, 2 x size vec2 per line and direction) as storage
/// buffers, and `HorizonPush` (`steps` unused: the whole row).
pub static HORIZON_LINEAR_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_HORIZON_LINEAR_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 2, DescriptorKind::StorageBuffer),
    ],
    push_constant_bytes: size_of::<HorizonPush>() as u32,
};

/// How the horizon map is computed: both give the map of the whole periodic row
/// (`Brute { steps: size - 1 }` and `Linear` agree within rounding, `tests/ripple_maps.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HorizonWalk {
    /// `horizon.comp`: every texel walks `steps` texels along each direction (the
    /// paper's; O(texels x steps)). Kept as the reference.
    Brute {
        /// Texels walked per direction (the paper: size - 1).
        steps: u32,
    },
    /// `horizon_linear.comp`: every line swept once keeping the convex hull of the
    /// heights ahead (Timonen & Westerholm 2010; O(texels)), over the whole row.
    Linear,
}

/// The maps on the GPU, as storage buffers (host-visible so tests and exports can
/// read them).
pub struct RippleMaps {
    /// Every level of the normal chain, packed from level 0 (vec4 per texel).
    pub levels: Buffer,
    /// Horizon slopes of level 0: a plane of vec4 (directions 0–3), then another (4–7).
    pub horizon: Buffer,
    /// Side of level 0 in texels (a power of two, at least 2).
    pub size: u32,
    /// Texel offset of each level in `levels`.
    pub level_offsets: Vec<u32>,
    /// GPU time of the two builds.
    pub spans: Vec<Span>,
}

/// Offsets of each level of a `size` chain down to 1x1.
pub fn level_offsets(size: u32) -> Vec<u32> {
    let mut offsets = Vec::new();
    let (mut s, mut offset) = (size, 0);
    while s >= 1 {
        offsets.push(offset);
        offset += s * s;
        if s == 1 {
            break;
        }
        s /= 2;
    }
    offsets
}

impl RippleMaps {
    /// Builds both maps for a square, power-of-two ripple tile: the normals of the
    /// heights times `height_scale`, the horizons of the heights times
    /// `horizon_height_scale` — the heights the shading shows (the bump strength
    /// included), so that ripples cast the shadows of the ripples drawn.
    pub fn build(
        ctx: &Arc<Context>,
        field: &Heightfield,
        height_scale: f32,
        horizon_height_scale: f32,
        walk: HorizonWalk,
    ) -> Result<Self> {
        let size = field.width as u32;
        if field.width != field.height || !size.is_power_of_two() || size < 2 {
            return Err(Error::internal(
                "ripple tile",
                format!(
                    "{}x{} must be square with a power-of-two side >= 2",
                    field.width, field.height
                ),
            ));
        }
        let offsets = level_offsets(size);
        let total: u32 = offsets.last().copied().unwrap_or(0) + 1;
        let mut levels = Buffer::new(
            ctx,
            "ripple normal chain",
            BufferDesc::upload(
                u64::from(total) * 16,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            ),
        )?;
        levels.write(0, &normal_level0(field, height_scale))?;
        let heights: Vec<f32> = field.data.iter().map(|&h| h as f32).collect();
        let height_buffer = Buffer::with_data(
            ctx,
            "ripple heights",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &heights,
        )?;
        let horizon = Buffer::new(
            ctx,
            "ripple horizon map",
            BufferDesc::readback(
                u64::from(size * size) * 32,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            ),
        )?;

        let mip_layout = PipelineLayout::new(ctx, "normal mip layout", &[&NORMAL_MIP_INTERFACE])?;
        let mip = Pipeline::compute(ctx, "normal mip", NORMAL_MIP_INTERFACE.shader, &mip_layout)?;
        let mip_set = mip_layout.allocate_set("normal mip set", 0)?;
        mip_set.write_buffer(0, &levels)?;
        let (interface, steps) = match walk {
            HorizonWalk::Brute { steps } => (&HORIZON_INTERFACE, steps),
            HorizonWalk::Linear => (&HORIZON_LINEAR_INTERFACE, size - 1),
        };
        let hz_layout = PipelineLayout::new(ctx, "horizon layout", &[interface])?;
        let hz = Pipeline::compute(ctx, "horizon", interface.shader, &hz_layout)?;
        let hz_set = hz_layout.allocate_set("horizon set", 0)?;
        hz_set.write_buffer(0, &height_buffer)?;
        hz_set.write_buffer(1, &horizon)?;
        // The linear sweep's stacks: 2 x size (position, height) for each of 8 x size
        // lines.
        let hull = match walk {
            HorizonWalk::Linear => {
                let hull = Buffer::new(
                    ctx,
                    "horizon hull stacks",
                    BufferDesc::gpu_only(
                        u64::from(size) * 8 * u64::from(size) * 2 * 8,
                        vk::BufferUsageFlags::STORAGE_BUFFER,
                    ),
                )?;
                hz_set.write_buffer(2, &hull)?;
                Some(hull)
            }
            HorizonWalk::Brute { .. } => None,
        };

        let mut timer = GpuTimer::new(ctx, "ripple maps timer", 2)?;
        ctx.submit_and_wait("ripple maps", |cmd| {
            timer.reset(cmd);
            let span = timer.begin(cmd, "normal chain")?;
            cmd.bind_pipeline(&mip, &mip_layout, &[&mip_set]);
            let mut s = size;
            for pair in offsets.windows(2) {
                s /= 2;
                cmd.push_constants(
                    &mip_layout,
                    &MipPush {
                        src_offset: pair[0],
                        dst_offset: pair[1],
                        dst_size: s,
                        unused: 0,
                    },
                )?;
                cmd.dispatch(s.div_ceil(8), s.div_ceil(8), 1);
                // The next level reads what this one wrote.
                cmd.full_barrier();
            }
            timer.end(cmd, span);
            let span = timer.begin(cmd, "horizon map")?;
            cmd.bind_pipeline(&hz, &hz_layout, &[&hz_set]);
            cmd.push_constants(
                &hz_layout,
                &HorizonPush {
                    size,
                    steps,
                    height_scale: horizon_height_scale,
                    unused: 0,
                },
            )?;
            match walk {
                HorizonWalk::Brute { .. } => cmd.dispatch(size.div_ceil(8), size.div_ceil(8), 1),
                // One invocation per line and direction.
                HorizonWalk::Linear => cmd.dispatch((8 * size).div_ceil(64), 1, 1),
            }
            timer.end(cmd, span);
            cmd.shader_to_host_barrier();
            Ok(())
        })?;
        drop(hull);
        Ok(Self {
            spans: timer.read()?,
            levels,
            horizon,
            size,
            level_offsets: offsets,
        })
    }

    /// Level `k` of the chain as read back.
    pub fn level(&self, k: usize) -> Result<Vec<[f32; 4]>> {
        let all: Vec<[f32; 4]> = self.levels.read()?;
        let start =
            self.level_offsets.get(k).copied().ok_or_else(|| {
                Error::internal("normal chain level", format!("{k} beyond the chain"))
            })? as usize;
        let side = (self.size >> k).max(1) as usize;
        Ok(all[start..start + side * side].to_vec())
    }

    /// The horizon map as read back (two planes).
    pub fn horizon_slopes(&self) -> Result<Vec<[f32; 4]>> {
        self.horizon.read()
    }
}

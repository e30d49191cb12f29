//! The ripple tile's normal-map chain and horizon map, built on the GPU in compute
//! passes (`shaders-glsl/dunes/normal_mip.comp`; the horizons by the paper's walk,
//! `horizon.comp`, or the linear-time sweep, `horizon_linear.comp`) from a ripple
//! heightfield; their CPU twins are in `model::ripple_maps`, compared in
//! `tests/gpu/ripple_maps.rs`.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, FloatTexels, GpuTimer, Pipeline,
    PipelineLayout, Pod, Span, Usage, Use, vk,
};
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
/// storage buffers, the heights again as an R32F texel buffer (binding 2), and
/// `HorizonPush`.
pub static HORIZON_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_HORIZON_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 2, DescriptorKind::UniformTexelBuffer),
    ],
    push_constant_bytes: size_of::<HorizonPush>() as u32,
};

/// Push constants of `horizon_linear.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct SweepPush {
    /// Side of the periodic tile in texels.
    pub size: u32,
    /// 8 (axes and diagonals) or 16 (and the knight's moves between them).
    pub directions: u32,
    /// Factor on the stored heights before slopes are taken.
    pub height_scale: f32,
    /// The dispatch's first pair of opposite directions (pair d: directions d and
    /// d + directions / 2, each invocation one line of both).
    pub first_pair: u32,
}
// SAFETY: repr(C), four 4-byte fields.
unsafe impl Pod for SweepPush {}

/// `horizon_linear.comp`: the heights and their transpose (binding 0), the horizon
/// map's planes (binding 1) and the hull stacks (binding 2) as storage buffers, the
/// heights again as an R32F texel buffer (binding 3), and `SweepPush`.
pub static HORIZON_LINEAR_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_HORIZON_LINEAR_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 2, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 3, DescriptorKind::UniformTexelBuffer),
    ],
    push_constant_bytes: size_of::<SweepPush>() as u32,
};

/// `horizon.comp`'s and `horizon_linear.comp`'s `HEIGHTS_AS_TEXELS`: the heights read
/// through a texel buffer (binding 2 and 3).
const HEIGHTS_AS_TEXELS: u32 = 0;

/// How a [`HorizonSweep`] runs; the default is what the scenes use.
#[derive(Clone, Copy, Debug)]
pub struct SweepOptions {
    /// At most this many pairs of opposite directions a dispatch (fewer: less memory
    /// for the hull stacks, which the dispatches reuse); the memory budget may make it
    /// fewer.
    pub group: u32,
    /// Read the heights as a storage buffer even where the device's texel buffers
    /// would hold them (llvmpipe reads a texel buffer faster): the path of devices whose
    /// `maxTexelBufferElements` is below twice the tile's texels.
    pub storage_reads: bool,
}

impl Default for SweepOptions {
    fn default() -> Self {
        Self {
            group: 8,
            storage_reads: false,
        }
    }
}

/// The side of a square, power-of-two tile of at least 2 texels, or an error naming
/// `what`.
fn tile_side(field: &Heightfield, what: &str) -> Result<u32> {
    let size = field.width as u32;
    if field.width != field.height || !size.is_power_of_two() || size < 2 {
        return Err(Error::internal(
            what,
            format!(
                "{}x{} must be square with a power-of-two side >= 2",
                field.width, field.height
            ),
        ));
    }
    Ok(size)
}

/// The hull stacks of one dispatch are kept under this many bytes; pairs of directions
/// beyond it are swept in further dispatches that reuse them.
const HULL_BUDGET_BYTES: u64 = 64 << 20;

/// The linear-time horizon sweep (`horizon_linear.comp`) of one tile, ready to record:
/// its pipeline, the heights with their transpose, and the hull stacks.
pub struct HorizonSweep {
    layout: PipelineLayout,
    pipeline: Pipeline,
    set: DescriptorSet,
    // The texel view before the buffer it views.
    _texels: FloatTexels,
    _heights: Buffer,
    hull: Buffer,
    size: u32,
    directions: u32,
    /// Pairs of opposite directions a dispatch.
    per_dispatch: u32,
}

impl HorizonSweep {
    /// Prepares the sweep of a square, power-of-two `field` (at least 4x4) along 8 or
    /// 16 directions, writing each line's horizons in order into `horizon`
    /// (`directions` x the field's texels floats; [`planes_from_lines`] reads them as
    /// planes).
    pub fn new(
        ctx: &Arc<Context>,
        field: &Heightfield,
        directions: u32,
        horizon: &Buffer,
    ) -> Result<Self> {
        Self::with_options(ctx, field, directions, horizon, SweepOptions::default())
    }

    /// [`HorizonSweep::new`] run as `options` say.
    pub fn with_options(
        ctx: &Arc<Context>,
        field: &Heightfield,
        directions: u32,
        horizon: &Buffer,
        options: SweepOptions,
    ) -> Result<Self> {
        let size = tile_side(field, "horizon sweep")?;
        // The sweep writes four positions of a line as one vec4.
        if size < 4 {
            return Err(Error::internal(
                "horizon sweep",
                format!("a {size}x{size} tile: the sweep needs at least 4x4"),
            ));
        }
        if directions != 8 && directions != 16 {
            return Err(Error::internal(
                "horizon sweep",
                format!("{directions} directions: 8 or 16"),
            ));
        }
        let planes_bytes = u64::from(size * size) * u64::from(directions) * 4;
        if horizon.size() < planes_bytes {
            return Err(Error::internal(
                "horizon sweep",
                format!(
                    "the map needs {planes_bytes} bytes, the buffer has {}",
                    horizon.size()
                ),
            ));
        }
        // Row-major heights, then transposed: lines along x read the transpose so
        // that every line steps one row a texel.
        let n = size as usize;
        let mut heights: Vec<f32> = field.data.iter().map(|&h| h as f32).collect();
        heights.extend((0..n * n).map(|i| field.data[(i % n) * n + i / n] as f32));
        let heights = Buffer::with_data(
            ctx,
            "horizon sweep heights",
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &heights,
        )?;
        let texels = FloatTexels::new(
            ctx,
            "horizon sweep heights",
            &heights,
            options.storage_reads,
        )?;
        // An invocation sweeps one line along a pair of opposite directions, one after
        // the other on the same stack of at most a lap.
        let entries = u64::from(size);
        let per_pair = entries * u64::from(size) * 8;
        let per_dispatch = (HULL_BUDGET_BYTES / per_pair)
            .clamp(1, u64::from((directions / 2).min(options.group).max(1)))
            as u32;
        let lanes = u64::from((per_dispatch * size).div_ceil(64) * 64);
        let hull = Buffer::new(
            ctx,
            "horizon hull stacks",
            BufferDesc::gpu_only(entries * lanes * 8, vk::BufferUsageFlags::STORAGE_BUFFER),
        )?;
        let layout =
            PipelineLayout::new(ctx, "horizon sweep layout", &[&HORIZON_LINEAR_INTERFACE])?;
        let pipeline = Pipeline::compute_specialized(
            ctx,
            "horizon sweep",
            HORIZON_LINEAR_INTERFACE.shader,
            &layout,
            &[(HEIGHTS_AS_TEXELS, u32::from(texels.readable()))],
        )?;
        let set = layout.allocate_set("horizon sweep set", 0)?;
        set.write_buffer(0, &heights)?;
        set.write_buffer(1, horizon)?;
        set.write_buffer(2, &hull)?;
        set.write_texel_buffer(3, texels.view())?;
        Ok(Self {
            layout,
            pipeline,
            set,
            _texels: texels,
            _heights: heights,
            hull,
            size,
            directions,
            per_dispatch,
        })
    }

    /// Records the sweep: one dispatch per group of direction pairs whose stacks fit
    /// the budget, each after the one before has done with the stacks it reuses. The
    /// caller declares the map's use (`Usage::ComputeWrite`).
    pub fn record(&self, cmd: &Commands, height_scale: f32) -> Result<()> {
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        let mut first = 0;
        while first < self.directions / 2 {
            self.hull.use_as(cmd, Usage::ComputeReadWrite);
            cmd.push_constants(
                &self.layout,
                &SweepPush {
                    size: self.size,
                    directions: self.directions,
                    height_scale,
                    first_pair: first,
                },
            )?;
            cmd.dispatch((self.per_dispatch * self.size).div_ceil(64), 1, 1);
            first += self.per_dispatch;
        }
        Ok(())
    }
}

/// The horizon map of `field` along 8 or 16 directions by the linear sweep on the GPU
/// (`directions / 4` planes of vec4, as [`horizon_map_linear_along`] lays them out),
/// with the sweep's GPU time in milliseconds, run as `options` say.
///
/// [`horizon_map_linear_along`]: crate::model::ripple_maps::horizon_map_linear_along
pub fn horizon_map_linear_gpu(
    ctx: &Arc<Context>,
    field: &Heightfield,
    height_scale: f32,
    directions: u32,
    options: SweepOptions,
) -> Result<(Vec<[f32; 4]>, f64)> {
    let (lines, ms) = run_alone::<f32, _>(
        ctx,
        field.data.len() * directions as usize,
        |horizon| HorizonSweep::with_options(ctx, field, directions, horizon, options),
        |sweep, cmd| sweep.record(cmd, height_scale),
    )?;
    Ok((
        planes_from_lines(&lines, field.width, directions as usize),
        ms,
    ))
}

/// The horizon map of `field` along the 8 directions by the paper's walk on the GPU
/// (`steps` texels each way; two planes of vec4, as [`horizon_map`] lays them out),
/// with the walk's GPU time in milliseconds; the heights read as a storage buffer
/// where `storage_reads`, else as texels where the device's texel buffers hold them.
///
/// [`horizon_map`]: crate::model::ripple_maps::horizon_map
pub fn horizon_map_brute_gpu(
    ctx: &Arc<Context>,
    field: &Heightfield,
    height_scale: f32,
    steps: u32,
    storage_reads: bool,
) -> Result<(Vec<[f32; 4]>, f64)> {
    run_alone(
        ctx,
        field.data.len() * 8,
        |horizon| BruteWalk::new(ctx, field, steps, horizon, storage_reads),
        |walk, cmd| walk.record(cmd, height_scale),
    )
}

/// One horizon pass alone: `prepare` builds it over a fresh host-readable map of
/// `floats` floats, `record` records it between two timestamps; the map as `T`s and the
/// pass's GPU milliseconds.
fn run_alone<T: Pod, P>(
    ctx: &Arc<Context>,
    floats: usize,
    prepare: impl FnOnce(&Buffer) -> Result<P>,
    record: impl Fn(&P, &Commands) -> Result<()>,
) -> Result<(Vec<T>, f64)> {
    let horizon = Buffer::new(
        ctx,
        "horizon map",
        BufferDesc::readback((floats * 4) as u64, vk::BufferUsageFlags::STORAGE_BUFFER),
    )?;
    let pass = prepare(&horizon)?;
    let mut timer = GpuTimer::new(ctx, "horizon map timer", 1)?;
    ctx.submit_and_wait("horizon map", |cmd| {
        timer.reset(cmd);
        horizon.use_as(cmd, Usage::ComputeWrite);
        timer.span(cmd, "horizon map", |cmd| record(&pass, cmd))?;
        horizon.use_as(cmd, Usage::HostRead);
        Ok(())
    })?;
    let ms = timer.read()?.first().map_or(0.0, |s| s.milliseconds);
    Ok((horizon.read()?, ms))
}

/// The texel that position `pos` of line `line` along `dir` is, in an `n` x `n`
/// tile: `horizon_linear.comp`'s frame (transposed where the direction is steeper in
/// y; along a row, line k is row k; across rows, the line through (k, 0)).
fn sweep_texel(n: usize, dir: (i32, i32), line: usize, pos: usize) -> usize {
    let transposed = dir.1.abs() > dir.0.abs();
    let (su, sv) = if transposed {
        (dir.1, dir.0)
    } else {
        (dir.0, dir.1)
    };
    let (u0, v0) = if sv == 0 { (0, line) } else { (line, 0) };
    let at = |start: usize, step: i32| {
        (start as i64 + pos as i64 * i64::from(step)).rem_euclid(n as i64) as usize
    };
    let (u, v) = (at(u0, su), at(v0, sv));
    if transposed { u * n + v } else { v * n + u }
}

/// The sweep's output (for each direction, each line's horizons position by position,
/// as each invocation writes them in order) as planes of vec4 per texel (directions
/// 0-3, then 4-7, ...: [`horizon_map_linear_along`]'s layout).
///
/// [`horizon_map_linear_along`]: crate::model::ripple_maps::horizon_map_linear_along
pub fn planes_from_lines(lines: &[f32], n: usize, directions: usize) -> Vec<[f32; 4]> {
    let table = &crate::model::ripple_maps::HORIZON_DIRECTIONS_16;
    let mut planes = vec![[0.0f32; 4]; n * n * directions.div_ceil(4)];
    for d in 0..directions {
        let dir = table[if directions == 8 { 2 * d } else { d }];
        for line in 0..n {
            for pos in 0..n {
                let texel = sweep_texel(n, dir, line, pos);
                planes[d / 4 * n * n + texel][d % 4] = lines[(d * n + line) * n + pos];
            }
        }
    }
    planes
}

/// The paper's walk (`horizon.comp`) of one tile, ready to record.
struct BruteWalk {
    layout: PipelineLayout,
    pipeline: Pipeline,
    set: DescriptorSet,
    // The texel view before the buffer it views.
    _texels: FloatTexels,
    _heights: Buffer,
    size: u32,
    steps: u32,
}

impl BruteWalk {
    /// Prepares the walk of `steps` texels along 8 directions over `field`, writing
    /// two planes of vec4 into `horizon`.
    fn new(
        ctx: &Arc<Context>,
        field: &Heightfield,
        steps: u32,
        horizon: &Buffer,
        storage_reads: bool,
    ) -> Result<Self> {
        let heights: Vec<f32> = field.data.iter().map(|&h| h as f32).collect();
        let heights = Buffer::with_data(
            ctx,
            "ripple heights",
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &heights,
        )?;
        let texels = FloatTexels::new(ctx, "ripple heights", &heights, storage_reads)?;
        let layout = PipelineLayout::new(ctx, "horizon layout", &[&HORIZON_INTERFACE])?;
        let pipeline = Pipeline::compute_specialized(
            ctx,
            "horizon",
            HORIZON_INTERFACE.shader,
            &layout,
            &[(HEIGHTS_AS_TEXELS, u32::from(texels.readable()))],
        )?;
        let set = layout.allocate_set("horizon set", 0)?;
        set.write_buffer(0, &heights)?;
        set.write_buffer(1, horizon)?;
        set.write_texel_buffer(2, texels.view())?;
        Ok(Self {
            layout,
            pipeline,
            set,
            _texels: texels,
            _heights: heights,
            size: tile_side(field, "ripple tile")?,
            steps,
        })
    }

    fn record(&self, cmd: &Commands, height_scale: f32) -> Result<()> {
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        cmd.push_constants(
            &self.layout,
            &HorizonPush {
                size: self.size,
                steps: self.steps,
                height_scale,
                unused: 0,
            },
        )?;
        cmd.dispatch(self.size.div_ceil(8), self.size.div_ceil(8), 1);
        Ok(())
    }
}

/// Whichever horizon pass `RippleMaps::build` was asked for (only its pipeline is
/// built).
enum HorizonPass {
    Walk(BruteWalk),
    Sweep(HorizonSweep),
}

/// How the horizon map is computed: both give the map of the whole periodic row
/// (`Brute { steps: size - 1 }` and `Linear` agree within rounding, `tests/gpu/ripple_maps.rs`).
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
    /// Horizon slopes of level 0: by the brute walk a plane of vec4 (directions 0–3),
    /// then another (4–7); by the linear sweep each line's in order
    /// ([`planes_from_lines`]). [`RippleMaps::horizon_slopes`] reads either as planes.
    pub horizon: Buffer,
    /// Side of level 0 in texels (a power of two, at least 2).
    pub size: u32,
    /// Texel offset of each level in `levels`.
    pub level_offsets: Vec<u32>,
    /// GPU time of the two builds.
    pub spans: Vec<Span>,
    /// How `horizon` is laid out: by line (the linear sweep) or by texel.
    walk: HorizonWalk,
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
        let size = tile_side(field, "ripple tile")?;
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
        let pass = match walk {
            HorizonWalk::Linear => HorizonPass::Sweep(HorizonSweep::new(ctx, field, 8, &horizon)?),
            HorizonWalk::Brute { steps } => {
                HorizonPass::Walk(BruteWalk::new(ctx, field, steps, &horizon, false)?)
            }
        };

        let mut timer = GpuTimer::new(ctx, "ripple maps timer", 2)?;
        ctx.submit_and_wait("ripple maps", |cmd| {
            timer.reset(cmd);
            timer.span(cmd, "normal chain", |cmd| {
                cmd.bind_pipeline(&mip, &mip_layout, &[&mip_set]);
                let mut s = size;
                for pair in offsets.windows(2) {
                    // The next level reads what the one before wrote.
                    levels.use_as(cmd, Usage::ComputeReadWrite);
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
                }
                Ok(())
            })?;
            horizon.use_as(cmd, Usage::ComputeWrite);
            timer.span(cmd, "horizon map", |cmd| match &pass {
                HorizonPass::Sweep(sweep) => sweep.record(cmd, horizon_height_scale),
                HorizonPass::Walk(brute) => brute.record(cmd, horizon_height_scale),
            })?;
            cmd.uses(&[
                Use::buffer(&levels, Usage::HostRead),
                Use::buffer(&horizon, Usage::HostRead),
            ]);
            Ok(())
        })?;
        drop(pass);
        Ok(Self {
            spans: timer.read()?,
            levels,
            horizon,
            size,
            level_offsets: offsets,
            walk,
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

    /// The horizon map as read back (two planes of vec4 per texel).
    pub fn horizon_slopes(&self) -> Result<Vec<[f32; 4]>> {
        match self.walk {
            HorizonWalk::Linear => Ok(planes_from_lines(
                &self.horizon.read::<f32>()?,
                self.size as usize,
                8,
            )),
            HorizonWalk::Brute { .. } => self.horizon.read(),
        }
    }
}

//! The desert's atmosphere on the GPU: the sky-view table integrated by
//! `shaders-glsl/dunes/sky_view.comp` whenever the sun moves (CPU reference
//! `model::atmosphere`), and the full-screen sky that looks it up
//! (`shaders-glsl/dunes/atmosphere_sky.frag`).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::tone_map::ToneMap;
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, DescriptorSet, GraphicsPipelineDesc, Image, ImageDesc,
    Pipeline, PipelineLayout, Pod, Sampler, TargetFormat, TexelView, Usage, Use, vk,
};
use crate::model::atmosphere::{Atmosphere, MS_SIZE, MultipleScattering};
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// The table's size: azimuths from the sun's (0..pi, the sky is symmetric about the
/// sun's vertical plane) by elevations (-pi/2..pi/2).
pub const SKY_VIEW_WIDTH: u32 = 64;
/// Rows of the sky-view table, one per elevation from the nadir (-pi/2) up to the zenith.
pub const SKY_VIEW_HEIGHT: u32 = 64;

/// `Air` of `atmosphere.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirPush {
    /// rgb Rayleigh scattering per metre at the ground, w its scale height (m).
    pub rayleigh: Vec4,
    /// x Mie scattering and y extinction per metre at the ground, z scale height (m),
    /// w the phase asymmetry g.
    pub mie: Vec4,
    /// rgb ground albedo, w the ground's radius (m).
    pub ground: Vec4,
    /// rgb solar irradiance above the air, w the radius of the top of the air (m).
    pub sun: Vec4,
    /// rgb ozone's absorption per metre at its layer's peak, w unused.
    pub ozone: Vec4,
}
// SAFETY: repr(C), five Vec4.
unsafe impl Pod for AirPush {}

impl From<&Atmosphere> for AirPush {
    fn from(a: &Atmosphere) -> Self {
        Self {
            rayleigh: a.rayleigh.extend(a.rayleigh_height_m),
            mie: Vec4::new(a.mie_scattering, a.mie_extinction, a.mie_height_m, a.mie_g),
            ground: a.ground_albedo.extend(a.ground_radius_m),
            sun: a.sun_irradiance.extend(a.top_radius_m),
            ozone: a.ozone.extend(0.0),
        }
    }
}

/// Push constants of `sky_view.comp`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
struct SkyViewPush {
    air: AirPush,
    /// x viewer radius (m), y sin and z cos of the sun's elevation.
    view: Vec4,
    /// rgb the sky's irradiance on the ground, in units of the sun's.
    ambient: Vec4,
    /// Width, height, multiple scattering on (1), unused.
    size: [u32; 4],
}
// SAFETY: repr(C), seven Vec4 and four u32, no padding.
unsafe impl Pod for SkyViewPush {}

/// `sky_view.comp`: the table buffer (0), the Psi_ms table as an RGBA32F texel buffer
/// (1), the half-float storage image (2) and `SkyViewPush`. Declared by hand: naga
/// reads no texel buffers.
pub static SKY_VIEW_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_SKY_VIEW_COMP,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::StorageBuffer),
        DescriptorBinding::new(0, 1, DescriptorKind::UniformTexelBuffer),
        DescriptorBinding::new(0, 2, DescriptorKind::StorageImage),
    ],
    push_constant_bytes: size_of::<SkyViewPush>() as u32,
};

/// The sky-view compute pass and its table, written twice: RGBA f32 texels in a
/// host-readable buffer (rows from the nadir up; the frame integrates the ambient
/// light from it, the tests compare it with the CPU's) and a half-float image, kept in
/// the GENERAL layout while the pass writes it and read-only while the sky samples it
/// with bilinear filtering.
pub struct SkyViewPass {
    set: DescriptorSet,
    /// Host-readable storage buffer of `SKY_VIEW_WIDTH` x `SKY_VIEW_HEIGHT` RGBA f32
    /// texels (16 bytes each), rows from the nadir up.
    pub table: Buffer,
    /// The same table as an RGBA16F storage + sampled image (sampled after `record`).
    pub image: Image,
    /// Hillaire's Psi_ms table (zeros when multiple scattering is off), its view first
    /// (dropped before the buffer).
    _multiple_view: TexelView,
    _multiple: Buffer,
    multiple_on: bool,
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl SkyViewPass {
    /// With `multiple`, the table adds Hillaire's multiple scattering from it.
    pub fn new(ctx: &Arc<Context>, multiple: Option<&MultipleScattering>) -> Result<Self> {
        let layout = PipelineLayout::new(ctx, "sky view layout", &[&SKY_VIEW_INTERFACE])?;
        let pipeline = Pipeline::compute(ctx, "sky view", SKY_VIEW_INTERFACE.shader, &layout)?;
        let table = Buffer::new(
            ctx,
            "sky view table",
            BufferDesc::readback(
                u64::from(SKY_VIEW_WIDTH * SKY_VIEW_HEIGHT) * 16,
                vk::BufferUsageFlags::STORAGE_BUFFER,
            ),
        )?;
        let psi: Vec<Vec4> = match multiple {
            Some(m) => m.table.iter().map(|c| c.extend(0.0)).collect(),
            None => vec![Vec4::ZERO; (MS_SIZE * MS_SIZE) as usize],
        };
        let multiple_buffer = Buffer::with_data(
            ctx,
            "multiple scattering table",
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &psi,
        )?;
        let multiple_view = TexelView::rgba32f(ctx, "multiple scattering table", &multiple_buffer)?;
        let image = Image::new(
            ctx,
            "sky view image",
            ImageDesc::new_2d(
                SKY_VIEW_WIDTH,
                SKY_VIEW_HEIGHT,
                vk::Format::R16G16B16A16_SFLOAT,
                vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED,
            ),
        )?;
        let set = layout.allocate_set("sky view set", 0)?;
        set.write_buffer(0, &table)?;
        set.write_texel_buffer(1, &multiple_view)?;
        set.write_image(2, image.view(), vk::ImageLayout::GENERAL)?;
        Ok(Self {
            set,
            table,
            image,
            _multiple_view: multiple_view,
            _multiple: multiple_buffer,
            multiple_on: multiple.is_some(),
            pipeline,
            layout,
        })
    }

    /// Records the table for `air` seen from altitude `h` (m) with the sun at
    /// `elevation` radians, the ground below the horizon lit by the sun and
    /// `ground_sky` (the sky's irradiance there, in units of the sun's), with the
    /// barriers that make it visible to the sky's fragment shader and the host.
    pub fn record(
        &self,
        cmd: &Commands<'_>,
        air: &Atmosphere,
        h: f32,
        elevation: f32,
        ground_sky: Vec3,
    ) -> Result<()> {
        // Rewritten whole: what it held (read by earlier frames' skies) is discarded.
        cmd.uses(&[
            Use::image_discarding(&self.image, Usage::ComputeWrite),
            Use::buffer(&self.table, Usage::ComputeWrite),
        ]);
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        cmd.push_constants(
            &self.layout,
            &SkyViewPush {
                air: AirPush::from(air),
                view: Vec4::new(
                    air.ground_radius_m + h.max(0.1),
                    elevation.sin(),
                    elevation.cos(),
                    0.0,
                ),
                ambient: ground_sky.extend(0.0),
                size: [
                    SKY_VIEW_WIDTH,
                    SKY_VIEW_HEIGHT,
                    u32::from(self.multiple_on),
                    0,
                ],
            },
        )?;
        cmd.dispatch(SKY_VIEW_WIDTH.div_ceil(8), SKY_VIEW_HEIGHT.div_ceil(8), 1);
        cmd.uses(&[
            Use::image(&self.image, Usage::SampledFragment),
            Use::buffer(&self.table, Usage::HostRead),
        ]);
        Ok(())
    }

    /// The table as last computed (call after the submission has finished).
    pub fn read(&self) -> Result<Vec<Vec3>> {
        let texels: Vec<Vec4> = self.table.read()?;
        Ok(texels.into_iter().map(|t| t.truncate()).collect())
    }
}

/// Push constants of `atmosphere_sky.frag`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct AtmosphereSkyPush {
    /// Clip space to world, to turn each pixel into a view ray.
    pub inverse_view_proj: Mat4,
    /// xyz unit direction toward the sun, w the sun's azimuth (radians from +x to +z).
    pub sun: Vec4,
    /// xyz eye, w exposure.
    pub camera: Vec4,
    /// rgb the sun disk's radiance, w the cosine of its angular radius.
    pub disk: Vec4,
}
// SAFETY: repr(C), Mat4 + three Vec4.
unsafe impl Pod for AtmosphereSkyPush {}

/// `atmosphere_sky.frag`: the sky-view image (0), its sampler (1) and
/// `AtmosphereSkyPush`.
pub static SKY_FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_ATMOSPHERE_SKY_FRAG,
    bindings: &[
        DescriptorBinding::new(0, 0, DescriptorKind::SampledImage),
        DescriptorBinding::new(0, 1, DescriptorKind::Sampler),
    ],
    push_constant_bytes: size_of::<AtmosphereSkyPush>() as u32,
};

/// The full-screen sky from the sky-view table.
pub struct AtmosphereSkyPass {
    set: DescriptorSet,
    _sampler: Sampler,
    pipeline: Pipeline,
    layout: PipelineLayout,
}

impl AtmosphereSkyPass {
    /// Builds the full-screen-triangle pipeline for `target` (no culling, depth tested
    /// but not written, tone-mapping with `tone`) and binds `table`'s image with a
    /// linear clamping sampler; the caller keeps `table` alive as long as this pass.
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        table: &SkyViewPass,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "atmosphere sky layout",
            &[&super::sky::VERTEX_INTERFACE, &SKY_FRAGMENT_INTERFACE],
        )?;
        let mut desc =
            GraphicsPipelineDesc::new("atmosphere sky", super::sky::VERTEX_INTERFACE.shader)
                .fragment(SKY_FRAGMENT_INTERFACE.shader)
                .target(target)
                .specialize(&tone.constants());
        desc.cull_mode = vk::CullModeFlags::NONE;
        // Drawn after the terrain at the far plane: the depth test keeps it to the
        // pixels no surface covered.
        desc.depth_test = true;
        desc.depth_write = false;
        let sampler = Sampler::linear_clamp(ctx, "sky view sampler")?;
        let set = layout.allocate_set("atmosphere sky set", 0)?;
        set.write_image(
            0,
            table.image.view(),
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        set.write_sampler(1, &sampler)?;
        Ok(Self {
            set,
            _sampler: sampler,
            pipeline: desc.build(ctx, &layout)?,
            layout,
        })
    }

    /// Draws the sky inside an open rendering scope.
    pub fn draw(&self, cmd: &Commands<'_>, push: &AtmosphereSkyPush) -> Result<()> {
        cmd.bind_pipeline(&self.pipeline, &self.layout, &[&self.set]);
        cmd.push_constants(&self.layout, push)?;
        cmd.draw(3, 1);
        Ok(())
    }
}

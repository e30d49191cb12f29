//! Samplers.

use std::sync::Arc;

use ash::vk;

use super::Context;
use crate::error::{Result, VkContext};

/// An owned `VkSampler`.
pub struct Sampler {
    raw: vk::Sampler,
    ctx: Arc<Context>,
}

impl Sampler {
    /// Trilinear filtering, repeating in both directions (tiling textures).
    pub fn linear_repeat(ctx: &Arc<Context>, name: &str) -> Result<Self> {
        Self::linear_repeat_max_lod(ctx, name, vk::LOD_CLAMP_NONE)
    }

    /// Trilinear repeating filtering using mip levels 0..=`max_lod` only.
    pub fn linear_repeat_max_lod(ctx: &Arc<Context>, name: &str, max_lod: f32) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .max_lod(max_lod);
        Self::create(ctx, name, &info)
    }

    /// Bilinear filtering clamped to the edge (maps over a bounded field).
    pub fn linear_clamp(ctx: &Arc<Context>, name: &str) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        Self::create(ctx, name, &info)
    }

    /// Nearest texel, one level, clamped to the edge: for formats that cannot be
    /// filtered (depth) read texel by texel.
    pub fn nearest_clamp(ctx: &Arc<Context>, name: &str) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        Self::create(ctx, name, &info)
    }

    /// Depth comparison (a shadow map): bilinear over the four texels' pass/fail
    /// (LESS_OR_EQUAL against the reference), one level; outside the map the border
    /// compares as the far plane, so what the map does not cover is lit.
    pub fn depth_compare(ctx: &Arc<Context>, name: &str) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_BORDER)
            .border_color(vk::BorderColor::FLOAT_OPAQUE_WHITE)
            .compare_enable(true)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL)
            .max_lod(0.0);
        Self::create(ctx, name, &info)
    }

    /// Trilinear filtering over every mip level, clamped to the edge (a cube map read
    /// at a level chosen by roughness).
    pub fn linear_clamp_mips(ctx: &Arc<Context>, name: &str) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE);
        Self::create(ctx, name, &info)
    }

    /// Creates and names the sampler `info` describes.
    fn create(ctx: &Arc<Context>, name: &str, info: &vk::SamplerCreateInfo<'_>) -> Result<Self> {
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device.create_sampler(info, None) }.vk("vkCreateSampler")?;
        ctx.name(raw, name);
        Ok(Self {
            raw,
            ctx: ctx.clone(),
        })
    }

    /// The `VkSampler` handle; destroyed with `self`.
    pub fn raw(&self) -> vk::Sampler {
        self.raw
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: the GPU is done with the sampler (submissions wait).
        unsafe { self.ctx.device.destroy_sampler(self.raw, None) };
    }
}

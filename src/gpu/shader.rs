//! `VkShaderModule` from the SPIR-V `build.rs` embedded, and stage conversions.

use std::sync::Arc;

use ash::vk;

use super::Context;
use crate::error::{Result, VkContext};
use crate::shaders::{DescriptorKind, ShaderSpirv, ShaderStageKind};

/// An owned shader module.
pub struct ShaderModule {
    raw: vk::ShaderModule,
    stage: ShaderStageKind,
    ctx: Arc<Context>,
}

impl ShaderModule {
    /// Creates a `VkShaderModule` from the embedded SPIR-V, debug-named by its path;
    /// fails if the bytes are not SPIR-V (length not a multiple of 4, or no magic number).
    pub fn new(ctx: &Arc<Context>, spirv: &ShaderSpirv) -> Result<Self> {
        let words = spirv.words()?;
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: `words` is SPIR-V produced by glslang at build time.
        let raw =
            unsafe { ctx.device.create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
        ctx.name(raw, spirv.path);
        Ok(Self {
            raw,
            stage: spirv.stage,
            ctx: ctx.clone(),
        })
    }

    /// The `VkShaderModule` handle; destroyed with `self` (needed only while pipelines
    /// are created).
    pub fn raw(&self) -> vk::ShaderModule {
        self.raw
    }

    /// The single stage flag of the module's stage, for pipeline stage create infos.
    pub fn stage(&self) -> vk::ShaderStageFlags {
        stage_flags(self.stage)
    }
}

impl Drop for ShaderModule {
    fn drop(&mut self) {
        // SAFETY: modules are only needed during pipeline creation, which has returned.
        unsafe { self.ctx.device.destroy_shader_module(self.raw, None) };
    }
}

pub(crate) fn stage_flags(stage: ShaderStageKind) -> vk::ShaderStageFlags {
    match stage {
        ShaderStageKind::Vertex => vk::ShaderStageFlags::VERTEX,
        ShaderStageKind::Geometry => vk::ShaderStageFlags::GEOMETRY,
        ShaderStageKind::Fragment => vk::ShaderStageFlags::FRAGMENT,
        ShaderStageKind::Compute => vk::ShaderStageFlags::COMPUTE,
    }
}

pub(crate) fn descriptor_type(kind: DescriptorKind) -> vk::DescriptorType {
    match kind {
        DescriptorKind::UniformBuffer => vk::DescriptorType::UNIFORM_BUFFER,
        DescriptorKind::StorageBuffer => vk::DescriptorType::STORAGE_BUFFER,
        DescriptorKind::SampledImage => vk::DescriptorType::SAMPLED_IMAGE,
        DescriptorKind::Sampler => vk::DescriptorType::SAMPLER,
        DescriptorKind::StorageImage => vk::DescriptorType::STORAGE_IMAGE,
        DescriptorKind::UniformTexelBuffer => vk::DescriptorType::UNIFORM_TEXEL_BUFFER,
    }
}

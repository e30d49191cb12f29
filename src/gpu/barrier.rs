//! Pipeline barriers (synchronization2), written once: those derived from tracked
//! resources' uses (`usage`), and the raw ones the wrappers in this module place for
//! what the tracking does not cover (mip levels one at a time, transform-feedback
//! counters, swapchain images, timestamps).

use ash::vk;

use super::Context;

/// A full memory barrier: all prior commands' writes visible to all later commands.
pub fn full(ctx: &Context, cmd: vk::CommandBuffer) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        .src_access_mask(vk::AccessFlags2::MEMORY_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
        .dst_access_mask(vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE)];
    let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
    // SAFETY: `cmd` is in the recording state on this device.
    unsafe { ctx.device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// A global memory barrier between two stage/access scopes.
pub fn memory(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
    // SAFETY: `cmd` is in the recording state on this device.
    unsafe { ctx.device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// A stage/access scope of a barrier.
pub type Scope = (vk::PipelineStageFlags2, vk::AccessFlags2);

/// Several global memory barriers (source scope, destination scope) in one pipeline
/// barrier (none: nothing recorded).
pub fn memories(ctx: &Context, cmd: vk::CommandBuffer, scopes: &[(Scope, Scope)]) {
    if scopes.is_empty() {
        return;
    }
    let barriers: Vec<vk::MemoryBarrier2<'_>> = scopes
        .iter()
        .map(|(src, dst)| {
            vk::MemoryBarrier2::default()
                .src_stage_mask(src.0)
                .src_access_mask(src.1)
                .dst_stage_mask(dst.0)
                .dst_access_mask(dst.1)
        })
        .collect();
    let dep = vk::DependencyInfo::default().memory_barriers(&barriers);
    // SAFETY: `cmd` is in the recording state on this device.
    unsafe { ctx.device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// One image layout transition with its scopes.
pub struct ImageTransition {
    /// Image whose layout changes; the caller keeps it alive until the barrier has run.
    pub image: vk::Image,
    /// Mip levels, array layers and aspects that change layout.
    pub range: vk::ImageSubresourceRange,
    /// Old layout, and the stages and accesses that must finish before the transition.
    pub from: LayoutScope,
    /// New layout, and the stages and accesses that wait for the transition.
    pub to: LayoutScope,
}

/// A side of a layout transition: layout, stages and accesses.
pub type LayoutScope = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

impl ImageTransition {
    /// Whatever the image held, nothing to wait for (its contents are discarded).
    pub const DISCARDED: LayoutScope = (
        vk::ImageLayout::UNDEFINED,
        vk::PipelineStageFlags2::TOP_OF_PIPE,
        vk::AccessFlags2::NONE,
    );
    /// Written by copies and blits.
    pub const TRANSFER_WRITTEN: LayoutScope = (
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
    );

    /// `range` of `image`, whatever it held, becomes the destination of copies or
    /// blits.
    pub fn discard_to_transfer_dst(image: vk::Image, range: vk::ImageSubresourceRange) -> Self {
        Self {
            image,
            range,
            from: Self::DISCARDED,
            to: Self::TRANSFER_WRITTEN,
        }
    }
}

/// Records the layout transitions in one barrier.
pub fn images(ctx: &Context, cmd: vk::CommandBuffer, transitions: &[ImageTransition]) {
    let barriers: Vec<vk::ImageMemoryBarrier2<'_>> = transitions
        .iter()
        .map(|t| {
            vk::ImageMemoryBarrier2::default()
                .image(t.image)
                .subresource_range(t.range)
                .old_layout(t.from.0)
                .src_stage_mask(t.from.1)
                .src_access_mask(t.from.2)
                .new_layout(t.to.0)
                .dst_stage_mask(t.to.1)
                .dst_access_mask(t.to.2)
        })
        .collect();
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barriers);
    // SAFETY: `cmd` is recording; the images belong to this device.
    unsafe { ctx.device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// The barriers derived for tracked images and buffers (`usage::Dependency`), in one
/// pipeline barrier (none: nothing recorded).
pub(crate) fn dependencies(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    images: &[(
        vk::Image,
        vk::ImageSubresourceRange,
        super::usage::Dependency,
    )],
    buffers: &[(vk::Buffer, super::usage::Dependency)],
) {
    if images.is_empty() && buffers.is_empty() {
        return;
    }
    let image_barriers: Vec<vk::ImageMemoryBarrier2<'_>> = images
        .iter()
        .map(|(image, range, d)| {
            vk::ImageMemoryBarrier2::default()
                .image(*image)
                .subresource_range(*range)
                .old_layout(d.old_layout)
                .new_layout(d.new_layout)
                .src_stage_mask(d.src_stages)
                .src_access_mask(d.src_access)
                .dst_stage_mask(d.dst_stages)
                .dst_access_mask(d.dst_access)
        })
        .collect();
    let buffer_barriers: Vec<vk::BufferMemoryBarrier2<'_>> = buffers
        .iter()
        .map(|(buffer, d)| {
            vk::BufferMemoryBarrier2::default()
                .buffer(*buffer)
                .offset(0)
                .size(vk::WHOLE_SIZE)
                .src_stage_mask(d.src_stages)
                .src_access_mask(d.src_access)
                .dst_stage_mask(d.dst_stages)
                .dst_access_mask(d.dst_access)
        })
        .collect();
    let dep = vk::DependencyInfo::default()
        .image_memory_barriers(&image_barriers)
        .buffer_memory_barriers(&buffer_barriers);
    // SAFETY: `cmd` is recording outside a rendering scope; the images and buffers
    // belong to this device and their owners keep them alive until it has run.
    unsafe { ctx.device.cmd_pipeline_barrier2(cmd, &dep) };
}

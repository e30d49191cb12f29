//! A command buffer being recorded, with the draw/bind/copy calls passes need, so that
//! passes never call ash themselves.

use ash::vk;

use super::pipeline::{DescriptorSet, Pipeline, PipelineLayout};
use super::{Buffer, Context, Pod};
use crate::error::Result;

/// A command buffer in the recording state (see `Context::submit_and_wait`).
pub struct Commands<'a> {
    pub(crate) ctx: &'a Context,
    pub(crate) raw: vk::CommandBuffer,
}

impl Commands<'_> {
    /// The `vk::CommandBuffer` being recorded; owned by the context, valid only for the
    /// recording closure.
    pub fn raw(&self) -> vk::CommandBuffer {
        self.raw
    }

    /// The context whose device and queue the commands are recorded for.
    pub fn context(&self) -> &Context {
        self.ctx
    }

    /// Binds `pipeline` at its bind point and `sets` from set 0 against `layout`.
    pub fn bind_pipeline(
        &self,
        pipeline: &Pipeline,
        layout: &PipelineLayout,
        sets: &[&DescriptorSet],
    ) {
        pipeline.bind(self.raw, layout, sets);
    }

    /// Pushes `value` as the layout's whole push-constant block; its size must equal the
    /// declared block's, else an internal error and nothing is recorded.
    pub fn push_constants<T: Pod>(&self, layout: &PipelineLayout, value: &T) -> Result<()> {
        layout.push(self.raw, value)
    }

    /// Viewport and scissor covering `width` x `height` from the origin.
    pub fn set_viewport(&self, width: u32, height: u32) {
        self.set_viewport_at(0.0, width as f32, height as f32);
        self.set_scissor(0, 0, width, height);
    }

    /// Viewport of `width` x `height` from column `x` (which may lie left of the
    /// target, within the device's viewport bounds: a frame-sized viewport centred
    /// on a panel); the scissor is left as it was.
    pub fn set_viewport_at(&self, x: f32, width: f32, height: f32) {
        let viewport = [vk::Viewport {
            x,
            y: 0.0,
            width,
            height,
            min_depth: 0.0,
            max_depth: 1.0,
        }];
        // SAFETY: `raw` is recording; the pipelines declare the viewport dynamic.
        unsafe {
            self.ctx.device.cmd_set_viewport(self.raw, 0, &viewport);
        }
    }

    /// Scissor to `width` x `height` from pixel (`x`, `y`): nothing drawn outside.
    pub fn set_scissor(&self, x: u32, y: u32, width: u32, height: u32) {
        let scissor = [vk::Rect2D {
            offset: vk::Offset2D {
                x: i32::try_from(x).unwrap_or(i32::MAX),
                y: i32::try_from(y).unwrap_or(i32::MAX),
            },
            extent: vk::Extent2D { width, height },
        }];
        // SAFETY: `raw` is recording; the pipelines declare the scissor dynamic.
        unsafe {
            self.ctx.device.cmd_set_scissor(self.raw, 0, &scissor);
        }
    }

    /// Binds `buffer` from byte `offset` as vertex binding 0; it needs `VERTEX_BUFFER`
    /// usage.
    pub fn bind_vertex_buffer(&self, buffer: &Buffer, offset: u64) {
        // SAFETY: `raw` is recording; the buffer has VERTEX_BUFFER usage by construction.
        unsafe {
            self.ctx
                .device
                .cmd_bind_vertex_buffers(self.raw, 0, &[buffer.raw()], &[offset])
        };
    }

    /// Binds the whole of `buffer` as `u32` indices; it needs `INDEX_BUFFER` usage.
    pub fn bind_index_buffer(&self, buffer: &Buffer) {
        // SAFETY: `raw` is recording; the buffer holds u32 indices.
        unsafe {
            self.ctx
                .device
                .cmd_bind_index_buffer(self.raw, buffer.raw(), 0, vk::IndexType::UINT32)
        };
    }

    /// Non-indexed draw from vertex 0 and instance 0; needs an open rendering scope and
    /// a bound graphics pipeline.
    pub fn draw(&self, vertex_count: u32, instance_count: u32) {
        // SAFETY: `raw` is recording inside a rendering scope with a bound pipeline.
        unsafe {
            self.ctx
                .device
                .cmd_draw(self.raw, vertex_count, instance_count, 0, 0)
        };
    }

    /// Indexed draw from index 0 with no vertex offset; needs an open rendering scope and
    /// bound pipeline, vertex and index buffers.
    pub fn draw_indexed(&self, index_count: u32, instance_count: u32) {
        // SAFETY: `raw` is recording inside a rendering scope with bound pipeline/buffers.
        unsafe {
            self.ctx
                .device
                .cmd_draw_indexed(self.raw, index_count, instance_count, 0, 0, 0)
        };
    }

    /// Draws `index_count` indices from `first_index` of the bound index buffer, one
    /// instance.
    pub fn draw_indexed_range(&self, first_index: u32, index_count: u32) {
        // SAFETY: `raw` is recording inside a rendering scope with bound pipeline/buffers.
        unsafe {
            self.ctx
                .device
                .cmd_draw_indexed(self.raw, index_count, 1, first_index, 0, 0)
        };
    }

    /// Dispatches `x` x `y` x `z` workgroups (not invocations) of the bound compute
    /// pipeline, with no barrier after it.
    pub fn dispatch(&self, x: u32, y: u32, z: u32) {
        // SAFETY: `raw` is recording with a bound compute pipeline.
        unsafe { self.ctx.device.cmd_dispatch(self.raw, x, y, z) };
    }

    /// A dispatch whose writes every later command sees: the next stage of a
    /// multi-stage compute pass, a draw reading its output as vertices or as an
    /// indirect count (a full barrier).
    pub fn dispatch_then_sync(&self, x: u32, y: u32, z: u32) {
        self.dispatch(x, y, z);
        self.full_barrier();
    }

    /// Copies `size` bytes between buffers.
    pub fn copy_buffer(&self, src: &Buffer, dst: &Buffer, size: u64) {
        let region = [vk::BufferCopy {
            src_offset: 0,
            dst_offset: 0,
            size,
        }];
        // SAFETY: `raw` is recording; both buffers are large enough (caller's contract,
        // checked by validation in tests).
        unsafe {
            self.ctx
                .device
                .cmd_copy_buffer(self.raw, src.raw(), dst.raw(), &region)
        };
    }

    /// Copies `size` bytes from `src` at `src_offset` to `dst` at `dst_offset`.
    pub fn copy_buffer_region(
        &self,
        src: &Buffer,
        src_offset: u64,
        dst: &Buffer,
        dst_offset: u64,
        size: u64,
    ) {
        let region = [vk::BufferCopy {
            src_offset,
            dst_offset,
            size,
        }];
        // SAFETY: `raw` is recording; ranges are checked by validation in tests.
        unsafe {
            self.ctx
                .device
                .cmd_copy_buffer(self.raw, src.raw(), dst.raw(), &region)
        };
    }

    /// Fills `size` bytes of `buffer` from `offset` with the word `value`.
    pub fn fill_buffer(&self, buffer: &Buffer, offset: u64, size: u64, value: u32) {
        // SAFETY: `raw` is recording outside a rendering scope; the buffer has
        // TRANSFER_DST usage (validation checks it in tests).
        unsafe {
            self.ctx
                .device
                .cmd_fill_buffer(self.raw, buffer.raw(), offset, size, value)
        };
    }

    /// A full memory barrier (see `barrier::full`).
    pub(crate) fn full_barrier(&self) {
        super::barrier::full(self.ctx, self.raw);
    }

    /// Transfer writes made visible to the host (before reading a readback buffer).
    pub(crate) fn transfer_to_host_barrier(&self) {
        super::barrier::memory(
            self.ctx,
            self.raw,
            (
                vk::PipelineStageFlags2::TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
    }

    /// Begins dynamic rendering with no attachments over `width` x `height`, for
    /// transform-feedback passes whose rasterizer is discarded.
    pub fn begin_rendering_without_attachments(&self, width: u32, height: u32) {
        let info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D { x: 0, y: 0 },
                extent: vk::Extent2D { width, height },
            })
            .layer_count(1);
        // SAFETY: `raw` is recording outside a rendering scope.
        unsafe { self.ctx.device.cmd_begin_rendering(self.raw, &info) };
        self.set_viewport(width, height);
    }

    /// Begins dynamic rendering into `colors` (each in COLOR_ATTACHMENT_OPTIMAL, every
    /// pixel overwritten: nothing is loaded), no depth, over `width` x `height`.
    pub fn begin_rendering_colors(&self, colors: &[vk::ImageView], width: u32, height: u32) {
        let attachments: Vec<vk::RenderingAttachmentInfo<'_>> = colors
            .iter()
            .map(|&view| {
                vk::RenderingAttachmentInfo::default()
                    .image_view(view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .store_op(vk::AttachmentStoreOp::STORE)
            })
            .collect();
        let info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D { x: 0, y: 0 },
                extent: vk::Extent2D { width, height },
            })
            .layer_count(1)
            .color_attachments(&attachments);
        // SAFETY: `raw` is recording outside a rendering scope; the caller put the
        // views' images in COLOR_ATTACHMENT_OPTIMAL.
        unsafe { self.ctx.device.cmd_begin_rendering(self.raw, &info) };
        self.set_viewport(width, height);
    }

    /// Copies mip level 0, layer 0 of `from` (TRANSFER_SRC_OPTIMAL) into the same of
    /// `to` (TRANSFER_DST_OPTIMAL), `width` x `height` texels of `aspect`; the two
    /// images share a format (or a compatible one) and have the transfer usages.
    pub fn copy_whole_image(
        &self,
        from: vk::Image,
        to: vk::Image,
        aspect: vk::ImageAspectFlags,
        width: u32,
        height: u32,
    ) {
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: aspect,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let region = [vk::ImageCopy::default()
            .src_subresource(layers)
            .dst_subresource(layers)
            .extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })];
        // SAFETY: recording outside a rendering scope; the caller keeps both images
        // alive, in the layouts named, with the usages and formats documented above.
        unsafe {
            self.ctx.device.cmd_copy_image(
                self.raw,
                from,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                to,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
            )
        };
    }

    /// Ends the dynamic-rendering scope begun on this command buffer.
    pub fn end_rendering(&self) {
        // SAFETY: a rendering scope begun on `raw` is open.
        unsafe { self.ctx.device.cmd_end_rendering(self.raw) };
    }
}

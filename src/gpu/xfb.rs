//! Safe wrappers, written once, over VK_EXT_transform_feedback, which ash 0.38 exposes
//! only as raw function pointers: binding capture buffers, begin/end with counter
//! buffers, `vkCmdDrawIndirectByteCountEXT` (Vulkan's DrawAuto), the stream query, and
//! the barriers a capture needs (validation does not check them, and lavapipe tolerates
//! their absence, so they must be right by construction).

use std::sync::Arc;

use ash::vk;

use super::{Buffer, BufferDesc, Commands, Context};
use crate::error::{Error, Result, VkContext};

/// Usage a capture buffer needs: written by XFB, read back as vertices, copyable.
pub const CAPTURE_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::TRANSFORM_FEEDBACK_BUFFER_EXT.as_raw()
        | vk::BufferUsageFlags::VERTEX_BUFFER.as_raw()
        | vk::BufferUsageFlags::STORAGE_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

/// A counter buffer is both written by XFB and read by the indirect draw.
pub const COUNTER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::TRANSFORM_FEEDBACK_COUNTER_BUFFER_EXT.as_raw()
        | vk::BufferUsageFlags::INDIRECT_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

/// A device-local capture buffer of `bytes`.
pub fn capture_buffer(ctx: &Arc<Context>, name: &str, bytes: u64) -> Result<Buffer> {
    Buffer::new(ctx, name, BufferDesc::gpu_only(bytes, CAPTURE_USAGE))
}

/// A counter buffer (one u32 byte counter per capture buffer, 4-byte aligned).
pub fn counter_buffer(ctx: &Arc<Context>, name: &str, counters: u32) -> Result<Buffer> {
    Buffer::new(
        ctx,
        name,
        BufferDesc::gpu_only(u64::from(counters.max(1)) * 4, COUNTER_USAGE),
    )
}

impl Commands<'_> {
    /// Binds `buffer[offset..offset+size]` as capture buffer `binding` (stream 0 writes
    /// binding 0 in sediment's shaders). `size` `None` means the rest of the buffer.
    pub fn bind_capture_buffer(
        &self,
        binding: u32,
        buffer: &Buffer,
        offset: u64,
        size: Option<u64>,
    ) {
        let buffers = [buffer.raw()];
        let offsets = [offset];
        let sizes = [size.unwrap_or(vk::WHOLE_SIZE)];
        // SAFETY: `raw` is recording; the buffer has TRANSFORM_FEEDBACK_BUFFER usage
        // (CAPTURE_USAGE) and the arrays hold one element each, as `binding_count` says.
        unsafe {
            (self.ctx.xfb.fp().cmd_bind_transform_feedback_buffers_ext)(
                self.raw,
                binding,
                1,
                buffers.as_ptr(),
                offsets.as_ptr(),
                sizes.as_ptr(),
            )
        };
    }

    /// Starts capture. With `resume = Some((counter, offset))` capture continues at the
    /// byte count stored in the counter (append); with `None` it starts at the bound
    /// offset. Must be inside a rendering scope with a pipeline bound.
    pub fn begin_capture(&self, resume: Option<(&Buffer, u64)>) {
        let (buffers, offsets) = match resume {
            Some((b, o)) => (vec![b.raw()], vec![o]),
            None => (Vec::new(), Vec::new()),
        };
        // SAFETY: `raw` is recording inside a rendering scope; a counter buffer, when
        // given, has TRANSFORM_FEEDBACK_COUNTER usage and a barrier from its last write
        // (see `counter_write_to_read`). count 0 with null arrays is allowed.
        unsafe {
            (self.ctx.xfb.fp().cmd_begin_transform_feedback_ext)(
                self.raw,
                0,
                buffers.len() as u32,
                if buffers.is_empty() {
                    std::ptr::null()
                } else {
                    buffers.as_ptr()
                },
                if offsets.is_empty() {
                    std::ptr::null()
                } else {
                    offsets.as_ptr()
                },
            )
        };
    }

    /// Ends capture, storing the byte count reached into `counter` at `offset`.
    pub fn end_capture(&self, counter: Option<(&Buffer, u64)>) {
        let (buffers, offsets) = match counter {
            Some((b, o)) => (vec![b.raw()], vec![o]),
            None => (Vec::new(), Vec::new()),
        };
        // SAFETY: capture is active on `raw` (begun by `begin_capture`).
        unsafe {
            (self.ctx.xfb.fp().cmd_end_transform_feedback_ext)(
                self.raw,
                0,
                buffers.len() as u32,
                if buffers.is_empty() {
                    std::ptr::null()
                } else {
                    buffers.as_ptr()
                },
                if offsets.is_empty() {
                    std::ptr::null()
                } else {
                    offsets.as_ptr()
                },
            )
        };
    }

    /// Draws as many vertices as the counter says were captured (`byte count /
    /// vertex_stride`): the CPU never reads the count.
    pub fn draw_indirect_byte_count(
        &self,
        counter: &Buffer,
        counter_offset: u64,
        vertex_stride: u32,
        instance_count: u32,
    ) {
        // SAFETY: `raw` is recording inside a rendering scope with a pipeline and vertex
        // buffer bound; the counter has INDIRECT_BUFFER usage and was made visible to
        // indirect reads (`counter_write_to_read`).
        unsafe {
            (self.ctx.xfb.fp().cmd_draw_indirect_byte_count_ext)(
                self.raw,
                instance_count,
                0,
                counter.raw(),
                counter_offset,
                0,
                vertex_stride,
            )
        };
    }

    /// Captured vertices become visible to the vertex-input stage and to copies/shaders.
    pub fn capture_to_vertex_read_barrier(&self) {
        super::barrier::memory(
            self.ctx,
            self.raw,
            (
                vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT,
                vk::AccessFlags2::TRANSFORM_FEEDBACK_WRITE_EXT,
            ),
            (
                vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                    | vk::PipelineStageFlags2::COPY
                    | vk::PipelineStageFlags2::ALL_COMMANDS,
                vk::AccessFlags2::VERTEX_ATTRIBUTE_READ
                    | vk::AccessFlags2::TRANSFER_READ
                    | vk::AccessFlags2::SHADER_STORAGE_READ,
            ),
        );
    }

    /// Counter writes become visible to the indirect draw, to a resumed capture and to
    /// copies.
    pub fn counter_write_to_read_barrier(&self) {
        super::barrier::memory(
            self.ctx,
            self.raw,
            (
                vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT,
                vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_WRITE_EXT,
            ),
            (
                vk::PipelineStageFlags2::DRAW_INDIRECT
                    | vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT
                    | vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::INDIRECT_COMMAND_READ
                    | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_READ_EXT
                    | vk::AccessFlags2::TRANSFER_READ,
            ),
        );
    }

    /// A reused capture buffer's previous reads (as vertex input) finish before it is
    /// overwritten (ping-pong: write-after-read).
    pub fn vertex_read_to_capture_barrier(&self) {
        super::barrier::memory(
            self.ctx,
            self.raw,
            (
                vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                    | vk::PipelineStageFlags2::DRAW_INDIRECT,
                vk::AccessFlags2::NONE,
            ),
            (
                vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT,
                vk::AccessFlags2::TRANSFORM_FEEDBACK_WRITE_EXT
                    | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_WRITE_EXT
                    | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_READ_EXT,
            ),
        );
    }
}

/// Primitives a capture wrote, and how many it would have written with room enough.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamCounts {
    pub written: u64,
    pub needed: u64,
}

impl StreamCounts {
    /// True when the capture buffer was too small and output was dropped.
    pub fn overflowed(&self) -> bool {
        self.needed > self.written
    }
}

/// A pool of transform-feedback stream queries (`VK_QUERY_TYPE_TRANSFORM_FEEDBACK_STREAM_EXT`).
pub struct StreamQueries {
    pool: vk::QueryPool,
    count: u32,
    ctx: Arc<Context>,
}

impl StreamQueries {
    pub fn new(ctx: &Arc<Context>, name: &str, count: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TRANSFORM_FEEDBACK_STREAM_EXT)
            .query_count(count.max(1));
        // SAFETY: valid device; transformFeedbackQueries was checked at device choice.
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        ctx.name(pool, name);
        Ok(Self {
            pool,
            count: count.max(1),
            ctx: ctx.clone(),
        })
    }

    /// Resets every query; record outside a rendering scope before using them.
    pub fn reset(&self, cmd: &Commands<'_>) {
        // SAFETY: `cmd` is recording outside a rendering scope; the range is the pool's.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(cmd.raw, self.pool, 0, self.count)
        };
    }

    /// Resets queries `first..first + count`; record outside a rendering scope.
    pub fn reset_range(&self, cmd: &Commands<'_>, first: u32, count: u32) -> Result<()> {
        if first.saturating_add(count) > self.count {
            return Err(Error::invalid(
                "stream query",
                format!(
                    "range {first}..{} outside the pool's {} queries",
                    first + count,
                    self.count
                ),
            ));
        }
        // SAFETY: `cmd` is recording outside a rendering scope; the range is checked.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(cmd.raw, self.pool, first, count)
        };
        Ok(())
    }

    /// Starts counting stream 0 into query `index`.
    pub fn begin(&self, cmd: &Commands<'_>, index: u32) -> Result<()> {
        self.check(index)?;
        // SAFETY: the query was reset and is not active; stream 0 exists.
        unsafe {
            (self.ctx.xfb.fp().cmd_begin_query_indexed_ext)(
                cmd.raw,
                self.pool,
                index,
                vk::QueryControlFlags::empty(),
                0,
            )
        };
        Ok(())
    }

    pub fn end(&self, cmd: &Commands<'_>, index: u32) -> Result<()> {
        self.check(index)?;
        // SAFETY: the query was begun on this command buffer.
        unsafe { (self.ctx.xfb.fp().cmd_end_query_indexed_ext)(cmd.raw, self.pool, index, 0) };
        Ok(())
    }

    fn check(&self, index: u32) -> Result<()> {
        if index < self.count {
            Ok(())
        } else {
            Err(Error::invalid(
                "stream query",
                format!("index {index} outside the pool's {} queries", self.count),
            ))
        }
    }

    /// Reads queries `0..n` (after the submission finished).
    pub fn results(&self, n: u32) -> Result<Vec<StreamCounts>> {
        let n = n.min(self.count);
        let mut data = vec![[0u64; 2]; n as usize];
        // SAFETY: the queries were written by a completed submission; each result is two
        // u64s (primitives written, primitives needed) as the spec defines.
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults (transform feedback stream)")?;
        Ok(data
            .into_iter()
            .map(|[written, needed]| StreamCounts { written, needed })
            .collect())
    }
}

impl Drop for StreamQueries {
    fn drop(&mut self) {
        // SAFETY: no submission using the pool is pending.
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}

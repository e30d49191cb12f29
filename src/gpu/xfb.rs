//! Transform feedback (VK_EXT_transform_feedback), which ash 0.38 exposes only as raw
//! function pointers, wrapped once: an [`XfbStream`] — a capture buffer and the counter
//! holding its byte count — that places its own barriers from the state its last use
//! left it in, `vkCmdDrawIndirectByteCountEXT` (Vulkan's DrawAuto) through it, and the
//! stream query. Validation does not check these barriers and lavapipe tolerates their
//! absence, so they are right by construction here, and nowhere else.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;

use super::{Buffer, BufferDesc, Commands, Context, Pod};
use crate::error::{Error, Result, VkContext};

/// Usage a capture buffer needs: written by XFB, read back as vertices, copyable.
const CAPTURE_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::TRANSFORM_FEEDBACK_BUFFER_EXT.as_raw()
        | vk::BufferUsageFlags::VERTEX_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw(),
);

/// A counter buffer is written by XFB, read by the indirect draw and by a resumed
/// capture, filled and copied.
const COUNTER_USAGE: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::TRANSFORM_FEEDBACK_COUNTER_BUFFER_EXT.as_raw()
        | vk::BufferUsageFlags::INDIRECT_BUFFER.as_raw()
        | vk::BufferUsageFlags::TRANSFER_SRC.as_raw()
        | vk::BufferUsageFlags::TRANSFER_DST.as_raw(),
);

/// Where a capture starts writing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaptureMode {
    /// At the start of the buffer: the capture replaces what was there.
    Restart,
    /// At the byte count the counter holds: the capture appends (a stream's first
    /// append starts at zero).
    Append,
}

/// What the last use of a stream left its buffer and counter in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    /// Nothing on the GPU has touched it; the counter is undefined.
    Fresh,
    /// Ready to be captured into (`prepare_captures`), inside the next rendering scope.
    Writable,
    /// Capturing between `begin` and `end`.
    Capturing,
    /// Written by a capture, not yet visible to anything.
    Captured,
    /// Captured vertices and byte count visible to vertex input, indirect draws,
    /// copies and a resumed capture, which may be reading them.
    Readable,
}

/// A transform-feedback capture buffer and its byte counter, owning their barriers.
///
/// Its life is a cycle: [`XfbStream::prepare_captures`] (outside a rendering scope),
/// [`begin`](XfbStream::begin) and [`end`](XfbStream::end) around the draws that emit
/// (inside one), [`XfbStream::finish_captures`] (outside again), after which it can
/// be drawn ([`draw`](XfbStream::draw)) or read back. State is tracked per stream
/// across command buffers, so every barrier a use needs is placed once, by the stream.
pub struct XfbStream {
    state: Cell<State>,
    counter: Buffer,
    buffer: Buffer,
}

impl XfbStream {
    /// A device-local capture buffer of `bytes` and its counter.
    pub fn new(ctx: &Arc<Context>, name: &str, bytes: u64) -> Result<Self> {
        Ok(Self {
            state: Cell::new(State::Fresh),
            counter: Buffer::new(
                ctx,
                &format!("{name} counter"),
                BufferDesc::gpu_only(4, COUNTER_USAGE),
            )?,
            buffer: Buffer::new(ctx, name, BufferDesc::gpu_only(bytes.max(4), CAPTURE_USAGE))?,
        })
    }

    /// Capacity in bytes.
    pub fn size(&self) -> u64 {
        self.buffer.size()
    }

    /// Makes each stream ready to be captured into with its mode, in one barrier,
    /// before the rendering scope of the capture:
    /// - read since its last capture (drawn, copied, or the input of a pass): those
    ///   reads finish first (write-after-read), and the write-after-write chain from
    ///   the capture before runs through the barrier that made it readable;
    /// - captured and not yet made readable (an append after an append): its data and
    ///   counter writes come before the new capture's (write-after-write), and the
    ///   counter's byte count before the resumed capture reads it;
    /// - fresh and appending: its counter is filled with zero first.
    pub fn prepare_captures(cmd: &Commands<'_>, streams: &[(&XfbStream, CaptureMode)]) {
        let mut after_reads = false;
        let mut after_capture = false;
        let mut after_fill = false;
        for (stream, mode) in streams {
            match (stream.state.get(), mode) {
                (State::Readable, _) => after_reads = true,
                (State::Captured, _) => after_capture = true,
                (State::Fresh, CaptureMode::Append) => {
                    cmd.fill_buffer(&stream.counter, 0, 4, 0);
                    after_fill = true;
                }
                _ => {}
            }
            stream.state.set(State::Writable);
        }
        let capture = (
            vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT,
            vk::AccessFlags2::TRANSFORM_FEEDBACK_WRITE_EXT
                | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_WRITE_EXT
                | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_READ_EXT,
        );
        let mut barriers = Vec::new();
        if after_reads {
            barriers.push((
                (
                    vk::PipelineStageFlags2::VERTEX_ATTRIBUTE_INPUT
                        | vk::PipelineStageFlags2::DRAW_INDIRECT
                        | vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT
                        | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::NONE,
                ),
                capture,
            ));
        }
        if after_capture {
            barriers.push((
                (
                    vk::PipelineStageFlags2::TRANSFORM_FEEDBACK_EXT,
                    vk::AccessFlags2::TRANSFORM_FEEDBACK_WRITE_EXT
                        | vk::AccessFlags2::TRANSFORM_FEEDBACK_COUNTER_WRITE_EXT,
                ),
                capture,
            ));
        }
        if after_fill {
            barriers.push((
                (
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
                capture,
            ));
        }
        super::barrier::memories(cmd.ctx, cmd.raw, &barriers);
    }

    /// Makes what the streams captured visible to vertex input, indirect draws,
    /// copies and resumed captures, in one barrier, after the capture's rendering
    /// scope.
    pub fn finish_captures(cmd: &Commands<'_>, streams: &[&XfbStream]) {
        let mut any = false;
        for stream in streams {
            if stream.state.get() == State::Captured {
                any = true;
                stream.state.set(State::Readable);
            }
        }
        if any {
            readable_barrier(cmd);
        }
    }

    /// Binds the stream as capture buffer 0 and starts capturing (stream 0, inside a
    /// rendering scope, with the emitting pipeline bound, after `prepare_captures`).
    pub fn begin(&self, cmd: &Commands<'_>, mode: CaptureMode) -> Result<()> {
        if self.state.get() != State::Writable {
            return Err(Error::internal(
                "transform feedback",
                format!(
                    "capture begun on a stream in state {:?} (prepare_captures first)",
                    self.state.get()
                ),
            ));
        }
        self.state.set(State::Capturing);
        let buffers = [self.buffer.raw()];
        let offsets = [0u64];
        let sizes = [vk::WHOLE_SIZE];
        // SAFETY: `raw` is recording inside a rendering scope; the buffer has
        // TRANSFORM_FEEDBACK_BUFFER usage and each array holds the one binding.
        unsafe {
            (cmd.ctx.xfb.fp().cmd_bind_transform_feedback_buffers_ext)(
                cmd.raw,
                0,
                1,
                buffers.as_ptr(),
                offsets.as_ptr(),
                sizes.as_ptr(),
            )
        };
        let counters = [self.counter.raw()];
        let counter_offsets = [0u64];
        let resume = mode == CaptureMode::Append;
        // SAFETY: capture is not active; with `Append` the counter has
        // TRANSFORM_FEEDBACK_COUNTER usage and `prepare_captures` made its byte count
        // visible; with zero counter buffers the arrays may be null.
        unsafe {
            (cmd.ctx.xfb.fp().cmd_begin_transform_feedback_ext)(
                cmd.raw,
                0,
                u32::from(resume),
                if resume {
                    counters.as_ptr()
                } else {
                    std::ptr::null()
                },
                if resume {
                    counter_offsets.as_ptr()
                } else {
                    std::ptr::null()
                },
            )
        };
        Ok(())
    }

    /// Ends capturing, storing the byte count reached in the stream's counter.
    pub fn end(&self, cmd: &Commands<'_>) -> Result<()> {
        if self.state.get() != State::Capturing {
            return Err(Error::internal(
                "transform feedback",
                "capture ended on a stream that was not capturing",
            ));
        }
        self.state.set(State::Captured);
        let counters = [self.counter.raw()];
        let offsets = [0u64];
        // SAFETY: capture is active on `raw` (begun by `begin`); the counter has
        // TRANSFORM_FEEDBACK_COUNTER usage.
        unsafe {
            (cmd.ctx.xfb.fp().cmd_end_transform_feedback_ext)(
                cmd.raw,
                0,
                1,
                counters.as_ptr(),
                offsets.as_ptr(),
            )
        };
        Ok(())
    }

    /// Binds the stream as vertex buffer 0 and draws as many vertices as its counter
    /// says were captured (byte count / `vertex_stride`): the CPU never reads the count.
    /// Inside a rendering scope, after `finish_captures`.
    pub fn draw(&self, cmd: &Commands<'_>, vertex_stride: u32, instances: u32) -> Result<()> {
        self.draw_skipping(cmd, vertex_stride, instances, 0)
    }

    /// Draws the captured vertices from vertex `first` on (`vertex_stride` bytes each)
    /// to the end of the capture, with the byte count its counter holds less the
    /// skipped bytes; nothing where `first` is at or past the buffer's end.
    pub fn draw_from(&self, cmd: &Commands<'_>, vertex_stride: u32, first: u64) -> Result<()> {
        let skipped = first * u64::from(vertex_stride);
        if skipped > 0 && skipped >= self.buffer.size() {
            return Ok(());
        }
        self.draw_skipping(cmd, vertex_stride, 1, skipped)
    }

    /// `draw` with the vertex buffer bound `skipped` bytes in and the same bytes taken
    /// off the counter's byte count.
    fn draw_skipping(
        &self,
        cmd: &Commands<'_>,
        vertex_stride: u32,
        instances: u32,
        skipped: u64,
    ) -> Result<()> {
        if self.state.get() != State::Readable {
            return Err(Error::internal(
                "transform feedback",
                format!(
                    "a stream in state {:?} drawn (finish_captures first)",
                    self.state.get()
                ),
            ));
        }
        let counter_offset = u32::try_from(skipped)
            .map_err(|_| Error::internal("transform feedback", "a draw offset past 4 GiB"))?;
        cmd.bind_vertex_buffer(&self.buffer, skipped);
        // SAFETY: `raw` is recording inside a rendering scope with a pipeline and this
        // vertex buffer bound (from `skipped`, inside the buffer); the counter has
        // INDIRECT_BUFFER usage and its byte count was made visible to indirect reads
        // (`finish_captures`).
        unsafe {
            (cmd.ctx.xfb.fp().cmd_draw_indirect_byte_count_ext)(
                cmd.raw,
                instances,
                0,
                self.counter.raw(),
                0,
                counter_offset,
                vertex_stride,
            )
        };
        Ok(())
    }

    /// Records a copy of `bytes` of the capture from byte `from` into `dst` (from its
    /// start); the stream must be readable (its capture finished), and `dst` is then
    /// made visible to the host.
    pub fn copy_out(&self, cmd: &Commands<'_>, from: u64, bytes: u64, dst: &Buffer) -> Result<()> {
        if self.state.get() != State::Readable {
            return Err(Error::internal(
                "transform feedback",
                format!("a stream in state {:?} copied", self.state.get()),
            ));
        }
        if from + bytes > self.buffer.size() || bytes > dst.size() {
            return Err(Error::internal(
                "transform feedback",
                format!(
                    "a copy of {bytes} bytes from {from} out of a {} byte capture into {}",
                    self.buffer.size(),
                    dst.size()
                ),
            ));
        }
        cmd.copy_buffer_region(&self.buffer, from, dst, 0, bytes);
        cmd.transfer_to_host_barrier();
        Ok(())
    }

    /// The captured data as `T`s, read back (submits its own copy and waits).
    pub fn read_back<T: Pod>(&self, ctx: &Arc<Context>) -> Result<Vec<T>> {
        let bytes = self.buffer.size();
        let readback = Buffer::new(
            ctx,
            "capture readback",
            BufferDesc::readback(bytes + 4, vk::BufferUsageFlags::TRANSFER_DST),
        )?;
        if self.state.get() == State::Fresh {
            return Ok(Vec::new());
        }
        ctx.submit_and_wait("capture readback", |cmd| {
            Self::finish_captures(cmd, &[self]);
            if self.state.get() != State::Readable {
                return Err(Error::internal(
                    "transform feedback",
                    "a stream read back in the middle of a capture",
                ));
            }
            cmd.copy_buffer(&self.buffer, &readback, bytes);
            cmd.copy_buffer_region(&self.counter, 0, &readback, bytes, 4);
            cmd.transfer_to_host_barrier();
            Ok(())
        })?;
        let data = readback.mapped()?;
        let mut word = [0u8; 4];
        word.copy_from_slice(&data[bytes as usize..bytes as usize + 4]);
        let used = u64::from(u32::from_le_bytes(word)).min(bytes);
        Ok(crate::gpu::from_bytes(&data[..used as usize]))
    }
}

/// Captured data and counters visible to their readers: vertex input and copies (and
/// shaders) for the data; indirect draws, resumed captures and copies for the counter.
fn readable_barrier(cmd: &Commands<'_>) {
    super::barrier::memories(
        cmd.ctx,
        cmd.raw,
        &[
            (
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
            ),
            (
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
            ),
        ],
    );
}

/// Primitives a capture wrote, and how many it would have written with room enough.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StreamCounts {
    /// Primitives actually written to the capture buffer(s) of stream 0.
    pub written: u64,
    /// Primitives emitted to stream 0, whether or not they fitted in the buffer(s).
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
    /// Creates a pool of `count` stream queries (at least one), debug-named `name`; they
    /// must be reset (`reset`, `reset_range`) before first use.
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
            return Err(Error::internal(
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

    /// Stops counting stream 0 into query `index`, begun on the same command buffer.
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
            Err(Error::internal(
                "stream query",
                format!("index {index} outside the pool's {} queries", self.count),
            ))
        }
    }

    /// Reads queries `0..n` (after the submission finished).
    pub fn results(&self, n: u32) -> Result<Vec<StreamCounts>> {
        let n = n.min(self.count);
        if n == 0 {
            // vkGetQueryPoolResults with no queries is invalid (dataSize 0).
            return Ok(Vec::new());
        }
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

//! GPU timings: named spans bracketed by timestamp queries.
//!
//! On lavapipe a timestamp brackets vertex, geometry or compute work only if a full
//! memory barrier follows the start stamp and precedes the end stamp; without them such
//! work reads as ~0 ms. So every span is `stamp, barrier, work, barrier, stamp`. The
//! barriers cannot go inside a rendering scope, so a span wraps a whole pass (begin and
//! end rendering included): [`GpuTimer::span`] around a closure that records it, or
//! [`GpuTimer::scope`], which ends the span when it is dropped.

use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;

use super::{Commands, Context};
use crate::error::{Error, Result, VkContext};

/// Identifies an open span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpanId(usize);

/// One finished span.
#[derive(Clone, Debug, PartialEq)]
pub struct Span {
    /// Name given to `GpuTimer::begin`.
    pub name: String,
    /// GPU time from start stamp to end stamp in ms, barriers included; 0 if the end
    /// stamp is not after the start.
    pub milliseconds: f64,
}

/// A timestamp pool holding up to `capacity` spans per recording.
pub struct GpuTimer {
    pool: vk::QueryPool,
    capacity: u32,
    /// The spans opened since `reset`, in query order (a lock so that spans open
    /// through a shared timer).
    names: Mutex<Vec<String>>,
    period_ns: f64,
    ctx: Arc<Context>,
}

impl GpuTimer {
    /// Creates a timestamp query pool of two queries per span for `capacity` spans (at
    /// least one), debug-named `name`; ticks convert with the device's timestamp period.
    pub fn new(ctx: &Arc<Context>, name: &str, capacity: u32) -> Result<Self> {
        let capacity = capacity.max(1);
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(capacity * 2);
        // SAFETY: valid device; timestamps were checked at device choice.
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
        ctx.name(pool, name);
        Ok(Self {
            pool,
            capacity,
            names: Mutex::new(Vec::new()),
            period_ns: f64::from(ctx.info().timestamp_period_ns),
            ctx: ctx.clone(),
        })
    }

    fn names(&self) -> MutexGuard<'_, Vec<String>> {
        match self.names.lock() {
            Ok(n) => n,
            // The list is pushed to or cleared whole; a panic leaves it usable.
            Err(poisoned) => poisoned.into_inner(),
        }
    }

    /// Forgets earlier spans and resets the queries; record before the first span.
    pub fn reset(&mut self, cmd: &Commands<'_>) {
        self.names().clear();
        // SAFETY: `cmd` is recording outside a rendering scope; the range is the pool's.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(cmd.raw, self.pool, 0, self.capacity * 2)
        };
    }

    /// Records `record` as the span `name`: the span ends after it unless it fails
    /// (the recording is then abandoned).
    pub fn span<T>(
        &self,
        cmd: &Commands<'_>,
        name: &str,
        record: impl FnOnce(&Commands<'_>) -> Result<T>,
    ) -> Result<T> {
        let span = self.begin(cmd, name)?;
        let value = record(cmd)?;
        self.end(cmd, span);
        Ok(value)
    }

    /// Opens the span `name`, which ends when the returned scope is dropped (outside
    /// any rendering scope, like its start).
    pub fn scope<'t, 'c>(&'t self, cmd: &'t Commands<'c>, name: &str) -> Result<SpanScope<'t, 'c>> {
        Ok(SpanScope {
            id: self.begin(cmd, name)?,
            timer: self,
            cmd,
        })
    }

    /// Opens a span: start stamp, then a full barrier (see the module comment). Close
    /// it with [`GpuTimer::end`]; [`GpuTimer::span`] and [`GpuTimer::scope`] pair the
    /// two.
    pub fn begin(&self, cmd: &Commands<'_>, name: &str) -> Result<SpanId> {
        let index = {
            let mut names = self.names();
            let index = names.len();
            if index as u32 >= self.capacity {
                return Err(Error::internal(
                    "GPU timer",
                    format!("more than {} spans in one recording", self.capacity),
                ));
            }
            names.push(name.to_owned());
            index
        };
        // SAFETY: the query was reset in this command buffer and is written once.
        unsafe {
            self.ctx.device.cmd_write_timestamp2(
                cmd.raw,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                index as u32 * 2,
            )
        };
        cmd.full_barrier();
        Ok(SpanId(index))
    }

    /// Closes a span: a full barrier, then the end stamp.
    pub fn end(&self, cmd: &Commands<'_>, span: SpanId) {
        cmd.full_barrier();
        // SAFETY: as in `begin`; the end query of this span is written once.
        unsafe {
            self.ctx.device.cmd_write_timestamp2(
                cmd.raw,
                vk::PipelineStageFlags2::ALL_COMMANDS,
                self.pool,
                span.0 as u32 * 2 + 1,
            )
        };
    }

    /// The spans of the last recording (after its submission finished).
    pub fn read(&self) -> Result<Vec<Span>> {
        let names = self.names().clone();
        if names.is_empty() {
            return Ok(Vec::new());
        }
        let mut stamps = vec![0u64; names.len() * 2];
        // SAFETY: every query in the range was written by a completed submission.
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                0,
                &mut stamps,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .vk("vkGetQueryPoolResults (timestamps)")?;
        Ok(names
            .iter()
            .enumerate()
            .map(|(i, name)| Span {
                name: name.clone(),
                milliseconds: stamps[2 * i + 1].saturating_sub(stamps[2 * i]) as f64
                    * self.period_ns
                    / 1e6,
            })
            .collect())
    }
}

/// An open span of a [`GpuTimer`] ([`GpuTimer::scope`]): dropping it ends the span.
pub struct SpanScope<'t, 'c> {
    id: SpanId,
    timer: &'t GpuTimer,
    cmd: &'t Commands<'c>,
}

impl Drop for SpanScope<'_, '_> {
    fn drop(&mut self) {
        self.timer.end(self.cmd, self.id);
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        // SAFETY: no submission using the pool is pending.
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}

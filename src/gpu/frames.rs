//! Frames in flight: a window's frames are submitted without waiting, each into one of
//! a few slots, every slot with its own command buffer (allocated once and re-recorded),
//! fence and acquire semaphore. A slot is reused only once its last frame finished, so
//! the host runs at most `slots` frames ahead of the GPU. Headless work keeps
//! `Context::submit_and_wait`.

use std::sync::Arc;

use ash::vk;

use super::{Commands, Context};
use crate::error::{Result, VkContext};

/// One slot: its command buffer, the fence its submission signals, and the semaphore
/// a swapchain acquire signals for it.
struct Slot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    /// Submitted and not yet waited for.
    pending: bool,
}

/// A ring of frame slots (see the module comment).
pub struct FramesInFlight {
    slots: Vec<Slot>,
    /// The slot the next frame takes.
    next: usize,
    pool: vk::CommandPool,
    ctx: Arc<Context>,
}

impl FramesInFlight {
    /// `count` slots (at least one), named `name` for debugging.
    pub fn new(ctx: &Arc<Context>, name: &str, count: usize) -> Result<Self> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { ctx.device.create_command_pool(&info, None) }.vk("vkCreateCommandPool")?;
        ctx.name(pool, &format!("{name} command pool"));
        let mut frames = Self {
            slots: Vec::new(),
            next: 0,
            pool,
            ctx: ctx.clone(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count.max(1) as u32);
        // SAFETY: the pool belongs to this device and is used by this thread only.
        let buffers = unsafe { ctx.device.allocate_command_buffers(&alloc) }
            .vk("vkAllocateCommandBuffers")?;
        for (i, cmd) in buffers.into_iter().enumerate() {
            ctx.name(cmd, &format!("{name} {i}"));
            // SAFETY: valid device; the fence starts unsignalled and unsubmitted.
            let fence = unsafe {
                ctx.device
                    .create_fence(&vk::FenceCreateInfo::default(), None)
            }
            .vk("vkCreateFence")?;
            // Pushed at once so that Drop destroys what was made if the next call fails.
            frames.slots.push(Slot {
                cmd,
                fence,
                acquired: vk::Semaphore::null(),
                pending: false,
            });
            // SAFETY: valid device.
            let acquired = unsafe {
                ctx.device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            }
            .vk("vkCreateSemaphore")?;
            if let Some(slot) = frames.slots.last_mut() {
                slot.acquired = acquired;
            }
        }
        Ok(frames)
    }

    /// The slot the next frame records into, once the frame that last used it has
    /// finished (its command buffer, semaphore and anything it read are free).
    pub fn next_slot(&mut self) -> Result<usize> {
        let slot = self.next;
        self.wait(slot)?;
        self.next = (slot + 1) % self.slots.len();
        Ok(slot)
    }

    /// The slot of the frame submitted last, if it may still be running.
    pub fn last_pending(&self) -> Option<usize> {
        let last = (self.next + self.slots.len() - 1) % self.slots.len();
        self.slots[last].pending.then_some(last)
    }

    /// Waits for the frame last submitted in `slot` (nothing if none is pending).
    pub fn wait(&mut self, slot: usize) -> Result<()> {
        let Some(s) = self.slots.get_mut(slot) else {
            return Ok(());
        };
        if !s.pending {
            return Ok(());
        }
        // SAFETY: the fence was submitted with the slot's last frame.
        unsafe { self.ctx.device.wait_for_fences(&[s.fence], true, u64::MAX) }
            .vk("vkWaitForFences")?;
        // SAFETY: the fence is signalled and no submission uses it.
        unsafe { self.ctx.device.reset_fences(&[s.fence]) }.vk("vkResetFences")?;
        s.pending = false;
        Ok(())
    }

    /// Waits for every frame submitted so far.
    pub fn wait_all(&mut self) -> Result<()> {
        (0..self.slots.len()).try_for_each(|slot| self.wait(slot))
    }

    /// The semaphore a swapchain acquire signals for `slot`'s frame.
    pub(crate) fn acquired(&self, slot: usize) -> vk::Semaphore {
        self.slots
            .get(slot)
            .map_or(vk::Semaphore::null(), |s| s.acquired)
    }

    /// Records `slot`'s command buffer with `record` and submits it, waiting on
    /// `waits` (each at its stage) and signalling `signals` and the slot's fence;
    /// returns without waiting for it. The slot comes from `next_slot`.
    pub(crate) fn submit(
        &mut self,
        slot: usize,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
        record: impl FnOnce(&Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        let Some(s) = self.slots.get_mut(slot) else {
            return Err(crate::error::Error::internal(
                "frames in flight",
                format!("slot {slot} of {}", self.slots.len()),
            ));
        };
        let ctx = &self.ctx;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the slot's last submission has finished (`next_slot` waited for it),
        // and its pool allows resetting a buffer by beginning it again.
        unsafe { ctx.device.begin_command_buffer(s.cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        record(&Commands { ctx, raw: s.cmd })?;
        // SAFETY: recording began above.
        unsafe { ctx.device.end_command_buffer(s.cmd) }.vk("vkEndCommandBuffer")?;
        let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(s.cmd)];
        let wait_info: Vec<vk::SemaphoreSubmitInfo<'_>> = waits
            .iter()
            .map(|&(semaphore, stage)| {
                vk::SemaphoreSubmitInfo::default()
                    .semaphore(semaphore)
                    .stage_mask(stage)
            })
            .collect();
        let signal_info: Vec<vk::SemaphoreSubmitInfo<'_>> = signals
            .iter()
            .map(|&semaphore| {
                vk::SemaphoreSubmitInfo::default()
                    .semaphore(semaphore)
                    .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            })
            .collect();
        let submit = [vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait_info)
            .command_buffer_infos(&cmd_info)
            .signal_semaphore_infos(&signal_info)];
        // SAFETY: the command buffer is fully recorded and the fence unsignalled and
        // not in use (reset when it was last waited for).
        unsafe { ctx.device.queue_submit2(ctx.queue, &submit, s.fence) }.vk("vkQueueSubmit2")?;
        s.pending = true;
        Ok(())
    }
}

impl Drop for FramesInFlight {
    fn drop(&mut self) {
        // A frame still running reads the slots' buffers; a failed wait leaves only
        // the device idle wait below to rely on.
        let _ = self.wait_all();
        // SAFETY: no submission of the slots is pending any more (waited above, and
        // the device is idle); the pool frees its command buffers.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            for s in &self.slots {
                self.ctx.device.destroy_fence(s.fence, None);
                self.ctx.device.destroy_semaphore(s.acquired, None);
            }
            self.ctx.device.destroy_command_pool(self.pool, None);
        }
    }
}

//! A layer of the frame that does not change while the camera stands still — the
//! chamber's rock while speleothems grow in front of it — drawn once for each of the
//! camera's samples into a kept target, colour and depth, and copied into the frame
//! instead of drawn again.
//!
//! Under temporal anti-aliasing a still camera cycles through the 16 sample positions
//! of `frame::temporal`, so 16 kept targets hold every frame it draws; a scene fills
//! them a few a frame (`GrowthFrame` draws the samples still missing beside the
//! frame's own). On lavapipe the rock's fragment shading runs in every pixel it covers,
//! most of the window, where a copy is a memcpy. A moving camera draws the layer into
//! the frame and keeps nothing; the pictures are the same to the byte
//! (`tests/gpu/layer_cache.rs`).

use std::sync::Arc;

use crate::error::Result;
use crate::gpu::{Commands, Context, OffscreenTarget, TargetFormat};

/// Targets kept (the temporal anti-aliasing's sample positions).
pub const SLOTS: usize = 16;

/// The most memory the kept targets may take, bytes; a larger frame draws the layer
/// every time.
pub const MAX_BYTES: u64 = 256 << 20;

struct Slot {
    /// What the layer was drawn from (its uniforms, its pipeline's options).
    key: Vec<u8>,
    layer: OffscreenTarget,
    /// When it was last drawn or copied (the least recent is drawn over).
    used: u64,
}

/// The kept layers, for one target size and format at a time.
pub struct LayerCache {
    ctx: Arc<Context>,
    slots: Vec<Slot>,
    /// The targets the slots were made for.
    made_for: Option<(u32, u32, TargetFormat)>,
    clock: u64,
}

impl LayerCache {
    /// An empty cache; targets are made as layers are kept.
    pub fn new(ctx: &Arc<Context>) -> Self {
        Self {
            ctx: ctx.clone(),
            slots: Vec::new(),
            made_for: None,
            clock: 0,
        }
    }

    /// Whether layers of `target` can be kept: single-sampled with a kept depth, and
    /// `SLOTS` targets of its size (colour and depth) within `MAX_BYTES` (1920x1080
    /// fits).
    pub fn serves(target: &OffscreenTarget) -> bool {
        let bytes = u64::from(target.width()) * u64::from(target.height()) * 8;
        target.copies_attachments() && bytes * SLOTS as u64 <= MAX_BYTES
    }

    /// Whether the layer drawn from `key` is kept (for targets like `target`).
    pub fn holds(&self, target: &OffscreenTarget, key: &[u8]) -> bool {
        self.made_for == Some(shape(target)) && self.slots.iter().any(|s| s.key == key)
    }

    /// Draws the layer of `key` into a kept target like `target` (a new one, or the
    /// least recently used): `draw(cmd, slot)` records its draws inside the kept
    /// target's open rendering scope, cleared to `clear`; `slot` (below `SLOTS`) is the
    /// same for as long as the layer stays kept (uniforms of its own can live there).
    /// Only where `serves(target)`.
    pub fn keep(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        key: &[u8],
        clear: [f32; 4],
        draw: impl FnOnce(&Commands<'_>, usize) -> Result<()>,
    ) -> Result<()> {
        if self.made_for != Some(shape(target)) {
            self.slots.clear();
            self.made_for = Some(shape(target));
        }
        let index = if self.slots.len() < SLOTS {
            self.slots.push(Slot {
                key: Vec::new(),
                layer: target.like(&self.ctx)?,
                used: 0,
            });
            self.slots.len() - 1
        } else {
            (0..self.slots.len())
                .min_by_key(|&i| self.slots[i].used)
                .unwrap_or(0)
        };
        self.clock += 1;
        let slot = &mut self.slots[index];
        slot.key.clear();
        slot.layer.begin(cmd, clear);
        draw(cmd, index)?;
        slot.layer.end(cmd);
        slot.layer.hold_for_copies(cmd);
        slot.key = key.to_vec();
        slot.used = self.clock;
        Ok(())
    }

    /// Opens `target`'s rendering scope with the kept layer of `key` copied in; false
    /// (nothing recorded) where none is kept.
    pub fn begin_from(&mut self, cmd: &Commands<'_>, target: &OffscreenTarget, key: &[u8]) -> bool {
        if self.made_for != Some(shape(target)) {
            return false;
        }
        self.clock += 1;
        let clock = self.clock;
        let Some(slot) = self.slots.iter_mut().find(|s| s.key == key) else {
            return false;
        };
        slot.used = clock;
        target.copy_attachments_from(cmd, &slot.layer);
        target.begin_loaded(cmd);
        true
    }
}

fn shape(target: &OffscreenTarget) -> (u32, u32, TargetFormat) {
    (target.width(), target.height(), target.format())
}

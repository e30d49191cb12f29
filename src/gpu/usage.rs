//! Resource state: how a pass uses an image or a buffer ([`Usage`]), and what each
//! resource remembers of its uses ([`Tracked`]), from which the barrier before the
//! next use is derived (vk-sync's idea, as kajiya uses it). Passes say what they do
//! with a resource; which stages, accesses and layouts that means, and which barrier
//! it needs after the last use, is decided here, once.
//!
//! State is kept per resource across command buffers, in recording order: sediment
//! submits what it records, in order, on one queue.

use std::sync::Mutex;

use ash::vk;

use super::{Buffer, Commands, Image};

/// How a pass is about to use an image or a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Usage {
    /// Sampled by fragment shaders (an image in SHADER_READ_ONLY_OPTIMAL).
    SampledFragment,
    /// A depth image sampled by fragment shaders (DEPTH_READ_ONLY_OPTIMAL).
    SampledDepthFragment,
    /// Drawn into as a colour attachment (read by loads and blending, written).
    ColorAttachment,
    /// The depth attachment: tested and written.
    DepthAttachment,
    /// Written by compute shaders: a storage image (GENERAL) or storage buffer.
    ComputeWrite,
    /// Read and written by compute shaders (storage).
    ComputeReadWrite,
    /// Read by compute shaders (storage, uniform or texel reads; an image in GENERAL).
    ComputeRead,
    /// The source of copies and blits.
    TransferSrc,
    /// The destination of copies, blits and fills.
    TransferDst,
    /// Read by the host once the submission has finished (a mapped buffer).
    HostRead,
}

/// One resource's use, for [`Commands::uses`], which records the barriers of several
/// in one pipeline barrier.
#[derive(Clone, Copy)]
pub struct Use<'a> {
    resource: Resource<'a>,
    usage: Usage,
    discard: bool,
}

#[derive(Clone, Copy)]
enum Resource<'a> {
    Image(&'a Image),
    Buffer(&'a Buffer),
}

impl<'a> Use<'a> {
    /// `image` used as `usage`, keeping what it holds.
    pub fn image(image: &'a Image, usage: Usage) -> Self {
        Self {
            resource: Resource::Image(image),
            usage,
            discard: false,
        }
    }

    /// `image` used as `usage` with what it held discarded: it is rewritten whole.
    pub fn image_discarding(image: &'a Image, usage: Usage) -> Self {
        Self {
            resource: Resource::Image(image),
            usage,
            discard: true,
        }
    }

    /// `buffer` used as `usage`.
    pub fn buffer(buffer: &'a Buffer, usage: Usage) -> Self {
        Self {
            resource: Resource::Buffer(buffer),
            usage,
            discard: false,
        }
    }
}

impl Commands<'_> {
    /// Records the barrier that makes each resource ready for its use after its last
    /// one (in one pipeline barrier; nothing where no use needs one), outside a
    /// rendering scope.
    pub fn uses(&self, uses: &[Use<'_>]) {
        let mut images = Vec::new();
        let mut buffers = Vec::new();
        for u in uses {
            match u.resource {
                Resource::Image(image) => {
                    if let Some(d) = image.tracked().advance(u.usage, true, u.discard) {
                        images.push((image.raw(), image.full_range(), d));
                    }
                }
                Resource::Buffer(buffer) => {
                    if let Some(d) = buffer.tracked().advance(u.usage, false, false) {
                        buffers.push((buffer.raw(), d));
                    }
                }
            }
        }
        super::barrier::dependencies(self.ctx, self.raw, &images, &buffers);
    }
}

/// Every access that writes.
const WRITES: vk::AccessFlags2 = vk::AccessFlags2::from_raw(
    vk::AccessFlags2::SHADER_WRITE.as_raw()
        | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw()
        | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
        | vk::AccessFlags2::TRANSFER_WRITE.as_raw()
        | vk::AccessFlags2::HOST_WRITE.as_raw()
        | vk::AccessFlags2::MEMORY_WRITE.as_raw(),
);

impl Usage {
    /// The layout an image needs for this use, and the stages and accesses it makes.
    pub(crate) fn scope(self) -> (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2) {
        use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
        match self {
            Usage::SampledFragment => (
                L::SHADER_READ_ONLY_OPTIMAL,
                S::FRAGMENT_SHADER,
                A::SHADER_SAMPLED_READ,
            ),
            Usage::SampledDepthFragment => (
                L::DEPTH_READ_ONLY_OPTIMAL,
                S::FRAGMENT_SHADER,
                A::SHADER_SAMPLED_READ,
            ),
            Usage::ColorAttachment => (
                L::COLOR_ATTACHMENT_OPTIMAL,
                S::COLOR_ATTACHMENT_OUTPUT,
                A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
            ),
            Usage::DepthAttachment => (
                L::DEPTH_ATTACHMENT_OPTIMAL,
                S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            Usage::ComputeWrite => (L::GENERAL, S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            Usage::ComputeReadWrite => (
                L::GENERAL,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
            ),
            Usage::ComputeRead => (
                L::GENERAL,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::UNIFORM_READ | A::SHADER_SAMPLED_READ,
            ),
            Usage::TransferSrc => (L::TRANSFER_SRC_OPTIMAL, S::ALL_TRANSFER, A::TRANSFER_READ),
            Usage::TransferDst => (L::TRANSFER_DST_OPTIMAL, S::ALL_TRANSFER, A::TRANSFER_WRITE),
            Usage::HostRead => (L::GENERAL, S::HOST, A::HOST_READ),
        }
    }
}

/// One barrier a use needs: the scopes it joins and, for an image, the layouts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Dependency {
    pub src_stages: vk::PipelineStageFlags2,
    pub src_access: vk::AccessFlags2,
    pub dst_stages: vk::PipelineStageFlags2,
    pub dst_access: vk::AccessFlags2,
    pub old_layout: vk::ImageLayout,
    pub new_layout: vk::ImageLayout,
}

/// What the uses of a resource since its last write left behind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct State {
    /// The image's layout (UNDEFINED for buffers and fresh images).
    pub layout: vk::ImageLayout,
    /// Stages of the last write (a layout transition counts as one, at the stages it
    /// was made for), and its write accesses; empty when nothing has written.
    write_stages: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    /// The stages and accesses the last write has been made visible to.
    visible_stages: vk::PipelineStageFlags2,
    visible_access: vk::AccessFlags2,
    /// Stages that read since the last write: a write waits for them.
    read_stages: vk::PipelineStageFlags2,
}

impl State {
    /// Nothing on the GPU has used the resource.
    pub const FRESH: State = State {
        layout: vk::ImageLayout::UNDEFINED,
        write_stages: vk::PipelineStageFlags2::NONE,
        write_access: vk::AccessFlags2::NONE,
        visible_stages: vk::PipelineStageFlags2::NONE,
        visible_access: vk::AccessFlags2::NONE,
        read_stages: vk::PipelineStageFlags2::NONE,
    };

    /// The barrier `usage` needs after the uses this state records (none where it
    /// needs none), and the state after it. `image`: layouts count; `discard`: the
    /// contents before are not needed (an image's layout then starts UNDEFINED).
    pub fn next(self, usage: Usage, image: bool, discard: bool) -> (Option<Dependency>, State) {
        let (layout, stages, access) = usage.scope();
        let layout = if image {
            layout
        } else {
            vk::ImageLayout::UNDEFINED
        };
        let transition = image && layout != self.layout;
        let writes = access.intersects(WRITES) || transition;
        if writes {
            let src_stages = self.write_stages | self.read_stages;
            let barrier = (transition || !src_stages.is_empty()).then_some(Dependency {
                src_stages,
                src_access: self.write_access,
                dst_stages: stages,
                dst_access: access,
                old_layout: if discard {
                    vk::ImageLayout::UNDEFINED
                } else {
                    self.layout
                },
                new_layout: layout,
            });
            let after = State {
                layout,
                write_stages: stages,
                write_access: access & WRITES,
                visible_stages: stages,
                visible_access: access,
                read_stages: if (access & !WRITES).is_empty() {
                    vk::PipelineStageFlags2::NONE
                } else {
                    stages
                },
            };
            return (barrier, after);
        }
        let seen = self.visible_stages.contains(stages) && self.visible_access.contains(access);
        let barrier = (!self.write_stages.is_empty() && !seen).then_some(Dependency {
            src_stages: self.write_stages,
            src_access: self.write_access,
            dst_stages: stages,
            dst_access: access,
            old_layout: layout,
            new_layout: layout,
        });
        let mut after = self;
        if barrier.is_some() {
            after.visible_stages |= stages;
            after.visible_access |= access;
        }
        after.read_stages |= stages;
        (barrier, after)
    }
}

/// A resource's [`State`], shared by every command buffer that records its uses.
#[derive(Debug)]
pub(crate) struct Tracked(Mutex<State>);

impl Tracked {
    pub fn new() -> Self {
        Self(Mutex::new(State::FRESH))
    }

    /// Moves to the state after `usage` and returns the barrier that needs.
    pub fn advance(&self, usage: Usage, image: bool, discard: bool) -> Option<Dependency> {
        let mut state = match self.0.lock() {
            Ok(s) => s,
            // A state is replaced whole, never left half-written by a panic.
            Err(poisoned) => poisoned.into_inner(),
        };
        let (barrier, after) = state.next(usage, image, discard);
        *state = after;
        barrier
    }

    /// Records that barriers placed per mip level or layer (an upload, a mip chain)
    /// left the whole image as a barrier into `usage` would have.
    pub fn set_image(&self, usage: Usage) {
        let (_, after) = State::FRESH.next(usage, true, true);
        match self.0.lock() {
            Ok(mut s) => *s = after,
            Err(poisoned) => *poisoned.into_inner() = after,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};

    fn run(uses: &[(Usage, bool)], image: bool) -> Vec<Option<Dependency>> {
        let mut state = State::FRESH;
        uses.iter()
            .map(|&(usage, discard)| {
                let (barrier, after) = state.next(usage, image, discard);
                state = after;
                barrier
            })
            .collect()
    }

    #[test]
    fn a_fresh_buffer_written_needs_no_barrier_and_its_reader_waits_for_the_write() {
        let barriers = run(
            &[(Usage::ComputeWrite, false), (Usage::HostRead, false)],
            false,
        );
        assert_eq!(barriers[0], None);
        let b = barriers[1].expect("host read after a shader write");
        assert_eq!(
            (b.src_stages, b.src_access, b.dst_stages, b.dst_access),
            (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_WRITE,
                S::HOST,
                A::HOST_READ
            )
        );
    }

    #[test]
    fn reads_after_a_visible_write_need_nothing_and_a_write_waits_for_every_reader() {
        let barriers = run(
            &[
                (Usage::ColorAttachment, true),
                (Usage::SampledFragment, false),
                (Usage::SampledFragment, false),
                (Usage::ColorAttachment, true),
            ],
            true,
        );
        let first = barriers[0].expect("undefined to attachment");
        assert_eq!(
            (first.old_layout, first.src_stages),
            (L::UNDEFINED, S::NONE)
        );
        let read = barriers[1].expect("attachment to sampled");
        assert_eq!(
            (read.old_layout, read.new_layout, read.src_access),
            (
                L::COLOR_ATTACHMENT_OPTIMAL,
                L::SHADER_READ_ONLY_OPTIMAL,
                A::COLOR_ATTACHMENT_WRITE
            )
        );
        assert_eq!(barriers[2], None, "a second read of a visible write");
        let again = barriers[3].expect("rewritten after reads");
        assert_eq!(
            (again.old_layout, again.src_stages),
            (L::UNDEFINED, S::FRAGMENT_SHADER)
        );
    }

    #[test]
    fn a_read_in_a_new_stage_waits_for_the_write_once() {
        let barriers = run(
            &[
                (Usage::ComputeWrite, false),
                (Usage::ComputeRead, false),
                (Usage::TransferSrc, false),
                (Usage::TransferSrc, false),
                (Usage::ComputeRead, false),
            ],
            false,
        );
        assert_eq!(barriers[0], None);
        assert!(barriers[1].is_some());
        let copy = barriers[2].expect("a copy reads what the shader wrote");
        assert_eq!(
            (copy.src_stages, copy.dst_stages),
            (S::COMPUTE_SHADER, S::ALL_TRANSFER)
        );
        assert_eq!(barriers[3], None);
        assert_eq!(barriers[4], None);
    }

    #[test]
    fn a_write_after_writes_waits_for_them() {
        let barriers = run(
            &[
                (Usage::ComputeReadWrite, false),
                (Usage::ComputeReadWrite, false),
            ],
            false,
        );
        let b = barriers[1].expect("write after write");
        assert_eq!(
            (b.src_stages, b.src_access, b.dst_access),
            (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_WRITE,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE
            )
        );
    }

    #[test]
    fn a_kept_image_changes_layout_from_the_one_it_is_in() {
        let barriers = run(
            &[
                (Usage::TransferDst, true),
                (Usage::TransferSrc, false),
                (Usage::SampledFragment, false),
            ],
            true,
        );
        let b = barriers[2].expect("to sampled");
        assert_eq!(
            (b.old_layout, b.src_stages),
            (L::TRANSFER_SRC_OPTIMAL, S::ALL_TRANSFER)
        );
    }
}

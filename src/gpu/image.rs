//! 2D images with one view: a plain-data description and an owning wrapper.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use super::Context;
use crate::error::{Error, Result, VkContext};

/// What a 2D image is: size, format, mip levels and usage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ImageDesc {
    /// Width of mip level 0 in texels (1 up to the device's `maxImageDimension2D`).
    pub width: u32,
    /// Height of mip level 0 in texels (1 up to the device's `maxImageDimension2D`).
    pub height: u32,
    /// Texel format of the image and of its view.
    pub format: vk::Format,
    /// Number of mip levels, level `k` being `max(1, size >> k)` per side.
    pub mip_levels: u32,
    /// Every way the image will be used (sampled, attachment, transfer...).
    pub usage: vk::ImageUsageFlags,
    /// Samples per texel (multisampled attachments).
    pub samples: vk::SampleCountFlags,
    /// Six layers seen as a cube (an environment map), else one 2D layer.
    pub cube: bool,
}

impl ImageDesc {
    /// One 2D layer of `width` x `height` texels, one mip level, one sample.
    pub fn new_2d(width: u32, height: u32, format: vk::Format, usage: vk::ImageUsageFlags) -> Self {
        Self {
            width,
            height,
            format,
            mip_levels: 1,
            usage,
            samples: vk::SampleCountFlags::TYPE_1,
            cube: false,
        }
    }

    /// A cube map of `size`² faces (six layers, viewed as a cube).
    pub fn new_cube(size: u32, format: vk::Format, usage: vk::ImageUsageFlags) -> Self {
        Self {
            cube: true,
            ..Self::new_2d(size, size, format, usage)
        }
    }

    /// Array layers: six for a cube.
    pub fn layers(&self) -> u32 {
        if self.cube { 6 } else { 1 }
    }

    /// Sets the number of mip levels; the caller keeps it within the full chain.
    pub fn mip_levels(mut self, levels: u32) -> Self {
        self.mip_levels = levels;
        self
    }

    /// Sets the samples per texel (above one only for multisampled attachments).
    pub fn samples(mut self, samples: vk::SampleCountFlags) -> Self {
        self.samples = samples;
        self
    }

    /// The aspect the single view covers.
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        match self.format {
            vk::Format::D16_UNORM | vk::Format::D32_SFLOAT | vk::Format::X8_D24_UNORM_PACK32 => {
                vk::ImageAspectFlags::DEPTH
            }
            vk::Format::D24_UNORM_S8_UINT | vk::Format::D32_SFLOAT_S8_UINT => {
                vk::ImageAspectFlags::DEPTH
            }
            _ => vk::ImageAspectFlags::COLOR,
        }
    }
}

/// An owned device-local `VkImage`, its memory and one view of all its mip levels.
pub struct Image {
    /// The layout and accesses its last use left (see `Image::use_as`).
    state: super::usage::Tracked,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    raw: vk::Image,
    desc: ImageDesc,
    ctx: Arc<Context>,
}

impl Image {
    /// Creates an optimal-tiling image of `desc` in device-local memory, in layout
    /// UNDEFINED, with one 2D (or cube) view of all levels and layers; a side of 0 or
    /// above the device's limit is an error.
    pub fn new(ctx: &Arc<Context>, name: &str, desc: ImageDesc) -> Result<Self> {
        let max = ctx.info().max_image_dimension_2d;
        if desc.width == 0 || desc.height == 0 || desc.width > max || desc.height > max {
            return Err(Error::invalid(
                format!("image \"{name}\" size"),
                format!(
                    "{}x{} is outside 1..={max} per side on this device",
                    desc.width, desc.height
                ),
            ));
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(desc.layers())
            .flags(if desc.cube {
                vk::ImageCreateFlags::CUBE_COMPATIBLE
            } else {
                vk::ImageCreateFlags::empty()
            })
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device.create_image(&info, None) }.vk("vkCreateImage")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { ctx.device.get_image_memory_requirements(raw) };
        let allocation = match ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        }) {
            Ok(a) => a,
            Err(source) => {
                // SAFETY: no memory bound, no other user.
                unsafe { ctx.device.destroy_image(raw, None) };
                return Err(Error::Allocation {
                    name: name.to_owned(),
                    bytes: requirements.size,
                    source,
                });
            }
        };
        let mut image = Image {
            state: super::usage::Tracked::new(),
            view: vk::ImageView::null(),
            allocation: Some(allocation),
            raw,
            desc,
            ctx: ctx.clone(),
        };
        let allocation = image.allocation.as_ref().map(|a| {
            // SAFETY: the allocation is freed only after the image is destroyed.
            (unsafe { a.memory() }, a.offset())
        });
        if let Some((memory, offset)) = allocation {
            // SAFETY: the allocation satisfies the image's requirements.
            unsafe { ctx.device.bind_image_memory(raw, memory, offset) }.vk("vkBindImageMemory")?;
        }
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(if desc.cube {
                vk::ImageViewType::CUBE
            } else {
                vk::ImageViewType::TYPE_2D
            })
            .format(desc.format)
            .subresource_range(image.full_range());
        // SAFETY: the image is bound to memory and the range is within it.
        image.view =
            unsafe { ctx.device.create_image_view(&view_info, None) }.vk("vkCreateImageView")?;
        ctx.name(raw, name);
        ctx.name(image.view, &format!("{name} view"));
        Ok(image)
    }

    /// A sampled RGBA8 (UNORM) texture filled with `rgba` (row-major, 4 bytes per
    /// texel), left in SHADER_READ_ONLY_OPTIMAL; with `mips`, a full blitted mip chain.
    pub fn upload_rgba8(
        ctx: &Arc<Context>,
        name: &str,
        width: u32,
        height: u32,
        rgba: &[u8],
        mips: bool,
    ) -> Result<Self> {
        let expected = width as usize * height as usize * 4;
        if rgba.len() != expected {
            return Err(Error::internal(
                format!("texture \"{name}\""),
                format!(
                    "{} bytes given for {width}x{height} RGBA8 ({expected})",
                    rgba.len()
                ),
            ));
        }
        let staging = super::Buffer::with_data(
            ctx,
            &format!("{name} staging"),
            vk::BufferUsageFlags::TRANSFER_SRC,
            rgba,
        )?;
        Self::sampled_from_buffer_with_mips(
            ctx,
            name,
            ImageDesc::new_2d(
                width,
                height,
                vk::Format::R8G8B8A8_UNORM,
                vk::ImageUsageFlags::SAMPLED,
            ),
            &staging,
            &[0],
            mips,
        )
    }

    /// A sampled texture whose mip level `k` is copied from `buffer` at byte offset
    /// `level_offsets[k]` (tightly packed rows), left in SHADER_READ_ONLY_OPTIMAL. The
    /// buffer needs TRANSFER_SRC usage. With `blit_mips`, levels after the given ones
    /// down to 1x1 are made by linear blits (a box filter: fine for maps whose mips
    /// need no special rule; the ripple normal chain is built by sediment instead).
    pub fn sampled_from_buffer(
        ctx: &Arc<Context>,
        name: &str,
        desc: ImageDesc,
        buffer: &super::Buffer,
        level_offsets: &[u64],
    ) -> Result<Self> {
        Self::sampled_from_buffer_with_mips(ctx, name, desc, buffer, level_offsets, false)
    }

    /// `sampled_from_buffer`, optionally completing the mip chain with blits.
    pub fn sampled_from_buffer_with_mips(
        ctx: &Arc<Context>,
        name: &str,
        desc: ImageDesc,
        buffer: &super::Buffer,
        level_offsets: &[u64],
        blit_mips: bool,
    ) -> Result<Self> {
        let given = level_offsets.len().max(1) as u32;
        let full = 32 - desc.width.max(desc.height).leading_zeros();
        let desc = ImageDesc {
            mip_levels: if blit_mips { full.max(given) } else { given },
            usage: desc.usage
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::TRANSFER_SRC,
            ..desc
        };
        let image = Image::new(ctx, name, desc)?;
        let range = image.full_range();
        let regions: Vec<vk::BufferImageCopy> = level_offsets
            .iter()
            .enumerate()
            .map(|(k, &offset)| {
                let mut r = color_copy_region((desc.width >> k).max(1), (desc.height >> k).max(1));
                r.buffer_offset = offset;
                r.image_subresource.mip_level = k as u32;
                r
            })
            .collect();
        ctx.submit_and_wait(&format!("upload {name}"), |cmd| {
            super::barrier::images(
                ctx,
                cmd.raw,
                &[super::barrier::ImageTransition::discard_to_transfer_dst(
                    image.raw, range,
                )],
            );
            // Writes of earlier submissions to the buffer (compute passes) are visible.
            cmd.full_barrier();
            // SAFETY: the image is in TRANSFER_DST_OPTIMAL; each region lies inside the
            // buffer (validation checks it in tests) and inside its mip level.
            unsafe {
                ctx.device.cmd_copy_buffer_to_image(
                    cmd.raw,
                    buffer.raw(),
                    image.raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &regions,
                )
            };
            image.record_mips(cmd, given);
            Ok(())
        })?;
        Ok(image)
    }

    /// Records the rest of the mip chain and the hand-over to shaders: levels
    /// `0..given` of every layer are in TRANSFER_DST (copied); each later level is a
    /// linear blit (a box filter) of the one before, which becomes a TRANSFER_SRC
    /// first; then every level goes to SHADER_READ_ONLY_OPTIMAL from the layout it is
    /// in (`layouts_after_copies_and_blits`).
    pub(crate) fn record_mips(&self, cmd: &super::Commands<'_>, given: u32) {
        let (desc, range) = (&self.desc, self.full_range());
        let level_range = |k: u32| vk::ImageSubresourceRange {
            base_mip_level: k,
            level_count: 1,
            ..range
        };
        if desc.mip_levels > given {
            // The levels to be blitted, whatever they held, become destinations.
            super::barrier::images(
                cmd.ctx,
                cmd.raw,
                &[super::barrier::ImageTransition::discard_to_transfer_dst(
                    self.raw,
                    vk::ImageSubresourceRange {
                        base_mip_level: given,
                        level_count: desc.mip_levels - given,
                        ..range
                    },
                )],
            );
        }
        for k in given..desc.mip_levels {
            // Level k-1 becomes a blit source.
            super::barrier::images(
                cmd.ctx,
                cmd.raw,
                &[super::barrier::ImageTransition {
                    image: self.raw,
                    range: level_range(k - 1),
                    from: (
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        vk::PipelineStageFlags2::ALL_TRANSFER,
                        vk::AccessFlags2::TRANSFER_WRITE,
                    ),
                    to: (
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        vk::PipelineStageFlags2::ALL_TRANSFER,
                        vk::AccessFlags2::TRANSFER_READ,
                    ),
                }],
            );
            let extent = |k: u32| vk::Offset3D {
                x: (desc.width >> k).max(1) as i32,
                y: (desc.height >> k).max(1) as i32,
                z: 1,
            };
            let layers = |k: u32| vk::ImageSubresourceLayers {
                aspect_mask: range.aspect_mask,
                mip_level: k,
                base_array_layer: 0,
                layer_count: desc.layers(),
            };
            let blit = [vk::ImageBlit {
                src_subresource: layers(k - 1),
                src_offsets: [vk::Offset3D::default(), extent(k - 1)],
                dst_subresource: layers(k),
                dst_offsets: [vk::Offset3D::default(), extent(k)],
            }];
            // SAFETY: level k-1 is in TRANSFER_SRC and level k in TRANSFER_DST; the
            // format supports linear blits (checked by validation in tests).
            unsafe {
                cmd.ctx.device.cmd_blit_image(
                    cmd.raw,
                    self.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    self.raw,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &blit,
                    vk::Filter::LINEAR,
                )
            };
        }
        // Every level to shader reads, from the layout the copies and blits left it in.
        let to_read = (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        );
        let transitions: Vec<super::barrier::ImageTransition> =
            layouts_after_copies_and_blits(given, desc.mip_levels)
                .into_iter()
                .map(|(base, count, layout)| super::barrier::ImageTransition {
                    image: self.raw,
                    range: vk::ImageSubresourceRange {
                        base_mip_level: base,
                        level_count: count,
                        ..range
                    },
                    from: if layout == vk::ImageLayout::TRANSFER_SRC_OPTIMAL {
                        (
                            layout,
                            vk::PipelineStageFlags2::ALL_TRANSFER,
                            vk::AccessFlags2::TRANSFER_READ,
                        )
                    } else {
                        (
                            layout,
                            vk::PipelineStageFlags2::ALL_TRANSFER,
                            vk::AccessFlags2::TRANSFER_WRITE,
                        )
                    },
                    to: to_read,
                })
                .collect();
        super::barrier::images(cmd.ctx, cmd.raw, &transitions);
        self.state.set_image(super::Usage::SampledFragment);
    }

    /// Reads mip level `level` of a sampled RGBA8 image back (tightly packed rows),
    /// leaving it in SHADER_READ_ONLY_OPTIMAL as `sampled_from_buffer` made it. The
    /// image needs TRANSFER_SRC usage. Submits its own copy and waits.
    pub fn read_level(&self, ctx: &Arc<Context>, level: u32) -> Result<Vec<u8>> {
        if level >= self.desc.mip_levels {
            return Err(Error::internal(
                "image readback",
                format!("level {level} of a {}-level image", self.desc.mip_levels),
            ));
        }
        let (w, h) = (
            (self.desc.width >> level).max(1),
            (self.desc.height >> level).max(1),
        );
        let bytes = u64::from(w) * u64::from(h) * 4;
        let readback = super::Buffer::new(
            ctx,
            "image level readback",
            super::BufferDesc::readback(bytes, vk::BufferUsageFlags::TRANSFER_DST),
        )?;
        let range = vk::ImageSubresourceRange {
            base_mip_level: level,
            level_count: 1,
            ..self.full_range()
        };
        let sampled = (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        );
        let source = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        );
        ctx.submit_and_wait("read image level", |cmd| {
            let transition = |from, to| super::barrier::ImageTransition {
                image: self.raw,
                range,
                from,
                to,
            };
            super::barrier::images(ctx, cmd.raw, &[transition(sampled, source)]);
            let mut region = color_copy_region(w, h);
            region.image_subresource.mip_level = level;
            // SAFETY: the level is in TRANSFER_SRC_OPTIMAL and the buffer holds it.
            unsafe {
                ctx.device.cmd_copy_image_to_buffer(
                    cmd.raw,
                    self.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.raw(),
                    &[region],
                )
            };
            super::barrier::images(ctx, cmd.raw, &[transition(source, sampled)]);
            cmd.transfer_to_host_barrier();
            Ok(())
        })?;
        Ok(readback.mapped()?.to_vec())
    }

    /// Records the barrier that makes the image ready for `usage` after its last use
    /// (layout, stages and accesses; nothing where none is needed), outside a
    /// rendering scope. Every use of a tracked image goes through here or
    /// [`Commands::uses`](super::Commands::uses).
    pub fn use_as(&self, cmd: &super::Commands<'_>, usage: super::Usage) {
        cmd.uses(&[super::Use::image(self, usage)]);
    }

    /// [`Image::use_as`] where the image is rewritten whole: what it held is discarded.
    pub fn discard_as(&self, cmd: &super::Commands<'_>, usage: super::Usage) {
        cmd.uses(&[super::Use::image_discarding(self, usage)]);
    }

    pub(crate) fn tracked(&self) -> &super::usage::Tracked {
        &self.state
    }

    /// Makes `range` ready for `usage` with what it held discarded, waiting for the
    /// whole image's last use; the whole image is then tracked as in `usage` (the
    /// caller brings the rest there too, as `record_mips` does).
    pub(crate) fn discard_range_as(
        &self,
        cmd: &super::Commands<'_>,
        range: vk::ImageSubresourceRange,
        usage: super::Usage,
    ) {
        let (layout, stages, access) = usage.scope();
        let dependency =
            self.state
                .advance(usage, true, true)
                .unwrap_or(super::usage::Dependency {
                    src_stages: vk::PipelineStageFlags2::NONE,
                    src_access: vk::AccessFlags2::NONE,
                    dst_stages: stages,
                    dst_access: access,
                    old_layout: vk::ImageLayout::UNDEFINED,
                    new_layout: layout,
                });
        super::barrier::dependencies(cmd.ctx, cmd.raw, &[(self.raw, range, dependency)], &[]);
    }

    /// The `VkImage` handle; destroyed with `self`.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }

    /// The view of every level and layer (2D or cube); destroyed with `self`.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// The description the image was created from (after any usage or mip additions).
    pub fn desc(&self) -> &ImageDesc {
        &self.desc
    }

    /// Every mip level of the image's aspect.
    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.desc.aspect(),
            base_mip_level: 0,
            level_count: self.desc.mip_levels,
            base_array_layer: 0,
            layer_count: self.desc.layers(),
        }
    }
}

/// The layout each mip level is left in by `sampled_from_buffer_with_mips`, as runs
/// (first level, count, layout): the `given` levels are copied (TRANSFER_DST); each
/// level after them is blitted from the one before, which becomes a TRANSFER_SRC
/// first — so levels `given - 1 .. levels - 1` end as sources and the last as a
/// destination, while the given levels before `given - 1` stay destinations.
fn layouts_after_copies_and_blits(given: u32, levels: u32) -> Vec<(u32, u32, vk::ImageLayout)> {
    let (dst, src) = (
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    if levels <= given {
        return vec![(0, levels, dst)];
    }
    let mut runs = vec![
        (0, given - 1, dst),
        (given - 1, levels - given, src),
        (levels - 1, 1, dst),
    ];
    runs.retain(|r| r.1 > 0);
    runs
}

/// A copy of mip level 0 of a whole colour image to or from a tightly packed buffer.
pub(crate) fn color_copy_region(width: u32, height: u32) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset: 0,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_offset: vk::Offset3D::default(),
        image_extent: vk::Extent3D {
            width,
            height,
            depth: 1,
        },
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: both belong to this device and the GPU is done with them; destroying a
        // null view is a no-op.
        unsafe {
            self.ctx.device.destroy_image_view(self.view, None);
            self.ctx.device.destroy_image(self.raw, None);
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = self.ctx.allocator().free(allocation);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replays the layouts the upload records (all levels to TRANSFER_DST, then each
    /// blit's source level to TRANSFER_SRC) and checks the final barrier starts every
    /// level from the layout it is in, exactly once.
    #[test]
    fn the_final_barrier_starts_each_level_from_its_recorded_layout() {
        for levels in 1..=9u32 {
            for given in 1..=levels {
                let mut recorded = vec![vk::ImageLayout::TRANSFER_DST_OPTIMAL; levels as usize];
                for k in given..levels {
                    recorded[k as usize - 1] = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                }
                let mut declared = vec![None; levels as usize];
                for (base, count, layout) in layouts_after_copies_and_blits(given, levels) {
                    for level in base..base + count {
                        assert!(declared[level as usize].is_none(), "level {level} twice");
                        declared[level as usize] = Some(layout);
                    }
                }
                let declared: Vec<_> = declared
                    .into_iter()
                    .map(|d| d.expect("every level"))
                    .collect();
                assert_eq!(declared, recorded, "{given} given of {levels} levels");
            }
        }
    }
}

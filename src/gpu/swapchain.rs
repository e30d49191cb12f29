//! Presenting to a window: the Vulkan surface of a window, the swapchain (recreated when
//! the window changes size), and a frame's copy of the offscreen target into a
//! swapchain image with an overlay panel on top. The scene passes never see any of
//! this: they draw into the same `OffscreenTarget` as the headless commands.

use std::sync::Arc;

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::barrier::{self, ImageTransition};
use super::{Buffer, Commands, Context, FramesInFlight, OffscreenTarget};
use crate::error::{Error, Result, VkContext};

/// The Vulkan surface of one window.
pub struct Surface {
    loader: ash::khr::surface::Instance,
    raw: vk::SurfaceKHR,
    // The instance the surface belongs to outlives it.
    _ctx: Arc<Context>,
}

impl Surface {
    /// # Safety
    /// The handles must belong to a live window that outlives the surface.
    pub unsafe fn new(
        ctx: &Arc<Context>,
        display: RawDisplayHandle,
        window: RawWindowHandle,
    ) -> Result<Self> {
        // SAFETY: the caller guarantees the handles are live; the instance was created
        // with the display's surface extensions (`ContextOptions::window`).
        let raw =
            unsafe { ash_window::create_surface(&ctx.entry, &ctx.instance, display, window, None) }
                .map_err(|r| Error::NoWindow {
                    detail: format!("vkCreate*SurfaceKHR failed ({r})"),
                })?;
        let loader = ash::khr::surface::Instance::new(&ctx.entry, &ctx.instance);
        let surface = Self {
            loader,
            raw,
            _ctx: ctx.clone(),
        };
        // SAFETY: the surface and the physical device belong to this instance.
        let supported = unsafe {
            surface
                .loader
                .get_physical_device_surface_support(ctx.physical, ctx.queue_family, raw)
        }
        .vk("vkGetPhysicalDeviceSurfaceSupportKHR")?;
        if !supported {
            return Err(Error::NoWindow {
                detail: format!("the device \"{}\" cannot present to it", ctx.info().name),
            });
        }
        Ok(surface)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: every swapchain of the surface was dropped first (the viewer owns both
        // and drops the swapchain before the surface).
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// What `Swapchain::present` found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Presented {
    /// The image was queued for presentation and the swapchain still fits the window.
    Ok,
    /// The window changed: recreate the swapchain before the next frame.
    Stale,
}

/// The swapchain of a surface, its images and the semaphores its presents wait on;
/// frames are drawn into it through `FramesInFlight` slots.
pub struct Swapchain {
    loader: ash::khr::swapchain::Device,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    format: vk::Format,
    extent: vk::Extent2D,
    /// Per image: signalled by the frame's submission, waited on by its present.
    rendered: Vec<vk::Semaphore>,
    ctx: Arc<Context>,
}

impl Swapchain {
    /// A swapchain of `width` x `height` pixels (the surface's own size wins when it has
    /// one). `vsync`: FIFO; otherwise IMMEDIATE or MAILBOX when the driver has one.
    pub fn new(
        ctx: &Arc<Context>,
        surface: &Surface,
        width: u32,
        height: u32,
        vsync: bool,
    ) -> Result<Self> {
        let (s, pd) = (&surface.loader, ctx.physical);
        // SAFETY: surface and physical device belong to this instance.
        let caps = unsafe { s.get_physical_device_surface_capabilities(pd, surface.raw) }
            .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        // SAFETY: as above.
        let formats = unsafe { s.get_physical_device_surface_formats(pd, surface.raw) }
            .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        // SAFETY: as above.
        let modes = unsafe { s.get_physical_device_surface_present_modes(pd, surface.raw) }
            .vk("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        // sRGB images, so the blit from the sRGB offscreen target keeps every byte.
        let format = formats
            .iter()
            .find(|f| {
                matches!(
                    f.format,
                    vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
                )
            })
            .or(formats.first())
            .copied()
            .ok_or_else(|| Error::NoWindow {
                detail: "the surface offers no image format".into(),
            })?;
        if !caps
            .supported_usage_flags
            .contains(vk::ImageUsageFlags::TRANSFER_DST)
        {
            return Err(Error::NoWindow {
                detail: "the surface's images cannot be copied into (no TRANSFER_DST)".into(),
            });
        }
        let mode = if vsync {
            vk::PresentModeKHR::FIFO
        } else {
            [vk::PresentModeKHR::IMMEDIATE, vk::PresentModeKHR::MAILBOX]
                .into_iter()
                .find(|m| modes.contains(m))
                .unwrap_or(vk::PresentModeKHR::FIFO)
        };
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|a| caps.supported_composite_alpha.contains(*a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            .present_mode(mode)
            .clipped(true);
        let loader = ash::khr::swapchain::Device::new(&ctx.instance, &ctx.device);
        // SAFETY: the create info refers to locals alive for the call; the device was
        // created with VK_KHR_swapchain (`ContextOptions::window`).
        let raw = unsafe { loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        let mut chain = Self {
            loader,
            raw,
            images: Vec::new(),
            format: format.format,
            extent,
            rendered: Vec::new(),
            ctx: ctx.clone(),
        };
        // SAFETY: the swapchain was just created on this device.
        chain.images =
            unsafe { chain.loader.get_swapchain_images(raw) }.vk("vkGetSwapchainImagesKHR")?;
        for _ in 0..chain.images.len() {
            chain.rendered.push(semaphore(ctx)?);
        }
        Ok(chain)
    }

    /// Width and height of the images, in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.extent.width, self.extent.height)
    }

    /// The images' format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// True when the images store blue first (the overlay's bytes are swapped to match).
    pub fn is_bgra(&self) -> bool {
        matches!(
            self.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        )
    }

    /// The next image for the frame of `slot` (from `FramesInFlight::next_slot`) to
    /// draw into, or `None` when the window changed (recreate).
    pub fn acquire(&self, frames: &FramesInFlight, slot: usize) -> Result<Option<u32>> {
        // SAFETY: the slot's semaphore is unsignalled: the slot's last submission, which
        // waited on it, has completed (`next_slot` waited for its fence).
        match unsafe {
            self.loader.acquire_next_image(
                self.raw,
                u64::MAX,
                frames.acquired(slot),
                vk::Fence::null(),
            )
        } {
            // A suboptimal image still signals the semaphore: draw it (its present
            // reports the swapchain stale), so the semaphore is consumed.
            Ok((index, _)) => Ok(Some(index)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(result) => Err(Error::Vulkan {
                call: "vkAcquireNextImageKHR",
                result,
            }),
        }
    }

    /// Records the frame with `record` (given the swapchain image, in TRANSFER_DST
    /// layout) into `slot`, leaves the image ready to present, submits and presents,
    /// without waiting for the frame: `FramesInFlight` says when it has finished.
    pub fn present(
        &self,
        frames: &mut FramesInFlight,
        slot: usize,
        index: u32,
        record: impl FnOnce(&Commands<'_>, vk::Image) -> Result<()>,
    ) -> Result<Presented> {
        let image = *self.images.get(index as usize).ok_or_else(|| {
            Error::internal("swapchain", format!("image {index} was never acquired"))
        })?;
        let rendered = self.rendered[index as usize];
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        frames.submit(
            slot,
            &[(frames.acquired(slot), vk::PipelineStageFlags2::ALL_COMMANDS)],
            &[rendered],
            |cmd| {
                barrier::images(
                    cmd.ctx,
                    cmd.raw,
                    &[ImageTransition {
                        image,
                        range,
                        from: (
                            vk::ImageLayout::UNDEFINED,
                            vk::PipelineStageFlags2::ALL_COMMANDS,
                            vk::AccessFlags2::NONE,
                        ),
                        to: (
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                            vk::PipelineStageFlags2::ALL_TRANSFER,
                            vk::AccessFlags2::TRANSFER_WRITE,
                        ),
                    }],
                );
                record(cmd, image)?;
                barrier::images(
                    cmd.ctx,
                    cmd.raw,
                    &[ImageTransition {
                        image,
                        range,
                        from: (
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                            vk::PipelineStageFlags2::ALL_TRANSFER,
                            vk::AccessFlags2::TRANSFER_WRITE,
                        ),
                        to: (
                            vk::ImageLayout::PRESENT_SRC_KHR,
                            vk::PipelineStageFlags2::ALL_COMMANDS,
                            vk::AccessFlags2::NONE,
                        ),
                    }],
                );
                Ok(())
            },
        )?;
        let swapchains = [self.raw];
        let indices = [index];
        let waits = [rendered];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired and is transitioned to PRESENT_SRC by the
        // submission, which signals `rendered` for the present to wait on.
        match unsafe { self.loader.queue_present(self.ctx.queue, &info) } {
            Ok(false) => Ok(Presented::Ok),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Presented::Stale),
            Err(result) => Err(Error::Vulkan {
                call: "vkQueuePresentKHR",
                result,
            }),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: the device is idle first, so no submission or present uses the
        // semaphores or images any more.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            for &s in &self.rendered {
                self.ctx.device.destroy_semaphore(s, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}

fn semaphore(ctx: &Context) -> Result<vk::Semaphore> {
    // SAFETY: valid device.
    unsafe {
        ctx.device
            .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
    }
    .vk("vkCreateSemaphore")
}

impl Commands<'_> {
    /// Scales the target's colour (in TRANSFER_SRC layout, i.e. after `copy_out`) into
    /// `dst` (TRANSFER_DST layout, `width` x `height`, in `dst_format`); copies it
    /// where the two match in size and format (`FrameRunner::for_window`).
    pub fn blit_target(
        &self,
        target: &OffscreenTarget,
        dst: vk::Image,
        dst_format: vk::Format,
        width: u32,
        height: u32,
    ) {
        target.color().use_as(self, super::Usage::TransferSrc);
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        if target.format().color == dst_format
            && (target.width(), target.height()) == (width, height)
        {
            self.copy_whole_image(
                target.color_image(),
                dst,
                vk::ImageAspectFlags::COLOR,
                width,
                height,
            );
            return;
        }
        let corner = |w: u32, h: u32| vk::Offset3D {
            x: w as i32,
            y: h as i32,
            z: 1,
        };
        let region = [vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([
                vk::Offset3D::default(),
                corner(target.width(), target.height()),
            ])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner(width, height)])];
        // SAFETY: recording outside a rendering scope; the layouts are as documented and
        // both images have the transfer usages (target: TRANSFER_SRC, swapchain:
        // TRANSFER_DST).
        unsafe {
            self.ctx.device.cmd_blit_image(
                self.raw,
                target.color_image(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
                vk::Filter::LINEAR,
            )
        };
    }

    /// Copies `width` x `height` RGBA8 pixels from `pixels` into `dst` (TRANSFER_DST
    /// layout) at (`x`, `y`), after the blit.
    pub fn copy_pixels(
        &self,
        pixels: &Buffer,
        dst: vk::Image,
        (x, y): (u32, u32),
        (width, height): (u32, u32),
    ) {
        // The blit wrote the same image: order the two writes.
        barrier::memory(
            self.ctx,
            self.raw,
            (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
        );
        let region = [vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            })
            .image_offset(vk::Offset3D {
                x: x as i32,
                y: y as i32,
                z: 0,
            })
            .image_extent(vk::Extent3D {
                width,
                height,
                depth: 1,
            })];
        // SAFETY: recording outside a rendering scope; the caller keeps the region inside
        // the image and the buffer holds width * height * 4 bytes (`Overlay` sizes both).
        unsafe {
            self.ctx.device.cmd_copy_buffer_to_image(
                self.raw,
                pixels.raw(),
                dst,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
            )
        };
    }
}

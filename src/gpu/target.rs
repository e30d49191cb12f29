//! The offscreen frame: a colour + depth target of any size and its readback into an
//! `image::RgbaImage`.

use std::sync::Arc;

use ash::vk;

use super::barrier::{self, ImageTransition};
use super::{Buffer, BufferDesc, Commands, Context, Image, ImageDesc};
use crate::error::{Error, Result};

/// sRGB colour: shaders write linear values and the hardware encodes them, so the PNG
/// bytes read back are display-ready.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// A colour + depth render target with a host-visible readback buffer.
pub struct OffscreenTarget {
    readback: Buffer,
    depth: Image,
    color: Image,
    width: u32,
    height: u32,
}

impl OffscreenTarget {
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32) -> Result<Self> {
        let max = ctx.info().max_image_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::invalid(
                "--size",
                format!("{width}x{height} is outside 1..={max} pixels per side on this device"),
            ));
        }
        let color = Image::new(
            ctx,
            "offscreen colour",
            ImageDesc::new_2d(
                width,
                height,
                COLOR_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            ),
        )?;
        let depth = Image::new(
            ctx,
            "offscreen depth",
            ImageDesc::new_2d(
                width,
                height,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            ),
        )?;
        let readback = Buffer::new(
            ctx,
            "offscreen readback",
            BufferDesc::readback(
                u64::from(width) * u64::from(height) * 4,
                vk::BufferUsageFlags::TRANSFER_DST,
            ),
        )?;
        Ok(Self {
            readback,
            depth,
            color,
            width,
            height,
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub(crate) fn color_image(&self) -> vk::Image {
        self.color.raw()
    }

    /// Transitions both attachments, clears them and opens a rendering scope with the
    /// viewport set to the whole target.
    pub fn begin(&self, cmd: &Commands<'_>, clear: [f32; 4]) {
        barrier::images(
            cmd.ctx,
            cmd.raw,
            &[
                ImageTransition {
                    image: self.color.raw(),
                    range: self.color.full_range(),
                    from: (
                        vk::ImageLayout::UNDEFINED,
                        vk::PipelineStageFlags2::TOP_OF_PIPE,
                        vk::AccessFlags2::NONE,
                    ),
                    to: (
                        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                    ),
                },
                ImageTransition {
                    image: self.depth.raw(),
                    range: self.depth.full_range(),
                    from: (
                        vk::ImageLayout::UNDEFINED,
                        vk::PipelineStageFlags2::TOP_OF_PIPE,
                        vk::AccessFlags2::NONE,
                    ),
                    to: (
                        vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
                    ),
                },
            ],
        );
        let color_attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(self.color.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue {
                color: vk::ClearColorValue { float32: clear },
            })];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            });
        let info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D { x: 0, y: 0 },
                extent: vk::Extent2D {
                    width: self.width,
                    height: self.height,
                },
            })
            .layer_count(1)
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        // SAFETY: `cmd` is recording outside a rendering scope; attachments are in the
        // layouts named above.
        unsafe { cmd.ctx.device.cmd_begin_rendering(cmd.raw, &info) };
        cmd.set_viewport(self.width, self.height);
    }

    /// Closes the rendering scope opened by `begin`.
    pub fn end(&self, cmd: &Commands<'_>) {
        cmd.end_rendering();
    }

    /// Leaves the colour image ready to be copied or blitted from (after `end`),
    /// without reading it back: what a window does with frames it does not save.
    pub fn finish_for_transfer(&self, cmd: &Commands<'_>) {
        self.to_transfer_src(cmd);
    }

    /// Copies the colour image into the readback buffer (after `end`).
    pub fn copy_out(&self, cmd: &Commands<'_>) {
        self.to_transfer_src(cmd);
        let region = [super::image::color_copy_region(self.width, self.height)];
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL and the buffer holds W*H*4 bytes.
        unsafe {
            cmd.ctx.device.cmd_copy_image_to_buffer(
                cmd.raw,
                self.color.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                self.readback.raw(),
                &region,
            )
        };
        barrier::memory(
            cmd.ctx,
            cmd.raw,
            (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
    }

    fn to_transfer_src(&self, cmd: &Commands<'_>) {
        barrier::images(
            cmd.ctx,
            cmd.raw,
            &[ImageTransition {
                image: self.color.raw(),
                range: self.color.full_range(),
                from: (
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                to: (
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    // Copies and blits.
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::TRANSFER_READ,
                ),
            }],
        );
    }

    /// The frame copied by the last `copy_out` (after its submission finished).
    pub fn read_image(&self) -> Result<image::RgbaImage> {
        let bytes = self.readback.mapped()?.to_vec();
        image::RgbaImage::from_raw(self.width, self.height, bytes).ok_or_else(|| {
            Error::internal("readback", "the readback buffer is smaller than the frame")
        })
    }
}

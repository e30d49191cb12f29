//! The offscreen frame: a multisampled colour + depth target of any size, resolved
//! into a single-sampled colour image, and its readback into an `image::RgbaImage`.

use std::sync::Arc;

use ash::vk;

use super::{Buffer, BufferDesc, Commands, Context, Image, ImageDesc, Usage, Use};
use crate::error::{Error, Result};

/// sRGB colour: shaders write linear values and the hardware encodes them, so the PNG
/// bytes read back are display-ready.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// 32-bit float depth with no stencil; cleared to 1.0 by `OffscreenTarget::begin` and
/// tested `LESS_OR_EQUAL` by the graphics pipelines.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// What a pass draws into: the formats and sample count of an offscreen target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TargetFormat {
    /// Format of the colour attachment and its resolved image (4 or, for RGBA16F, 8 bytes
    /// a texel).
    pub color: vk::Format,
    /// Format of the depth attachment (depth aspect only).
    pub depth: vk::Format,
    /// Samples per pixel of the colour and depth attachments (1: no resolve).
    pub samples: vk::SampleCountFlags,
}

impl TargetFormat {
    /// Every frame sediment shows or writes: sRGB colour, 32-bit depth, 4x MSAA
    /// (silhouettes and shadow-map edges resolved from four samples a pixel) unless the
    /// context was made with other samples (`Context::frame_format`).
    pub const FRAME: Self = Self {
        color: COLOR_FORMAT,
        depth: DEPTH_FORMAT,
        samples: vk::SampleCountFlags::TYPE_4,
    };

    /// Memory a `width` x `height` frame of this format costs, bytes: the resolved
    /// colour, the multisampled colour and depth, the readback buffer, and on the host
    /// the picture read back and its PNG encoding (about one more RGBA copy): 48 bytes
    /// a pixel at 4 samples, 20 at 1: an estimate meant to lie above the process's
    /// peak.
    pub fn frame_bytes(&self, width: u32, height: u32) -> u64 {
        let (color, depth) = (texel_bytes(self.color), texel_bytes(self.depth));
        let samples = u64::from(self.samples.as_raw().max(1));
        let multisampled = if samples > 1 { color * samples } else { 0 };
        let per_pixel = color + multisampled + depth * samples + color + 4 + 4;
        u64::from(width) * u64::from(height) * per_pixel
    }

    /// Refuses a frame over the host memory budget (4 GiB: on lavapipe device memory is
    /// host memory), naming the largest size of the same aspect that fits.
    pub fn check_budget(&self, width: u32, height: u32) -> Result<()> {
        self.check_budget_of("--size", width, height)
    }

    /// [`TargetFormat::check_budget`] for a size `what` sets (an option, "the
    /// window"): the message names it.
    pub fn check_budget_of(&self, what: &str, width: u32, height: u32) -> Result<()> {
        let bytes = self.frame_bytes(width, height);
        let samples = self.samples.as_raw().max(1);
        // Both sides scaled by the same factor keep the aspect and fit the budget.
        let scale = (crate::budget::HOST_BYTES as f64 / bytes as f64).sqrt();
        let fits = |side: u32| ((f64::from(side) * scale).floor() as u32).max(1);
        let reduce = if samples > 1 {
            format!(
                "reduce {what} (at most about {}x{} at this aspect) or --samples (at 1 sample a pixel: {})",
                fits(width),
                fits(height),
                match (Self {
                    samples: vk::SampleCountFlags::TYPE_1,
                    ..*self
                })
                .frame_bytes(width, height)
                {
                    b if b <= crate::budget::HOST_BYTES =>
                        format!("{:.1} GiB, which fits", crate::budget::gib(b)),
                    b => format!("still {:.1} GiB", crate::budget::gib(b)),
                }
            )
        } else {
            format!(
                "reduce {what} (at most about {}x{} at this aspect)",
                fits(width),
                fits(height)
            )
        };
        crate::budget::check_host(
            what,
            &format!("a {width}x{height} frame at {samples} sample(s) a pixel"),
            bytes,
            &reduce,
        )
    }
}

/// Bytes of one texel of the target formats sediment uses: 8 for RGBA16F, else 4
/// (RGBA8, D32).
fn texel_bytes(format: vk::Format) -> u64 {
    if format == vk::Format::R16G16B16A16_SFLOAT {
        8
    } else {
        4
    }
}

/// A colour + depth render target, multisampled and resolved into a single-sampled
/// colour image, with a host-visible readback buffer.
pub struct OffscreenTarget {
    /// `None` for a layer made by `like` (never read back).
    readback: Option<Buffer>,
    depth: Image,
    /// The multisampled colour attachment (`None` with one sample: `color` is drawn).
    samples: Option<Image>,
    /// The resolved colour: what is read back, blitted or copied.
    color: Image,
    format: TargetFormat,
    width: u32,
    height: u32,
    /// Colour and depth are kept and can be sampled after the frame (a pass that reads
    /// the frame drawn: temporal anti-aliasing).
    sampled: bool,
}

impl OffscreenTarget {
    /// A target of the context's frame format (`Context::frame_format`).
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32) -> Result<Self> {
        Self::with_format(ctx, width, height, ctx.frame_format())
    }

    /// A target of any format (a readback of a format other than RGBA8 reads raw
    /// texels, see `read_image`).
    pub fn with_format(
        ctx: &Arc<Context>,
        width: u32,
        height: u32,
        format: TargetFormat,
    ) -> Result<Self> {
        Self::make(ctx, width, height, format, false, true)
    }

    /// A single-sampled target of the context's colour and depth formats whose colour
    /// and depth a later pass samples (`to_shader_read`).
    pub fn sampled(ctx: &Arc<Context>, width: u32, height: u32) -> Result<Self> {
        let format = TargetFormat {
            samples: vk::SampleCountFlags::TYPE_1,
            ..ctx.frame_format()
        };
        Self::make(ctx, width, height, format, true, true)
    }

    /// A target of this one's size, format and kind (its depth kept or not) to draw a
    /// layer into and copy from (`hold_for_copies`), not to read back: it has no
    /// readback buffer (`copy_out` and `read_image` fail).
    pub fn like(&self, ctx: &Arc<Context>) -> Result<Self> {
        Self::make(
            ctx,
            self.width,
            self.height,
            self.format,
            self.sampled,
            false,
        )
    }

    fn make(
        ctx: &Arc<Context>,
        width: u32,
        height: u32,
        format: TargetFormat,
        sampled: bool,
        read_back: bool,
    ) -> Result<Self> {
        let read = if sampled {
            vk::ImageUsageFlags::SAMPLED
        } else {
            vk::ImageUsageFlags::empty()
        };
        let max = ctx.info().max_image_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::invalid(
                "--size",
                format!("{width}x{height} is outside 1..={max} pixels per side on this device"),
            ));
        }
        format.check_budget(width, height)?;
        let multisampled = format.samples != vk::SampleCountFlags::TYPE_1;
        let color = Image::new(
            ctx,
            "offscreen colour",
            ImageDesc::new_2d(
                width,
                height,
                format.color,
                vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | read,
            ),
        )?;
        let samples = if multisampled {
            Some(Image::new(
                ctx,
                "offscreen colour samples",
                ImageDesc::new_2d(
                    width,
                    height,
                    format.color,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT,
                )
                .samples(format.samples),
            )?)
        } else {
            None
        };
        let depth = Image::new(
            ctx,
            "offscreen depth",
            ImageDesc::new_2d(
                width,
                height,
                format.depth,
                // Always sampled: ambient occlusion reads the depth of any frame.
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::SAMPLED,
            )
            .samples(format.samples),
        )?;
        let texel = texel_bytes(format.color);
        let readback = if read_back {
            Some(Buffer::new(
                ctx,
                "offscreen readback",
                BufferDesc::readback(
                    u64::from(width) * u64::from(height) * texel,
                    vk::BufferUsageFlags::TRANSFER_DST,
                ),
            )?)
        } else {
            None
        };
        Ok(Self {
            readback,
            depth,
            samples,
            color,
            format,
            width,
            height,
            sampled,
        })
    }

    /// Formats and sample count the target was made with; pipelines drawing into it
    /// must match (`GraphicsPipelineDesc::target`).
    pub fn format(&self) -> TargetFormat {
        self.format
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    pub(crate) fn color_image(&self) -> vk::Image {
        self.color.raw()
    }

    /// The single-sampled colour image (resolved, or drawn directly at one sample).
    pub(crate) fn color(&self) -> &Image {
        &self.color
    }

    /// The depth image (multisampled when the target is).
    pub(crate) fn depth(&self) -> &Image {
        &self.depth
    }

    /// After `end`: the colour and depth of a `sampled` target become readable by
    /// fragment shaders (colour SHADER_READ_ONLY, depth DEPTH_READ_ONLY).
    pub fn to_shader_read(&self, cmd: &Commands<'_>) {
        cmd.uses(&[
            Use::image(&self.color, Usage::SampledFragment),
            Use::image(&self.depth, Usage::SampledDepthFragment),
        ]);
    }

    /// Transitions the attachments, clears them and opens a rendering scope with the
    /// viewport set to the whole target; with samples, the colour resolves into the
    /// single-sampled image when the scope closes.
    pub fn begin(&self, cmd: &Commands<'_>, clear: [f32; 4]) {
        let mut uses = vec![
            Use::image_discarding(&self.color, Usage::ColorAttachment),
            Use::image_discarding(&self.depth, Usage::DepthAttachment),
        ];
        if let Some(samples) = &self.samples {
            uses.push(Use::image_discarding(samples, Usage::ColorAttachment));
        }
        cmd.uses(&uses);
        let clear_color = vk::ClearValue {
            color: vk::ClearColorValue { float32: clear },
        };
        let color_attachment = [match &self.samples {
            Some(samples) => vk::RenderingAttachmentInfo::default()
                .image_view(samples.view())
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(self.color.view())
                .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::DONT_CARE)
                .clear_value(clear_color),
            None => vk::RenderingAttachmentInfo::default()
                .image_view(self.color.view())
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(clear_color),
        }];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(if self.sampled {
                vk::AttachmentStoreOp::STORE
            } else {
                vk::AttachmentStoreOp::DONT_CARE
            })
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            });
        self.open_scope(cmd, &color_attachment, Some(&depth_attachment));
    }

    /// Begins dynamic rendering over the whole target into these attachments (in
    /// the layouts they name).
    fn open_scope(
        &self,
        cmd: &Commands<'_>,
        color: &[vk::RenderingAttachmentInfo<'_>],
        depth: Option<&vk::RenderingAttachmentInfo<'_>>,
    ) {
        let mut info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D { x: 0, y: 0 },
                extent: vk::Extent2D {
                    width: self.width,
                    height: self.height,
                },
            })
            .layer_count(1)
            .color_attachments(color);
        if let Some(depth) = depth {
            info = info.depth_attachment(depth);
        }
        // SAFETY: `cmd` is recording outside a rendering scope; the callers put the
        // attachments in the layouts they name.
        unsafe { cmd.ctx.device.cmd_begin_rendering(cmd.raw, &info) };
        cmd.set_viewport(self.width, self.height);
    }

    /// Whether colour and depth can be copied between targets and drawn over
    /// (`hold_for_copies`, `copy_attachments_from`, `begin_loaded`): a single-sampled
    /// target that keeps its depth (made with `sampled`).
    pub fn copies_attachments(&self) -> bool {
        self.samples.is_none() && self.sampled
    }

    /// Opens a rendering scope over what colour and depth hold (loaded, not cleared):
    /// after `copy_attachments_from`. Only where `copies_attachments`.
    pub fn begin_loaded(&self, cmd: &Commands<'_>) {
        let color_attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(self.color.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE);
        self.open_scope(cmd, &color_attachment, Some(&depth_attachment));
    }

    /// After `end`: leaves colour and depth to be copied from (`copy_attachments_from`
    /// on another target) until the next `begin`. Only where `copies_attachments`.
    pub fn hold_for_copies(&self, cmd: &Commands<'_>) {
        cmd.uses(&[
            Use::image(&self.color, Usage::TransferSrc),
            Use::image(&self.depth, Usage::TransferSrc),
        ]);
    }

    /// Replaces colour and depth by `from`'s (a target of the same size and format,
    /// after its `hold_for_copies`), ready for `begin_loaded`. Only where
    /// `copies_attachments`.
    pub fn copy_attachments_from(&self, cmd: &Commands<'_>, from: &OffscreenTarget) {
        cmd.uses(&[
            Use::image(&from.color, Usage::TransferSrc),
            Use::image(&from.depth, Usage::TransferSrc),
            Use::image_discarding(&self.color, Usage::TransferDst),
            Use::image_discarding(&self.depth, Usage::TransferDst),
        ]);
        self.copy(cmd, (&from.color, &self.color), vk::ImageAspectFlags::COLOR);
        self.copy(cmd, (&from.depth, &self.depth), vk::ImageAspectFlags::DEPTH);
        cmd.uses(&[
            Use::image(&self.color, Usage::ColorAttachment),
            Use::image(&self.depth, Usage::DepthAttachment),
        ]);
    }

    /// One whole-image copy, `from` in TRANSFER_SRC_OPTIMAL to `to` in
    /// TRANSFER_DST_OPTIMAL (this target's size).
    fn copy(&self, cmd: &Commands<'_>, (from, to): (&Image, &Image), aspect: vk::ImageAspectFlags) {
        cmd.copy_whole_image(from.raw(), to.raw(), aspect, self.width, self.height);
    }

    /// After `end`: the depth (multisampled where the target is) becomes readable by
    /// fragment shaders (DEPTH_READ_ONLY), for a pass over the finished frame.
    pub fn depth_to_shader_read(&self, cmd: &Commands<'_>) {
        cmd.uses(&[Use::image(&self.depth, Usage::SampledDepthFragment)]);
    }

    /// After `end`: opens a rendering scope on the resolved colour alone, what it holds
    /// kept, for a pass drawn over the finished frame (closed with `end`).
    pub fn begin_over(&self, cmd: &Commands<'_>) {
        cmd.uses(&[Use::image(&self.color, Usage::ColorAttachment)]);
        let attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(self.color.view())
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::LOAD)
            .store_op(vk::AttachmentStoreOp::STORE)];
        self.open_scope(cmd, &attachment, None);
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

    /// Copies the resolved colour (after `end`) into mip level 0 of `layer` of `image`
    /// (same size and format), leaving that level in TRANSFER_DST for
    /// `Image::record_mips`; the layer's old contents are discarded.
    pub fn copy_into_layer(&self, cmd: &Commands<'_>, image: &Image, layer: u32) {
        self.to_transfer_src(cmd);
        let range = vk::ImageSubresourceRange {
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: layer,
            layer_count: 1,
            ..image.full_range()
        };
        image.discard_range_as(cmd, range, Usage::TransferDst);
        let layers = |layer| vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: layer,
            layer_count: 1,
        };
        let region = [vk::ImageCopy {
            src_subresource: layers(0),
            src_offset: vk::Offset3D::default(),
            dst_subresource: layers(layer),
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D {
                width: self.width,
                height: self.height,
                depth: 1,
            },
        }];
        // SAFETY: the colour is in TRANSFER_SRC_OPTIMAL and the layer's level 0 in
        // TRANSFER_DST_OPTIMAL; sizes and formats match (the caller's contract, checked
        // by validation in tests).
        unsafe {
            cmd.ctx.device.cmd_copy_image(
                cmd.raw,
                self.color.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                image.raw(),
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &region,
            )
        };
    }

    /// Copies the colour image into the readback buffer (after `end`).
    pub fn copy_out(&self, cmd: &Commands<'_>) -> Result<()> {
        let readback = self.readback()?;
        cmd.uses(&[
            Use::image(&self.color, Usage::TransferSrc),
            Use::buffer(readback, Usage::TransferDst),
        ]);
        let region = [super::image::color_copy_region(self.width, self.height)];
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL and the buffer holds W*H*4 bytes.
        unsafe {
            cmd.ctx.device.cmd_copy_image_to_buffer(
                cmd.raw,
                self.color.raw(),
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.raw(),
                &region,
            )
        };
        readback.use_as(cmd, Usage::HostRead);
        Ok(())
    }

    fn to_transfer_src(&self, cmd: &Commands<'_>) {
        self.color.use_as(cmd, Usage::TransferSrc);
    }

    fn readback(&self) -> Result<&Buffer> {
        self.readback
            .as_ref()
            .ok_or_else(|| Error::internal("readback", "a layer target (`like`) is not read back"))
    }

    /// The frame copied by the last `copy_out` (after its submission finished).
    pub fn read_image(&self) -> Result<image::RgbaImage> {
        let mut bytes = self.readback()?.mapped()?.to_vec();
        match self.format.color {
            COLOR_FORMAT => {}
            // A window's order (a viewer's frame resolved for its swapchain).
            vk::Format::B8G8R8A8_SRGB => {
                for pixel in bytes.chunks_exact_mut(4) {
                    pixel.swap(0, 2);
                }
            }
            other => {
                return Err(Error::internal(
                    "readback",
                    format!("{other:?} is not read back as RGBA8"),
                ));
            }
        }
        image::RgbaImage::from_raw(self.width, self.height, bytes).ok_or_else(|| {
            Error::internal("readback", "the readback buffer is smaller than the frame")
        })
    }
}

/// A single-sampled depth image drawn alone (no colour) and then sampled: a shadow
/// map. Created cleared to the far plane and readable, so a pass can bind it before
/// anything was drawn into it.
pub struct DepthTarget {
    depth: Image,
    size: u32,
}

impl DepthTarget {
    /// A `size`² depth target of `DEPTH_FORMAT`, cleared to 1 and left readable by
    /// fragment shaders.
    pub fn new(ctx: &Arc<Context>, name: &str, size: u32) -> Result<Self> {
        let depth = Image::new(
            ctx,
            name,
            ImageDesc::new_2d(
                size,
                size,
                DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                    | vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST,
            ),
        )?;
        let target = Self { depth, size };
        ctx.submit_and_wait("clear depth target", |cmd| {
            target.begin(cmd);
            target.end(cmd);
            Ok(())
        })?;
        Ok(target)
    }

    /// Side in texels.
    pub fn size(&self) -> u32 {
        self.size
    }

    /// The depth view (sample it after `end`).
    pub fn view(&self) -> vk::ImageView {
        self.depth.view()
    }

    /// Clears the depth to 1 and opens a depth-only rendering scope over the whole
    /// image, the viewport set to it.
    pub fn begin(&self, cmd: &Commands<'_>) {
        cmd.uses(&[Use::image_discarding(&self.depth, Usage::DepthAttachment)]);
        self.open(cmd, vk::AttachmentLoadOp::CLEAR);
    }

    /// Takes the depth of `from` (the same size) and opens a depth-only rendering
    /// scope over it, to draw more into it.
    pub fn begin_from(&self, cmd: &Commands<'_>, from: &DepthTarget) {
        cmd.uses(&[
            Use::image(&from.depth, Usage::TransferSrc),
            Use::image_discarding(&self.depth, Usage::TransferDst),
        ]);
        let size = self.size.min(from.size);
        cmd.copy_whole_image(
            from.depth.raw(),
            self.depth.raw(),
            vk::ImageAspectFlags::DEPTH,
            size,
            size,
        );
        cmd.uses(&[Use::image(&self.depth, Usage::DepthAttachment)]);
        self.open(cmd, vk::AttachmentLoadOp::LOAD);
    }

    fn open(&self, cmd: &Commands<'_>, load: vk::AttachmentLoadOp) {
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view())
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
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
                    width: self.size,
                    height: self.size,
                },
            })
            .layer_count(1)
            .depth_attachment(&depth_attachment);
        // SAFETY: `cmd` is recording outside a rendering scope; the callers' barriers
        // put the depth in DEPTH_ATTACHMENT_OPTIMAL.
        unsafe { cmd.ctx.device.cmd_begin_rendering(cmd.raw, &info) };
        cmd.set_viewport(self.size, self.size);
    }

    /// Closes the scope and leaves the depth readable by fragment shaders.
    pub fn end(&self, cmd: &Commands<'_>) {
        cmd.end_rendering();
        cmd.uses(&[Use::image(&self.depth, Usage::SampledDepthFragment)]);
    }
}

//! Buffers: a plain-data description, and an owning wrapper that frees its memory.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};

use super::Context;
use crate::error::{Error, Result, VkContext};
use crate::pod::{Pod, as_bytes, from_bytes};

/// What a buffer is for and where its memory lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BufferDesc {
    /// Size in bytes; must be at least 1.
    pub size: u64,
    /// Every way the buffer will be used (vertex, storage, transfer source, XFB...).
    pub usage: vk::BufferUsageFlags,
    /// gpu-allocator memory class: device-local, upload or readback.
    pub location: MemoryLocation,
}

impl BufferDesc {
    /// Device-local memory; filled by transfers or by the GPU itself.
    pub fn gpu_only(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self {
            size,
            usage,
            location: MemoryLocation::GpuOnly,
        }
    }

    /// Host-visible memory the CPU writes and the GPU reads (uploads, uniforms).
    pub fn upload(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self {
            size,
            usage,
            location: MemoryLocation::CpuToGpu,
        }
    }

    /// Host-visible memory the GPU writes and the CPU reads back.
    pub fn readback(size: u64, usage: vk::BufferUsageFlags) -> Self {
        Self {
            size,
            usage,
            location: MemoryLocation::GpuToCpu,
        }
    }
}

/// An owned `VkBuffer` with its memory. Dropping it frees both; the caller makes sure
/// the GPU is done with it (sediment's submissions wait on their fence).
pub struct Buffer {
    /// The accesses its last use left (see `Buffer::use_as`).
    state: super::usage::Tracked,
    allocation: Option<Allocation>,
    raw: vk::Buffer,
    desc: BufferDesc,
    ctx: Arc<Context>,
}

impl Buffer {
    /// Creates an exclusive-sharing `VkBuffer` of `desc`, binds fresh memory from the
    /// context's allocator and gives the buffer the debug name `name`; a zero size is
    /// an error.
    pub fn new(ctx: &Arc<Context>, name: &str, desc: BufferDesc) -> Result<Self> {
        if desc.size == 0 {
            return Err(Error::internal(
                format!("buffer \"{name}\" size"),
                "a buffer must hold at least one byte",
            ));
        }
        let info = vk::BufferCreateInfo::default()
            .size(desc.size)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid device and create info.
        let raw = unsafe { ctx.device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        // SAFETY: `raw` was just created on this device.
        let requirements = unsafe { ctx.device.get_buffer_memory_requirements(raw) };
        let allocation = ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: desc.location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                // SAFETY: the buffer has no memory bound and no other user.
                unsafe { ctx.device.destroy_buffer(raw, None) };
                return Err(Error::Allocation {
                    name: name.to_owned(),
                    bytes: desc.size,
                    source,
                });
            }
        };
        // SAFETY: the allocation satisfies `requirements`; it is freed only after the
        // buffer is destroyed (see Drop).
        let bound = unsafe {
            ctx.device
                .bind_buffer_memory(raw, allocation.memory(), allocation.offset())
        };
        let buffer = Buffer {
            state: super::usage::Tracked::new(),
            allocation: Some(allocation),
            raw,
            desc,
            ctx: ctx.clone(),
        };
        bound.vk("vkBindBufferMemory")?;
        ctx.name(raw, name);
        Ok(buffer)
    }

    /// A host-visible buffer filled with `data`.
    pub fn with_data<T: Pod>(
        ctx: &Arc<Context>,
        name: &str,
        usage: vk::BufferUsageFlags,
        data: &[T],
    ) -> Result<Self> {
        let bytes = as_bytes(data);
        let mut buffer = Buffer::new(ctx, name, BufferDesc::upload(bytes.len() as u64, usage))?;
        buffer.write(0, data)?;
        Ok(buffer)
    }

    /// Records the barrier that makes the buffer ready for `usage` after its last
    /// declared use (nothing where none is needed), outside a rendering scope.
    pub fn use_as(&self, cmd: &super::Commands<'_>, usage: super::Usage) {
        cmd.uses(&[super::Use::buffer(self, usage)]);
    }

    pub(crate) fn tracked(&self) -> &super::usage::Tracked {
        &self.state
    }

    /// The `VkBuffer` handle; valid while `self` lives.
    pub fn raw(&self) -> vk::Buffer {
        self.raw
    }

    /// Size in bytes as requested (the allocation may be larger).
    pub fn size(&self) -> u64 {
        self.desc.size
    }

    /// The description the buffer was created from.
    pub fn desc(&self) -> &BufferDesc {
        &self.desc
    }

    /// Copies `data` into a host-visible buffer at byte `offset`.
    pub fn write<T: Pod>(&mut self, offset: u64, data: &[T]) -> Result<()> {
        let bytes = as_bytes(data);
        let slice = self.mapped_mut()?;
        let start = usize::try_from(offset).unwrap_or(usize::MAX);
        let end = start.saturating_add(bytes.len());
        let Some(dst) = slice.get_mut(start..end) else {
            return Err(Error::internal(
                "buffer write",
                format!(
                    "{} bytes at offset {offset} do not fit in {} bytes",
                    bytes.len(),
                    slice.len()
                ),
            ));
        };
        dst.copy_from_slice(bytes);
        Ok(())
    }

    /// The bytes of a host-visible buffer (after the GPU work writing it has finished).
    pub fn mapped(&self) -> Result<&[u8]> {
        let size = self.size() as usize;
        self.allocation
            .as_ref()
            .and_then(Allocation::mapped_slice)
            .map(|s| &s[..size.min(s.len())])
            .ok_or_else(|| Error::internal("buffer read", "the buffer is not host-visible"))
    }

    fn mapped_mut(&mut self) -> Result<&mut [u8]> {
        let size = self.desc.size as usize;
        self.allocation
            .as_mut()
            .and_then(Allocation::mapped_slice_mut)
            .map(|s| {
                let n = size.min(s.len());
                &mut s[..n]
            })
            .ok_or_else(|| Error::internal("buffer write", "the buffer is not host-visible"))
    }

    /// Reads a host-visible buffer as a vector of `T` (whole elements only).
    pub fn read<T: Pod>(&self) -> Result<Vec<T>> {
        let bytes = self.mapped()?;
        Ok(from_bytes(bytes))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the buffer belongs to this device and the GPU is done with it.
        unsafe { self.ctx.device.destroy_buffer(self.raw, None) };
        if let Some(allocation) = self.allocation.take() {
            // A failed free only leaks; nothing better can be done in Drop.
            let _ = self.ctx.allocator().free(allocation);
        }
    }
}

/// A whole buffer viewed as texels (RGBA32F or R32F), read in shaders as a texel buffer
/// (`samplerBuffer`, `texelFetch`). Why: llvmpipe (Mesa 22.3) reads a storage buffer
/// for 8 invocations as a loop over them, component by component, where a texel fetch
/// gathers the 8 lanes' texels with vector instructions (see `ring_growth.comp`).
pub struct TexelView {
    raw: vk::BufferView,
    ctx: Arc<Context>,
}

impl TexelView {
    /// A view of all of `buffer` (created with UNIFORM_TEXEL_BUFFER usage) as 16-byte
    /// RGBA32F texels; an error naming `what` where the device's
    /// `maxTexelBufferElements` is smaller.
    pub fn rgba32f(ctx: &Arc<Context>, what: &str, buffer: &Buffer) -> Result<Self> {
        Self::whole(ctx, what, buffer, vk::Format::R32G32B32A32_SFLOAT, 16)
    }

    /// The same as [`TexelView::rgba32f`] with one float a texel (R32F).
    pub fn r32f(ctx: &Arc<Context>, what: &str, buffer: &Buffer) -> Result<Self> {
        Self::whole(ctx, what, buffer, vk::Format::R32_SFLOAT, 4)
    }

    fn whole(
        ctx: &Arc<Context>,
        what: &str,
        buffer: &Buffer,
        format: vk::Format,
        texel_bytes: u64,
    ) -> Result<Self> {
        let limit = ctx.info().max_texel_buffer_elements;
        let texels = texels_within(what, buffer.size(), texel_bytes, limit)?;
        let info = vk::BufferViewCreateInfo::default()
            .buffer(buffer.raw())
            .format(format)
            .offset(0)
            .range(texels * texel_bytes);
        // SAFETY: valid device; the range lies inside the buffer, within the device's
        // limit; callers keep the buffer alive as long as the view.
        let raw = unsafe { ctx.device.create_buffer_view(&info, None) }.vk("vkCreateBufferView")?;
        ctx.name(raw, what);
        Ok(Self {
            raw,
            ctx: ctx.clone(),
        })
    }

    /// The `VkBufferView` handle; destroyed with `self`.
    pub fn raw(&self) -> vk::BufferView {
        self.raw
    }
}

/// A buffer of floats offered to a shader as an R32F texel buffer where the device's
/// texel buffers hold it, else a view of a one-texel stand-in (a descriptor must be
/// valid even where the shader, told by a specialization constant, never reads it):
/// the passes that read heights lane by lane from a storage buffer read them as texels
/// instead where they can (llvmpipe gathers a texel fetch for its 8 lanes at once).
pub struct FloatTexels {
    // The view before the stand-in it may view.
    view: TexelView,
    _stand_in: Option<Box<Buffer>>,
    readable: bool,
}

impl FloatTexels {
    /// `buffer` (created with UNIFORM_TEXEL_BUFFER usage) as R32F texels unless
    /// `storage_reads` or the device's `maxTexelBufferElements` is below its floats.
    pub fn new(
        ctx: &Arc<Context>,
        what: &str,
        buffer: &Buffer,
        storage_reads: bool,
    ) -> Result<Self> {
        let floats = buffer.size() / 4;
        if !storage_reads && floats <= u64::from(ctx.info().max_texel_buffer_elements) {
            return Ok(Self {
                view: TexelView::r32f(ctx, what, buffer)?,
                _stand_in: None,
                readable: true,
            });
        }
        let name = format!("{what} (texel stand-in)");
        let stand_in = Buffer::with_data(
            ctx,
            &name,
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &[0.0f32],
        )?;
        let view = TexelView::r32f(ctx, &name, &stand_in)?;
        Ok(Self {
            view,
            _stand_in: Some(Box::new(stand_in)),
            readable: false,
        })
    }

    /// The view to bind (of the stand-in where not [`FloatTexels::readable`]).
    pub fn view(&self) -> &TexelView {
        &self.view
    }

    /// Whether the view holds the buffer's floats: the value of the shader's
    /// specialization constant that chooses texel reads.
    pub fn readable(&self) -> bool {
        self.readable
    }
}

/// The texels of `texel_bytes` in `bytes`, or an error naming `what` where there are
/// more than the device's `limit`.
fn texels_within(what: &str, bytes: u64, texel_bytes: u64, limit: u32) -> Result<u64> {
    let texels = bytes / texel_bytes;
    if texels > u64::from(limit) {
        return Err(Error::internal(
            what,
            format!(
                "{texels} texels of {texel_bytes} bytes, but this device's texel buffers \
                 hold at most {limit} (maxTexelBufferElements)"
            ),
        ));
    }
    Ok(texels)
}

impl Drop for TexelView {
    fn drop(&mut self) {
        // SAFETY: the view belongs to this device and the GPU is done with it.
        unsafe { self.ctx.device.destroy_buffer_view(self.raw, None) };
    }
}

#[cfg(test)]
mod tests {
    use super::texels_within;

    #[test]
    fn a_texel_view_beyond_the_device_limit_is_refused_with_the_limit_named() {
        assert_eq!(
            texels_within("mesh", 16 * 65536, 16, 65536).ok(),
            Some(65536)
        );
        let err = texels_within("compute growth mesh a", 16 * 65537, 16, 65536)
            .expect_err("one texel too many");
        let message = err.to_string();
        assert!(
            message.contains("65537 texels") && message.contains("maxTexelBufferElements"),
            "{message}"
        );
    }
}

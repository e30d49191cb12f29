//! Plain-old-data: types that can be copied to and from GPU memory as bytes. Kept
//! outside `gpu` so models can declare their vertex layouts without touching Vulkan.

/// Types whose every bit pattern is valid and which have no padding.
///
/// # Safety
/// Implement only for `#[repr(C)]` types made of `f32`/`u32`/`i32` fields (or arrays
/// of them) with no padding.
pub unsafe trait Pod: Copy + 'static {}

// SAFETY: primitive numbers have no padding and every bit pattern is valid.
unsafe impl Pod for f32 {}
// SAFETY: as above.
unsafe impl Pod for u32 {}
// SAFETY: as above.
unsafe impl Pod for i32 {}
// SAFETY: as above.
unsafe impl Pod for u64 {}
// SAFETY: as above.
unsafe impl Pod for u8 {}
// SAFETY: arrays of Pod are Pod.
unsafe impl<T: Pod, const N: usize> Pod for [T; N] {}
// SAFETY: glam's Vec2/Vec3/Vec4/Mat4 are `#[repr(C)]` f32 aggregates without padding.
unsafe impl Pod for glam::Vec2 {}
// SAFETY: as above.
unsafe impl Pod for glam::Vec3 {}
// SAFETY: as above.
unsafe impl Pod for glam::Vec4 {}
// SAFETY: as above.
unsafe impl Pod for glam::Mat4 {}

/// The bytes of a slice of plain data.
pub fn as_bytes<T: Pod>(data: &[T]) -> &[u8] {
    // SAFETY: `T: Pod` has no padding, so every byte is initialised; the length is the
    // slice's size in bytes.
    unsafe { std::slice::from_raw_parts(data.as_ptr().cast::<u8>(), std::mem::size_of_val(data)) }
}

/// Copies whole `T`s out of `bytes` (any alignment).
pub fn from_bytes<T: Pod>(bytes: &[u8]) -> Vec<T> {
    let size = std::mem::size_of::<T>().max(1);
    bytes
        .chunks_exact(size)
        // SAFETY: every bit pattern is a valid `T: Pod`; `read_unaligned` has no alignment
        // requirement and the chunk holds exactly size_of::<T>() bytes.
        .map(|chunk| unsafe { chunk.as_ptr().cast::<T>().read_unaligned() })
        .collect()
}

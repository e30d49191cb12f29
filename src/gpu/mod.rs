//! The only module that touches ash, and the only one that places barriers: context
//! and device choice, memory, buffers and images that track their last use (a pass
//! declares a `Usage` and the barrier is derived), shader modules, pipelines (incl.
//! geometry stage and transform feedback) and descriptors written by name, the
//! offscreen target and its readback, timestamp spans, a window's frames in flight
//! and XFB helpers.

mod barrier;
mod buffer;
mod commands;
mod context;
mod features;
mod frames;
mod heap;
mod image;
mod pipeline;
mod sampler;
mod shader;
mod swapchain;
mod target;
mod timing;
mod usage;
mod validation;
mod xfb;

/// Vulkan's types (formats, flags) for passes that describe pipelines; calls stay here.
pub use ash::vk;

pub use crate::pod::{Pod, as_bytes, from_bytes};
pub use buffer::{Buffer, BufferDesc, FloatTexels, TexelView};
pub use commands::Commands;
pub use context::{Context, ContextOptions, DeviceInfo, probe_devices};
pub use features::{Capability, DeviceReport};
pub use frames::FramesInFlight;
pub use heap::{keep_freed_memory, minor_page_faults};
pub use image::{Image, ImageDesc};
pub use pipeline::{
    Descriptor, DescriptorSet, GraphicsPipelineDesc, Pipeline, PipelineLayout, VertexLayout,
};
pub use sampler::Sampler;
pub use shader::ShaderModule;
pub use swapchain::{Presented, Surface, Swapchain};
pub use target::{COLOR_FORMAT, DEPTH_FORMAT, DepthTarget, OffscreenTarget, TargetFormat};
pub use timing::{GpuTimer, Span, SpanId, SpanScope};
pub use usage::{Usage, Use};
pub use validation::ValidationLog;
pub use xfb::{CaptureMode, StreamCounts, StreamQueries, XfbStream};

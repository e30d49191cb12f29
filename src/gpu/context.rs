//! The Vulkan context: loader, instance, validation messenger, device choice, queue,
//! memory allocator and one-shot command submission.

use std::ffi::{CStr, c_char};
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::Commands;
use super::features::{self, DeviceReport};
use super::validation::{self, ValidationLog};
use crate::error::{Error, Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to choose and set up the device.
#[derive(Clone, Debug, Default)]
pub struct ContextOptions {
    /// Pick the first device whose name contains this (case-insensitive).
    pub device: Option<String>,
    /// Enable VK_LAYER_KHRONOS_validation and record its errors.
    pub validate: bool,
    /// With `validate`, also check synchronization (the layer's
    /// `VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT`): missing or too
    /// narrow barriers become errors. Slower; the GPU tests turn it on.
    pub sync_validation: bool,
    /// Present to windows of this display (enables the surface and swapchain
    /// extensions); `None` for headless work.
    pub window: Option<raw_window_handle::RawDisplayHandle>,
    /// Anti-aliasing samples per pixel of every frame (1, 2, 4 or 8; `None`: 4).
    pub samples: Option<u32>,
    /// Shade surfaces with sub-pixel detail (the speleothems' normal map) once per
    /// sample rather than once per pixel when multisampled (`None`: on for headless
    /// work, off with a window, where the viewer's frame rate would pay for it).
    pub sample_shading: Option<bool>,
    /// Pictures read back are drawn at this many times their size each way and
    /// averaged down (`frame::supersample`), 1..=4 (`None`: 1). Reduced where the
    /// device or the memory budget cannot hold the larger frame.
    pub supersample: Option<u32>,
    /// Temporal anti-aliasing instead of multisampling (`frame::temporal`): frames are
    /// drawn with one sample a pixel at a jittered position and averaged over time;
    /// `samples` must then be unset or 1.
    pub temporal: bool,
}

/// Frames' samples per pixel unless asked otherwise.
pub const DEFAULT_SAMPLES: u32 = 4;

/// The largest supersampling factor (16 times the pixels).
pub const MAX_SUPERSAMPLE: u32 = 4;

impl ContextOptions {
    /// Fills unset options from `SEDIMENT_DEVICE` and `SEDIMENT_VALIDATE=1`
    /// (`SEDIMENT_VALIDATE=sync` also checks synchronization).
    pub fn with_env(mut self) -> Self {
        let asked = std::env::var("SEDIMENT_VALIDATE").unwrap_or_default();
        if self.device.is_none() {
            self.device = std::env::var("SEDIMENT_DEVICE")
                .ok()
                .filter(|s| !s.is_empty());
        }
        if !self.validate {
            self.validate = !asked.is_empty() && asked != "0";
        }
        if !self.sync_validation {
            self.sync_validation = asked == "sync";
        }
        self
    }
}

/// Names and numbers of the chosen device that reports and tests print.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// The device's `deviceName`.
    pub name: String,
    /// The driver's `driverName` (empty if the driver gives none).
    pub driver_name: String,
    /// The driver's `driverInfo`, usually its version.
    pub driver_info: String,
    /// Highest Vulkan version the device supports, "major.minor.patch".
    pub api_version: String,
    /// Nanoseconds per timestamp-query tick (`timestampPeriod`).
    pub timestamp_period_ns: f32,
    /// Largest width or height of a 2D image in pixels (`maxImageDimension2D`).
    pub max_image_dimension_2d: u32,
    /// Most vertices one geometry-shader invocation may emit.
    pub max_geometry_output_vertices: u32,
    /// Most output components, over all emitted vertices, of one geometry invocation.
    pub max_geometry_total_output_components: u32,
    /// The largest device-local memory heap, bytes (what GPU buffers are budgeted
    /// against).
    pub device_heap_bytes: u64,
    /// Most texels one texel-buffer view may address (`maxTexelBufferElements`).
    pub max_texel_buffer_elements: u32,
}

/// Instance-level state shared by `Context::new` and `probe_devices`.
struct InstanceParts {
    entry: ash::Entry,
    instance: ash::Instance,
    debug_utils: Option<ash::ext::debug_utils::Instance>,
}

fn load_entry() -> Result<ash::Entry> {
    // SAFETY: loading the system Vulkan loader runs its initialisers; we do it once per
    // context and keep the `Entry` alive as long as anything created from it.
    unsafe { ash::Entry::load() }.map_err(|e| Error::NoLoader {
        detail: e.to_string(),
    })
}

/// Which validation the instance enables.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Validation {
    Off,
    On,
    /// With synchronization validation.
    Sync,
}

fn create_instance(
    validation: Validation,
    log: Option<&ValidationLog>,
    window: Option<raw_window_handle::RawDisplayHandle>,
) -> Result<InstanceParts> {
    let entry = load_entry()?;
    let window_extensions = match window {
        Some(display) => {
            ash_window::enumerate_required_extensions(display).map_err(|r| Error::NoWindow {
                detail: format!("the display's surface extensions are unknown to Vulkan ({r})"),
            })?
        }
        None => &[],
    };
    // SAFETY: plain enumeration on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .vk("vkEnumerateInstanceLayerProperties")?;
    let has_layer = layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
    let validate = validation != Validation::Off;
    if validate && !has_layer {
        return Err(Error::NoValidationLayer);
    }
    // The layer offers VK_EXT_validation_features, which carries the switch for
    // synchronization validation.
    if validation == Validation::Sync {
        // SAFETY: plain enumeration on a loaded entry, for a layer that is present.
        let layer_extensions =
            unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                .vk("vkEnumerateInstanceExtensionProperties (validation layer)")?;
        if !layer_extensions.iter().any(|e| {
            e.extension_name_as_c_str()
                .is_ok_and(|n| n == ash::ext::validation_features::NAME)
        }) {
            return Err(Error::NoValidationLayer);
        }
    }
    // SAFETY: plain enumeration on a loaded entry.
    let extensions =
        unsafe { entry.enumerate_instance_extension_properties(None) }.map_err(|result| {
            Error::NoDriver {
                detail: format!("vkEnumerateInstanceExtensionProperties returned {result}"),
            }
        })?;
    let has_debug_utils = extensions.iter().any(|e| {
        e.extension_name_as_c_str()
            .is_ok_and(|n| n == ash::ext::debug_utils::NAME)
    });

    let app_name = c"sediment";
    let app = vk::ApplicationInfo::default()
        .application_name(app_name)
        .application_version(1)
        .engine_name(app_name)
        .api_version(features::REQUIRED_API);
    let layer_names: Vec<*const c_char> = if validate {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        Vec::new()
    };
    let mut extension_names: Vec<*const c_char> = if has_debug_utils {
        vec![ash::ext::debug_utils::NAME.as_ptr()]
    } else {
        Vec::new()
    };
    if validation == Validation::Sync {
        extension_names.push(ash::ext::validation_features::NAME.as_ptr());
    }
    let sync_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut features =
        vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync_features);
    for &wanted in window_extensions {
        // SAFETY: ash-window returns pointers to static NUL-terminated extension names.
        let name = unsafe { CStr::from_ptr(wanted) };
        if !extensions
            .iter()
            .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
        {
            return Err(Error::NoWindow {
                detail: format!(
                    "the Vulkan driver lacks the instance extension {}",
                    name.to_string_lossy()
                ),
            });
        }
        extension_names.push(wanted);
    }
    let mut messenger_info = log.map(validation::messenger_info);
    let mut info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layer_names)
        .enabled_extension_names(&extension_names);
    // Chaining the messenger into instance creation also reports errors from
    // vkCreateInstance/vkDestroyInstance themselves.
    if let (Some(m), true) = (messenger_info.as_mut(), has_debug_utils) {
        info = info.push_next(m);
    }
    if validation == Validation::Sync {
        info = info.push_next(&mut features);
    }
    // SAFETY: every pointer in `info` refers to locals that outlive the call.
    let instance =
        unsafe { entry.create_instance(&info, None) }.map_err(|result| Error::NoDriver {
            detail: format!("vkCreateInstance returned {result:?}"),
        })?;
    let debug_utils =
        has_debug_utils.then(|| ash::ext::debug_utils::Instance::new(&entry, &instance));
    Ok(InstanceParts {
        entry,
        instance,
        debug_utils,
    })
}

fn physical_devices(instance: &ash::Instance) -> Result<Vec<vk::PhysicalDevice>> {
    // SAFETY: enumeration on a live instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.map_err(|result| Error::NoDriver {
            detail: format!("vkEnumeratePhysicalDevices returned {result:?}"),
        })?;
    if devices.is_empty() {
        return Err(Error::NoDriver {
            detail: "the loader found no Vulkan device".to_owned(),
        });
    }
    Ok(devices)
}

/// Reports every device the loader sees, for `sediment info`. Needs no feature.
pub fn probe_devices() -> Result<Vec<DeviceReport>> {
    let parts = create_instance(Validation::Off, None, None)?;
    let result = physical_devices(&parts.instance).map(|devices| {
        devices
            .into_iter()
            .map(|pd| features::probe(&parts.instance, pd))
            .collect()
    });
    // SAFETY: nothing created from the instance outlives this function.
    unsafe { parts.instance.destroy_instance(None) };
    result
}

/// The device and everything that lives as long as it. Shared as `Arc<Context>`;
/// every owning wrapper holds one and frees itself in `Drop`.
pub struct Context {
    /// What every frame is drawn into (its samples are `ContextOptions::samples`).
    frame_format: super::TargetFormat,
    /// `ContextOptions::sample_shading`, resolved.
    sample_shading: bool,
    /// `ContextOptions::supersample`, resolved (1 under temporal anti-aliasing).
    supersample: u32,
    /// `ContextOptions::temporal`.
    temporal: bool,
    /// Pipelines created on this device so far (`pipelines_created`).
    pipelines: AtomicU64,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: Mutex<vk::CommandPool>,
    pub(crate) xfb: ash::ext::transform_feedback::Device,
    debug_device: Option<ash::ext::debug_utils::Device>,
    pub(crate) device: ash::Device,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_family: u32,
    pub(crate) physical: vk::PhysicalDevice,
    info: DeviceInfo,
    messenger: Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    pub(crate) instance: ash::Instance,
    pub(crate) entry: ash::Entry,
    // Boxed so its address, handed to the messenger callback, never moves; dropped last.
    validation_log: Box<ValidationLog>,
}

impl Context {
    /// Loads Vulkan, picks a device that has everything sediment needs and creates it.
    /// On a CPU device (lavapipe) the process keeps the memory the driver frees
    /// (`heap::keep_freed_memory`): its per-draw buffers otherwise page-fault in again
    /// every frame.
    pub fn new(options: &ContextOptions) -> Result<Arc<Self>> {
        let log = Box::<ValidationLog>::default();
        let validation = match (options.validate, options.sync_validation) {
            (false, _) => Validation::Off,
            (true, false) => Validation::On,
            (true, true) => Validation::Sync,
        };
        let parts = create_instance(
            validation,
            options.validate.then_some(&*log),
            options.window,
        )?;
        match Self::with_instance(options, log, parts) {
            Ok(ctx) => Ok(Arc::new(ctx)),
            Err((e, parts)) => {
                if let Some(parts) = parts {
                    // SAFETY: device creation failed, so nothing else uses the instance.
                    unsafe { parts.instance.destroy_instance(None) };
                }
                Err(e)
            }
        }
    }

    #[allow(
        clippy::result_large_err,
        reason = "the instance is handed back for cleanup"
    )]
    fn with_instance(
        options: &ContextOptions,
        validation_log: Box<ValidationLog>,
        parts: InstanceParts,
    ) -> std::result::Result<Self, (Error, Option<InstanceParts>)> {
        let (physical, report) = match choose_device(&parts.instance, options.device.as_deref()) {
            Ok(found) => found,
            Err(e) => return Err((e, Some(parts))),
        };
        // SAFETY: `physical` came from this instance.
        let properties = unsafe { parts.instance.get_physical_device_properties(physical) };
        let limits = properties.limits;
        if properties.device_type == vk::PhysicalDeviceType::CPU {
            super::heap::keep_freed_memory();
        }
        if options.temporal && options.samples.is_some_and(|n| n != 1) {
            return Err((
                Error::invalid(
                    "--samples",
                    "temporal anti-aliasing draws one sample a pixel: give --samples only \
                     with --anti-aliasing multisample",
                ),
                Some(parts),
            ));
        }
        let samples = if options.temporal {
            Some(1)
        } else {
            options.samples
        };
        let frame_format = match frame_format(samples, &limits) {
            Ok(f) => f,
            Err(e) => return Err((e, Some(parts))),
        };
        let Some((queue_family, _)) = features::graphics_queue_family(&parts.instance, physical)
        else {
            return Err((
                Error::MissingFeature {
                    device: report.name,
                    feature: "graphics+compute queue",
                    why: "every pass is submitted to one such queue",
                },
                Some(parts),
            ));
        };

        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut device_extensions = vec![ash::ext::transform_feedback::NAME.as_ptr()];
        if options.window.is_some() {
            device_extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        // SAFETY: `physical` came from this instance.
        let supported = unsafe { parts.instance.get_physical_device_features(physical) };
        // Optional: without it the speleothems are shaded once per pixel.
        let sample_rate_shading = supported.sample_rate_shading == vk::TRUE;
        let core = vk::PhysicalDeviceFeatures::default()
            .geometry_shader(true)
            .sample_rate_shading(sample_rate_shading);
        // maintenance4 (required of every 1.3 device) lets a vertex stage write outputs
        // that only the geometry stage of another pipeline reads, as the speleothems'
        // surface.vert does for cap.geom, without validation calling it a mismatch.
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(true);
        let mut xfb =
            vk::PhysicalDeviceTransformFeedbackFeaturesEXT::default().transform_feedback(true);
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&device_extensions)
            .enabled_features(&core)
            .push_next(&mut f13)
            .push_next(&mut xfb);
        // SAFETY: the device was checked to support every enabled feature/extension and
        // all pointers in `device_info` refer to locals alive for the call.
        let device = match unsafe { parts.instance.create_device(physical, &device_info, None) } {
            Ok(d) => d,
            Err(vk::Result::ERROR_EXTENSION_NOT_PRESENT) if options.window.is_some() => {
                let detail = format!(
                    "the device \"{}\" cannot present (no VK_KHR_swapchain)",
                    report.name
                );
                return Err((Error::NoWindow { detail }, Some(parts)));
            }
            Err(result) => {
                return Err((
                    Error::Vulkan {
                        call: "vkCreateDevice",
                        result,
                    },
                    Some(parts),
                ));
            }
        };
        let cleanup = |device: &ash::Device, e: Error, parts: InstanceParts| {
            // SAFETY: nothing created from the device is alive yet.
            unsafe { device.destroy_device(None) };
            Err((e, Some(parts)))
        };

        // SAFETY: queue 0 of the family was requested at device creation.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let xfb_device = ash::ext::transform_feedback::Device::new(&parts.instance, &device);
        let debug_device = parts
            .debug_utils
            .as_ref()
            .map(|_| ash::ext::debug_utils::Device::new(&parts.instance, &device));

        let messenger = match (&parts.debug_utils, options.validate) {
            (Some(du), true) => {
                let info = validation::messenger_info(&validation_log);
                // SAFETY: the log is boxed and outlives the messenger (see Drop).
                match unsafe { du.create_debug_utils_messenger(&info, None) } {
                    Ok(m) => Some((du.clone(), m)),
                    Err(result) => {
                        let e = Error::Vulkan {
                            call: "vkCreateDebugUtilsMessengerEXT",
                            result,
                        };
                        return cleanup(&device, e, parts);
                    }
                }
            }
            _ => None,
        };

        let allocator = match Allocator::new(&AllocatorCreateDesc {
            instance: parts.instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        }) {
            Ok(a) => a,
            Err(source) => {
                let e = Error::Allocation {
                    name: "allocator".to_owned(),
                    bytes: 0,
                    source,
                };
                return cleanup(&device, e, parts);
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid device and create info.
        let command_pool = match unsafe { device.create_command_pool(&pool_info, None) } {
            Ok(p) => p,
            Err(result) => {
                drop(allocator);
                let e = Error::Vulkan {
                    call: "vkCreateCommandPool",
                    result,
                };
                return cleanup(&device, e, parts);
            }
        };

        // SAFETY: `physical` came from this instance.
        let props = unsafe { parts.instance.get_physical_device_properties(physical) };
        // SAFETY: `physical` came from this instance.
        let memory = unsafe {
            parts
                .instance
                .get_physical_device_memory_properties(physical)
        };
        let device_heap_bytes = memory.memory_heaps[..memory.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0);
        let info = DeviceInfo {
            name: report.name,
            driver_name: report.driver_name,
            driver_info: report.driver_info,
            api_version: report.api_version,
            timestamp_period_ns: props.limits.timestamp_period,
            max_image_dimension_2d: props.limits.max_image_dimension2_d,
            max_geometry_output_vertices: props.limits.max_geometry_output_vertices,
            max_geometry_total_output_components: props.limits.max_geometry_total_output_components,
            device_heap_bytes,
            max_texel_buffer_elements: props.limits.max_texel_buffer_elements,
        };
        log::debug!(
            "device: {} ({}, Vulkan {}), {} MiB device heap, {} samples a pixel{}",
            info.name,
            info.driver_info,
            info.api_version,
            info.device_heap_bytes >> 20,
            frame_format.samples.as_raw(),
            if options.validate {
                ", validation on"
            } else {
                ""
            }
        );
        let ctx = Context {
            frame_format,
            sample_shading: sample_rate_shading
                && options.sample_shading.unwrap_or(options.window.is_none()),
            supersample: if options.temporal {
                1
            } else {
                options.supersample.unwrap_or(1).clamp(1, MAX_SUPERSAMPLE)
            },
            temporal: options.temporal,
            pipelines: AtomicU64::new(0),
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            command_pool: Mutex::new(command_pool),
            xfb: xfb_device,
            debug_device,
            device,
            queue,
            queue_family,
            physical,
            info,
            messenger,
            instance: parts.instance,
            entry: parts.entry,
            validation_log,
        };
        ctx.name(ctx.queue, "sediment queue");
        ctx.name(command_pool, "sediment command pool");
        Ok(ctx)
    }

    /// The chosen device's names and limits.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The format, depth and samples of every frame drawn on this context.
    pub fn frame_format(&self) -> super::TargetFormat {
        self.frame_format
    }

    /// Whether surfaces with sub-pixel detail shade every sample of a multisampled
    /// frame (`ContextOptions::sample_shading`; false for single-sample frames and on
    /// devices without `sampleRateShading`).
    pub fn sample_shading(&self) -> bool {
        self.sample_shading && self.frame_format.samples != vk::SampleCountFlags::TYPE_1
    }

    /// How many times its size each way a picture read back is drawn at
    /// (`ContextOptions::supersample`), before `frame::supersample::factor_for` fits it
    /// to the device.
    pub fn supersample(&self) -> u32 {
        self.supersample
    }

    /// Whether frames are anti-aliased over time (`ContextOptions::temporal`) rather
    /// than by multisampling.
    pub fn temporal(&self) -> bool {
        self.temporal
    }

    /// Whether validation is on for this context.
    pub fn validating(&self) -> bool {
        self.messenger.is_some()
    }

    /// Removes and returns the validation errors recorded since the last call.
    pub fn take_validation_errors(&self) -> Vec<String> {
        self.validation_log.take_errors()
    }

    /// How many validation errors are waiting.
    pub fn validation_error_count(&self) -> usize {
        self.validation_log.error_count()
    }

    /// How many graphics and compute pipelines have been created on this device: each
    /// is a shader compilation on lavapipe, so what should reuse pipelines (a moved
    /// sun) is held to creating none.
    pub fn pipelines_created(&self) -> u64 {
        self.pipelines.load(Ordering::Relaxed)
    }

    pub(crate) fn count_pipeline(&self) {
        self.pipelines.fetch_add(1, Ordering::Relaxed);
    }

    pub(crate) fn allocator(&self) -> MutexGuard<'_, Allocator> {
        // A panic while holding the lock cannot leave the allocator's books half-written
        // in a way that matters more than the panic itself; keep going with its state.
        match self.allocator.lock() {
            Ok(a) => a,
            Err(poisoned) => poisoned.into_inner(),
        }
    }

    /// Gives a Vulkan object a debug name (shown by validation messages and tools).
    pub(crate) fn name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(du) = &self.debug_device else { return };
        let Ok(cname) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&cname);
        // SAFETY: the handle belongs to this device; naming is advisory, so a failure is
        // ignored on purpose.
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }

    /// Records commands with `record`, submits them and waits for the GPU to finish.
    pub fn submit_and_wait(
        &self,
        label: &str,
        record: impl FnOnce(&Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        self.submit_and_wait_with(label, &[], &[], record)
    }

    /// `submit_and_wait` whose submission also waits on `waits` (each at its stage) and
    /// signals `signals`.
    pub(crate) fn submit_and_wait_with(
        &self,
        label: &str,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
        record: impl FnOnce(&Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        let pool = match self.command_pool.lock() {
            Ok(p) => p,
            Err(poisoned) => poisoned.into_inner(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool is locked for the whole recording and submission.
        let cmd = unsafe { self.device.allocate_command_buffers(&alloc) }
            .vk("vkAllocateCommandBuffers")?[0];
        self.name(cmd, label);
        let result = self.record_submit_wait(cmd, waits, signals, record);
        // SAFETY: the submission has completed (or never happened) by now.
        unsafe { self.device.free_command_buffers(*pool, &[cmd]) };
        result
    }

    fn record_submit_wait(
        &self,
        cmd: vk::CommandBuffer,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signals: &[vk::Semaphore],
        record: impl FnOnce(&Commands<'_>) -> Result<()>,
    ) -> Result<()> {
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: freshly allocated command buffer.
        unsafe { self.device.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        record(&Commands {
            ctx: self,
            raw: cmd,
        })?;
        // SAFETY: recording started above.
        unsafe { self.device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        // SAFETY: valid device.
        let fence = unsafe {
            self.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .vk("vkCreateFence")?;
        let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
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
        // SAFETY: the command buffer is fully recorded and the fence unsignalled.
        let submitted =
            unsafe { self.device.queue_submit2(self.queue, &submit, fence) }.vk("vkQueueSubmit2");
        let waited = submitted.and_then(|()| {
            // SAFETY: waits on our own fence.
            unsafe { self.device.wait_for_fences(&[fence], true, u64::MAX) }.vk("vkWaitForFences")
        });
        // SAFETY: the fence is signalled or was never submitted.
        unsafe { self.device.destroy_fence(fence, None) };
        waited
    }

    /// Blocks until the device is idle (used before tearing things down).
    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: valid device.
        unsafe { self.device.device_wait_idle() }.vk("vkDeviceWaitIdle")
    }
}

/// The frame format with `samples` per pixel, if the device renders colour and depth
/// with that many.
fn frame_format(
    samples: Option<u32>,
    limits: &vk::PhysicalDeviceLimits,
) -> Result<super::TargetFormat> {
    let n = samples.unwrap_or(DEFAULT_SAMPLES);
    let flag = vk::SampleCountFlags::from_raw(n);
    let supported = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    if !n.is_power_of_two() || n > 64 || !supported.contains(flag) {
        let counts: Vec<String> = (0..7)
            .map(|k| 1u32 << k)
            .filter(|&k| supported.contains(vk::SampleCountFlags::from_raw(k)))
            .map(|k| k.to_string())
            .collect();
        return Err(Error::invalid(
            "--samples",
            format!(
                "{n} samples per pixel: this device renders {}",
                counts.join(", ")
            ),
        ));
    }
    Ok(super::TargetFormat {
        samples: flag,
        ..super::TargetFormat::FRAME
    })
}

fn choose_device(
    instance: &ash::Instance,
    wanted: Option<&str>,
) -> Result<(vk::PhysicalDevice, DeviceReport)> {
    let mut candidates: Vec<(vk::PhysicalDevice, DeviceReport, u32)> = physical_devices(instance)?
        .into_iter()
        .map(|pd| {
            // SAFETY: `pd` came from this instance.
            let props = unsafe { instance.get_physical_device_properties(pd) };
            (
                pd,
                features::probe(instance, pd),
                features::preference(props.device_type),
            )
        })
        .collect();
    if let Some(wanted) = wanted {
        let available = candidates
            .iter()
            .map(|c| format!("\"{}\"", c.1.name))
            .collect::<Vec<_>>()
            .join(", ");
        let needle = wanted.to_lowercase();
        candidates.retain(|c| c.1.name.to_lowercase().contains(&needle));
        if candidates.is_empty() {
            return Err(Error::NoMatchingDevice {
                wanted: wanted.to_owned(),
                available,
            });
        }
    }
    candidates.sort_by_key(|c| c.2);
    if let Some(i) = candidates
        .iter()
        .position(|c| c.1.first_missing().is_none())
    {
        let (pd, report, _) = candidates.swap_remove(i);
        return Ok((pd, report));
    }
    // No device has everything: name what the most preferred one lacks.
    let (_, report, _) = candidates.swap_remove(0);
    let missing = report
        .first_missing()
        .map(|c| (c.name, c.why))
        .unwrap_or(("an unknown feature", ""));
    Err(Error::MissingFeature {
        device: report.name,
        feature: missing.0,
        why: missing.1,
    })
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every wrapper holding an `Arc<Context>` has been dropped, so the device
        // has no live children other than the pool and the allocator's memory.
        unsafe {
            let _ = self.device.device_wait_idle();
            let pool = match self.command_pool.lock() {
                Ok(p) => *p,
                Err(poisoned) => *poisoned.into_inner(),
            };
            self.device.destroy_command_pool(pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((du, messenger)) = self.messenger.take() {
                du.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

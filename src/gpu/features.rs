//! What a physical device offers, against what sediment needs: checked up front so a
//! missing feature is named in the error instead of surfacing later as a Vulkan code.

use std::ffi::CStr;

use ash::vk;

/// One capability sediment relies on (or reports), as read from a device.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Capability {
    /// The Vulkan name (feature, property or limit).
    pub name: &'static str,
    /// Why sediment needs it.
    pub why: &'static str,
    /// Whether the device meets the requirement.
    pub present: bool,
    /// The value as the device reports it.
    pub value: String,
    /// Required capabilities make device creation fail when absent.
    pub required: bool,
}

/// Everything `sediment info` shows about one device (`--json`: these fields, and
/// `usable`).
#[derive(Clone, Debug, serde::Serialize)]
pub struct DeviceReport {
    /// `deviceName` from the device properties (`<unnamed device>` if unreadable).
    pub name: String,
    /// Kind of device in words: "discrete GPU", "integrated GPU", "CPU (software)"...
    pub device_type: String,
    /// `driverName` from `VkPhysicalDeviceDriverProperties` (empty if unreadable).
    pub driver_name: String,
    /// `driverInfo` from `VkPhysicalDeviceDriverProperties`, usually the driver version.
    pub driver_info: String,
    /// Highest Vulkan version the device supports, as "major.minor.patch".
    pub api_version: String,
    /// Every required and reported capability, in a fixed order.
    pub capabilities: Vec<Capability>,
}

impl DeviceReport {
    /// The first required capability the device lacks, if any.
    pub fn first_missing(&self) -> Option<&Capability> {
        self.capabilities.iter().find(|c| c.required && !c.present)
    }
}

/// Vulkan 1.3: dynamic rendering and synchronization2 are core there.
pub(crate) const REQUIRED_API: u32 = vk::API_VERSION_1_3;

pub(crate) fn device_type_name(t: vk::PhysicalDeviceType) -> &'static str {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
        vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
        vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
        vk::PhysicalDeviceType::CPU => "CPU (software)",
        _ => "other",
    }
}

/// Preference among devices that meet the requirements: real GPUs first, then software.
pub(crate) fn preference(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// The queue family sediment submits to: graphics + compute in one.
pub(crate) fn graphics_queue_family(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
) -> Option<(u32, vk::QueueFamilyProperties)> {
    // SAFETY: `physical` was enumerated from this live instance.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    families
        .into_iter()
        .enumerate()
        .find(|(_, f)| {
            f.queue_flags
                .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
        })
        .and_then(|(i, f)| Some((u32::try_from(i).ok()?, f)))
}

fn version_string(v: u32) -> String {
    format!(
        "{}.{}.{}",
        vk::api_version_major(v),
        vk::api_version_minor(v),
        vk::api_version_patch(v)
    )
}

fn has_extension(instance: &ash::Instance, physical: vk::PhysicalDevice, name: &CStr) -> bool {
    // SAFETY: `physical` was enumerated from this live instance.
    let extensions = unsafe { instance.enumerate_device_extension_properties(physical) };
    extensions
        .unwrap_or_default()
        .iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
}

/// Reads the device's properties and features and lays them against sediment's needs.
pub(crate) fn probe(instance: &ash::Instance, physical: vk::PhysicalDevice) -> DeviceReport {
    let xfb_ext = has_extension(instance, physical, ash::ext::transform_feedback::NAME);

    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut xfb_props = vk::PhysicalDeviceTransformFeedbackPropertiesEXT::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    if xfb_ext {
        props2 = props2.push_next(&mut xfb_props);
    }
    // SAFETY: the chained structs live until the call returns; the xfb struct is only
    // chained when the device exposes the extension.
    unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
    let props = props2.properties;

    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut xfb_feat = vk::PhysicalDeviceTransformFeedbackFeaturesEXT::default();
    let mut feats2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
    if xfb_ext {
        feats2 = feats2.push_next(&mut xfb_feat);
    }
    // SAFETY: as above, every chained struct outlives the call.
    unsafe { instance.get_physical_device_features2(physical, &mut feats2) };
    let feats = feats2.features;

    let queue = graphics_queue_family(instance, physical);
    let timestamp_bits = queue.map(|(_, f)| f.timestamp_valid_bits).unwrap_or(0);
    let name = props
        .device_name_as_c_str()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|_| "<unnamed device>".to_owned());
    let limits = props.limits;
    let yes = |b: bool| if b { "yes" } else { "no" }.to_owned();

    let required = |name, why, present: bool, value: String| Capability {
        name,
        why,
        present,
        value,
        required: true,
    };
    let reported = |name, why, value: String| Capability {
        name,
        why,
        present: true,
        value,
        required: false,
    };
    let capabilities = vec![
        required(
            "Vulkan 1.3",
            "dynamic rendering and synchronization2 are core in 1.3",
            props.api_version >= REQUIRED_API,
            version_string(props.api_version),
        ),
        required(
            "graphics+compute queue",
            "every pass is submitted to one such queue",
            queue.is_some(),
            yes(queue.is_some()),
        ),
        required(
            "dynamicRendering",
            "offscreen passes render without render-pass objects",
            f13.dynamic_rendering == vk::TRUE,
            yes(f13.dynamic_rendering == vk::TRUE),
        ),
        required(
            "synchronization2",
            "barriers and submits use the 2-variants",
            f13.synchronization2 == vk::TRUE,
            yes(f13.synchronization2 == vk::TRUE),
        ),
        required(
            "VK_EXT_transform_feedback",
            "speleothem rings are captured by transform feedback",
            xfb_ext,
            yes(xfb_ext),
        ),
        required(
            "geometryShader",
            "the ring-growth pass amplifies rings in a geometry shader",
            feats.geometry_shader == vk::TRUE,
            yes(feats.geometry_shader == vk::TRUE),
        ),
        reported(
            "sampleRateShading",
            "pictures' speleothems shaded once per sample (without it: once per pixel)",
            yes(feats.sample_rate_shading == vk::TRUE),
        ),
        required(
            "transformFeedback",
            "the grown mesh is streamed out and fed back",
            xfb_feat.transform_feedback == vk::TRUE,
            yes(xfb_feat.transform_feedback == vk::TRUE),
        ),
        required(
            "transformFeedbackDraw",
            "passes draw the captured mesh with vkCmdDrawIndirectByteCountEXT",
            xfb_props.transform_feedback_draw == vk::TRUE,
            yes(xfb_props.transform_feedback_draw == vk::TRUE),
        ),
        required(
            "transformFeedbackQueries",
            "overflowing capture buffers are detected by the stream query",
            xfb_props.transform_feedback_queries == vk::TRUE,
            yes(xfb_props.transform_feedback_queries == vk::TRUE),
        ),
        required(
            "timestamps",
            "GPU timings of every named pass",
            limits.timestamp_compute_and_graphics == vk::TRUE && timestamp_bits > 0,
            format!(
                "timestampComputeAndGraphics={}, {} valid bits, period {} ns",
                yes(limits.timestamp_compute_and_graphics == vk::TRUE),
                timestamp_bits,
                limits.timestamp_period
            ),
        ),
        reported(
            "maxGeometryOutputVertices",
            "vertices one geometry-shader invocation may emit",
            limits.max_geometry_output_vertices.to_string(),
        ),
        reported(
            "maxGeometryTotalOutputComponents",
            "components one geometry-shader invocation may emit (validation counts 4 per location plus gl_Position)",
            limits.max_geometry_total_output_components.to_string(),
        ),
        reported(
            "maxGeometryShaderInvocations",
            "instanced geometry-shader invocations per primitive",
            limits.max_geometry_shader_invocations.to_string(),
        ),
        reported(
            "maxTransformFeedbackBufferSize",
            "largest capture buffer",
            xfb_props.max_transform_feedback_buffer_size.to_string(),
        ),
        reported(
            "maxTransformFeedbackBufferDataStride",
            "largest captured vertex stride in bytes",
            xfb_props
                .max_transform_feedback_buffer_data_stride
                .to_string(),
        ),
        reported(
            "transformFeedbackStreamsLinesTriangles",
            "triangles on streams other than 0 (sediment captures on stream 0 only)",
            yes(xfb_props.transform_feedback_streams_lines_triangles == vk::TRUE),
        ),
        reported(
            "maxPushConstantsSize",
            "bytes of push constants per pipeline",
            limits.max_push_constants_size.to_string(),
        ),
        reported(
            "maxImageDimension2D",
            "largest --size",
            limits.max_image_dimension2_d.to_string(),
        ),
        reported(
            "maxTexelBufferElements",
            "the compute growth path reads its mesh as texels: 3 a vertex",
            limits.max_texel_buffer_elements.to_string(),
        ),
    ];

    DeviceReport {
        name,
        device_type: device_type_name(props.device_type).to_owned(),
        driver_name: driver
            .driver_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        driver_info: driver
            .driver_info_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
        api_version: version_string(props.api_version),
        capabilities,
    }
}

//! Pipeline layouts built from the Rust-side shader interfaces, descriptor sets, and a
//! graphics-pipeline builder that takes an optional geometry stage and rasterizer
//! discard (for transform-feedback-only passes). Compute pipelines too.

use std::collections::BTreeMap;
use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::shader::{ShaderModule, descriptor_type, stage_flags};
use super::{Buffer, Context};
use crate::error::{Error, Result, VkContext};
use crate::shaders::{DescriptorKind, ShaderInterface, ShaderSpirv};

const ENTRY: &CStr = c"main";

/// One descriptor-set layout: its set index, handle, (binding, kind) list and the
/// names its modules give the bindings.
struct SetLayout {
    set: u32,
    raw: vk::DescriptorSetLayout,
    bindings: Vec<(u32, DescriptorKind)>,
    names: Vec<(String, u32)>,
}

/// Descriptor-set layouts and push-constant range derived from the interfaces of every
/// module of one pipeline (the declarations `shaders::check_interface` tests).
pub struct PipelineLayout {
    raw: vk::PipelineLayout,
    set_layouts: Vec<SetLayout>,
    push_constant_bytes: u32,
    push_stages: vk::ShaderStageFlags,
    ctx: Arc<Context>,
}

impl PipelineLayout {
    /// Merges the interfaces of a pipeline's modules into one set layout per set index
    /// (0 to the highest used, gaps left empty) and one push-constant range over the
    /// stages that push; fails if two stages give one binding different kinds.
    pub fn new(ctx: &Arc<Context>, name: &str, interfaces: &[&ShaderInterface]) -> Result<Self> {
        // set -> binding -> (kind, stages)
        let mut sets: BTreeMap<u32, BTreeMap<u32, (DescriptorKind, vk::ShaderStageFlags)>> =
            BTreeMap::new();
        let mut push_constant_bytes = 0;
        let mut push_stages = vk::ShaderStageFlags::empty();
        // set -> (name, binding), from the modules naga reads.
        let mut names: BTreeMap<u32, Vec<(String, u32)>> = BTreeMap::new();
        for iface in interfaces {
            for named in crate::shaders::binding_names(iface.shader) {
                let list = names.entry(named.set).or_default();
                if !list.contains(&(named.name.clone(), named.binding)) {
                    list.push((named.name, named.binding));
                }
            }
            let stage = stage_flags(iface.shader.stage);
            for b in iface.bindings {
                let entry = sets
                    .entry(b.set)
                    .or_default()
                    .entry(b.binding)
                    .or_insert((b.kind, vk::ShaderStageFlags::empty()));
                if entry.0 != b.kind {
                    return Err(Error::Shader {
                        path: iface.shader.path.to_owned(),
                        message: format!(
                            "set {} binding {} is {:?} here but {:?} in another stage of {name}",
                            b.set, b.binding, b.kind, entry.0
                        ),
                    });
                }
                entry.1 |= stage;
            }
            if iface.push_constant_bytes > 0 {
                push_constant_bytes = push_constant_bytes.max(iface.push_constant_bytes);
                push_stages |= stage;
            }
        }
        let mut layout = PipelineLayout {
            raw: vk::PipelineLayout::null(),
            set_layouts: Vec::new(),
            push_constant_bytes,
            push_stages,
            ctx: ctx.clone(),
        };
        let max_set = sets.keys().next_back().copied();
        for set in 0..max_set.map_or(0, |m| m + 1) {
            let bindings = sets.get(&set).cloned().unwrap_or_default();
            let vk_bindings: Vec<vk::DescriptorSetLayoutBinding<'_>> = bindings
                .iter()
                .map(|(&binding, &(kind, stages))| {
                    vk::DescriptorSetLayoutBinding::default()
                        .binding(binding)
                        .descriptor_type(descriptor_type(kind))
                        .descriptor_count(1)
                        .stage_flags(stages)
                })
                .collect();
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&vk_bindings);
            // SAFETY: valid device and create info.
            let raw = unsafe { ctx.device.create_descriptor_set_layout(&info, None) }
                .vk("vkCreateDescriptorSetLayout")?;
            ctx.name(raw, &format!("{name} set {set}"));
            layout.set_layouts.push(SetLayout {
                set,
                raw,
                bindings: bindings.iter().map(|(&b, &(k, _))| (b, k)).collect(),
                names: names.remove(&set).unwrap_or_default(),
            });
        }
        let raw_sets: Vec<vk::DescriptorSetLayout> =
            layout.set_layouts.iter().map(|s| s.raw).collect();
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_constant_bytes)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&raw_sets)
            .push_constant_ranges(if push_constant_bytes > 0 {
                &ranges
            } else {
                &[]
            });
        // SAFETY: the set layouts are alive; create info is valid.
        layout.raw = unsafe { ctx.device.create_pipeline_layout(&info, None) }
            .vk("vkCreatePipelineLayout")?;
        ctx.name(layout.raw, name);
        Ok(layout)
    }

    /// The `vk::PipelineLayout` handle; owned by `self` and destroyed on drop.
    pub fn raw(&self) -> vk::PipelineLayout {
        self.raw
    }

    /// Size in bytes of the push-constant range: the largest any stage declared (0: none).
    pub fn push_constant_bytes(&self) -> u32 {
        self.push_constant_bytes
    }

    /// Records `vkCmdPushConstants` for the whole declared block.
    pub fn push<T: super::Pod>(&self, cmd: vk::CommandBuffer, value: &T) -> Result<()> {
        let bytes = super::as_bytes(std::slice::from_ref(value));
        if bytes.len() as u32 != self.push_constant_bytes {
            return Err(Error::internal(
                "push constants",
                format!(
                    "{} bytes pushed but the layout declares {}",
                    bytes.len(),
                    self.push_constant_bytes
                ),
            ));
        }
        // SAFETY: `cmd` is recording and the range matches the layout's.
        unsafe {
            self.ctx
                .device
                .cmd_push_constants(cmd, self.raw, self.push_stages, 0, bytes)
        };
        Ok(())
    }

    /// Allocates descriptor set `set` of this layout from a pool of its own.
    pub fn allocate_set(&self, name: &str, set: u32) -> Result<DescriptorSet> {
        let Some(SetLayout {
            raw: raw_layout,
            bindings,
            names,
            ..
        }) = self.set_layouts.iter().find(|s| s.set == set)
        else {
            return Err(Error::internal(
                "descriptor set",
                format!("the layout has no set {set}"),
            ));
        };
        let mut counts: BTreeMap<i32, u32> = BTreeMap::new();
        for (_, kind) in bindings {
            *counts.entry(descriptor_type(*kind).as_raw()).or_default() += 1;
        }
        let sizes: Vec<vk::DescriptorPoolSize> = counts
            .into_iter()
            .map(|(ty, n)| vk::DescriptorPoolSize {
                ty: vk::DescriptorType::from_raw(ty),
                descriptor_count: n,
            })
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        // SAFETY: valid device and create info.
        let pool = unsafe { self.ctx.device.create_descriptor_pool(&info, None) }
            .vk("vkCreateDescriptorPool")?;
        let layouts = [*raw_layout];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        // SAFETY: the pool was sized for exactly this layout.
        let raw = match unsafe { self.ctx.device.allocate_descriptor_sets(&alloc) } {
            Ok(sets) => sets[0],
            Err(result) => {
                // SAFETY: the pool has no live sets.
                unsafe { self.ctx.device.destroy_descriptor_pool(pool, None) };
                return Err(Error::Vulkan {
                    call: "vkAllocateDescriptorSets",
                    result,
                });
            }
        };
        self.ctx.name(pool, &format!("{name} pool"));
        self.ctx.name(raw, name);
        Ok(DescriptorSet {
            raw,
            pool,
            set,
            bindings: bindings.clone(),
            names: names.clone(),
            ctx: self.ctx.clone(),
        })
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        // SAFETY: no pipeline using the layout is executing (submissions wait).
        unsafe {
            self.ctx.device.destroy_pipeline_layout(self.raw, None);
            for s in &self.set_layouts {
                self.ctx.device.destroy_descriptor_set_layout(s.raw, None);
            }
        }
    }
}

/// One descriptor set with the pool it came from.
pub struct DescriptorSet {
    raw: vk::DescriptorSet,
    pool: vk::DescriptorPool,
    set: u32,
    bindings: Vec<(u32, DescriptorKind)>,
    /// (name, binding) as the modules' SPIR-V names them (`shaders::binding_names`).
    names: Vec<(String, u32)>,
    ctx: Arc<Context>,
}

/// What a descriptor points at, for [`DescriptorSet::write`].
#[derive(Clone, Copy)]
pub enum Descriptor<'a> {
    /// The whole of a uniform or storage buffer.
    Buffer(&'a Buffer),
    /// A uniform texel buffer's view.
    TexelBuffer(&'a super::TexelView),
    /// An image's view, in the layout its binding reads it in: sampled colour
    /// SHADER_READ_ONLY_OPTIMAL, sampled depth DEPTH_READ_ONLY_OPTIMAL, storage
    /// GENERAL (what `Usage::SampledFragment`, `SampledDepthFragment` and the compute
    /// uses leave it in).
    Image(&'a super::Image),
    /// A sampler.
    Sampler(&'a super::Sampler),
}

impl DescriptorSet {
    /// The `vk::DescriptorSet` handle; freed with its pool when `self` drops.
    pub fn raw(&self) -> vk::DescriptorSet {
        self.raw
    }

    /// The binding the modules call `name`.
    pub fn binding(&self, name: &str) -> Result<u32> {
        let mut found = self
            .names
            .iter()
            .filter(|(n, _)| n == name)
            .map(|&(_, b)| b);
        match (found.next(), found.next()) {
            (Some(binding), None) => Ok(binding),
            (Some(a), Some(b)) => Err(Error::internal(
                "descriptor write",
                format!(
                    "set {} names bindings {a} and {b} \"{name}\" in different stages",
                    self.set
                ),
            )),
            (None, _) => {
                let known: Vec<&str> = self.names.iter().map(|(n, _)| n.as_str()).collect();
                Err(Error::internal(
                    "descriptor write",
                    format!(
                        "set {} has no binding named \"{name}\" (its modules name: {})",
                        self.set,
                        known.join(", ")
                    ),
                ))
            }
        }
    }

    /// Points the binding the shaders call `name` at `resource`, an image in the
    /// layout its binding's kind reads it in. Names come from the modules' SPIR-V,
    /// so a renamed or removed shader variable is an error here rather than a
    /// descriptor written to the wrong slot.
    pub fn write(&self, name: &str, resource: Descriptor<'_>) -> Result<()> {
        let binding = self.binding(name)?;
        match resource {
            Descriptor::Buffer(buffer) => self.write_buffer(binding, buffer),
            Descriptor::TexelBuffer(view) => self.write_texel_buffer(binding, view),
            Descriptor::Sampler(sampler) => self.write_sampler(binding, sampler),
            Descriptor::Image(image) => {
                let layout = match self.kind_of(binding)? {
                    DescriptorKind::StorageImage => vk::ImageLayout::GENERAL,
                    _ if image.desc().aspect() == vk::ImageAspectFlags::DEPTH => {
                        vk::ImageLayout::DEPTH_READ_ONLY_OPTIMAL
                    }
                    _ => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                };
                self.write_image(binding, image.view(), layout)
            }
        }
    }

    fn kind_of(&self, binding: u32) -> Result<DescriptorKind> {
        self.bindings
            .iter()
            .find(|b| b.0 == binding)
            .map(|b| b.1)
            .ok_or_else(|| {
                Error::internal(
                    "descriptor write",
                    format!("set {} has no binding {binding}", self.set),
                )
            })
    }

    /// Points a uniform or storage buffer binding at the whole of `buffer`.
    pub fn write_buffer(&self, binding: u32, buffer: &Buffer) -> Result<()> {
        let kind = self.kind_of(binding)?;
        let info = [vk::DescriptorBufferInfo {
            buffer: buffer.raw(),
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(self.raw)
            .dst_binding(binding)
            .descriptor_type(descriptor_type(kind))
            .buffer_info(&info)];
        // SAFETY: the set is not in use by the GPU while it is updated.
        unsafe { self.ctx.device.update_descriptor_sets(&write, &[]) };
        Ok(())
    }

    /// Points a uniform texel buffer binding at `view`.
    pub fn write_texel_buffer(&self, binding: u32, view: &super::TexelView) -> Result<()> {
        let kind = self.kind_of(binding)?;
        let views = [view.raw()];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(self.raw)
            .dst_binding(binding)
            .descriptor_type(descriptor_type(kind))
            .descriptor_count(1)
            .texel_buffer_view(&views)];
        // SAFETY: the set is not in use by the GPU while it is updated; the view
        // outlives the writes that read it (its owner keeps it beside the set).
        unsafe { self.ctx.device.update_descriptor_sets(&write, &[]) };
        Ok(())
    }

    /// Points a sampled or storage image binding at `view` in `layout`.
    pub fn write_image(
        &self,
        binding: u32,
        view: vk::ImageView,
        layout: vk::ImageLayout,
    ) -> Result<()> {
        self.write_image_info(
            binding,
            vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: view,
                image_layout: layout,
            },
        )
    }

    /// Points a sampler binding at `sampler`.
    pub fn write_sampler(&self, binding: u32, sampler: &super::Sampler) -> Result<()> {
        self.write_image_info(
            binding,
            vk::DescriptorImageInfo {
                sampler: sampler.raw(),
                image_view: vk::ImageView::null(),
                image_layout: vk::ImageLayout::UNDEFINED,
            },
        )
    }

    /// One image-info descriptor (image or sampler) written to `binding`.
    fn write_image_info(&self, binding: u32, info: vk::DescriptorImageInfo) -> Result<()> {
        let kind = self.kind_of(binding)?;
        let info = [info];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(self.raw)
            .dst_binding(binding)
            .descriptor_type(descriptor_type(kind))
            .image_info(&info)];
        // SAFETY: the set is not in use by the GPU while it is updated.
        unsafe { self.ctx.device.update_descriptor_sets(&write, &[]) };
        Ok(())
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        // SAFETY: destroying the pool frees the set; the GPU is done with it.
        unsafe { self.ctx.device.destroy_descriptor_pool(self.pool, None) };
    }
}

/// Vertex input: one interleaved binding.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct VertexLayout {
    /// Bytes from one vertex to the next in binding 0 (per-vertex input rate).
    pub stride: u32,
    /// (location, format, byte offset)
    pub attributes: Vec<(u32, vk::Format, u32)>,
}

/// A graphics pipeline, described as plain data and built with `build`.
#[derive(Clone)]
pub struct GraphicsPipelineDesc<'a> {
    /// Debug-utils name given to the created `vk::Pipeline`.
    pub name: &'a str,
    /// Vertex-stage module (entry point `main`).
    pub vertex: &'a ShaderSpirv,
    /// Optional geometry-stage module, e.g. one that emits to XFB streams.
    pub geometry: Option<&'a ShaderSpirv>,
    /// Optional fragment-stage module; `None` for depth-only or XFB-only passes.
    pub fragment: Option<&'a ShaderSpirv>,
    /// Vertex input on binding 0; no attributes means no vertex input state at all.
    pub vertex_layout: VertexLayout,
    /// Primitive topology for input assembly (default triangle list).
    pub topology: vk::PrimitiveTopology,
    /// Faces culled by the rasterizer (default back faces).
    pub cull_mode: vk::CullModeFlags,
    /// Winding that counts as front-facing (default counter-clockwise).
    pub front_face: vk::FrontFace,
    /// Fill, line or point rasterization (default fill; line width is fixed at 1).
    pub polygon_mode: vk::PolygonMode,
    /// For transform-feedback-only passes: nothing is rasterized.
    pub rasterizer_discard: bool,
    /// Formats of the dynamic-rendering colour attachments, one blend state each.
    pub color_formats: Vec<vk::Format>,
    /// Format of the depth attachment, or `None` (which also disables depth test/write).
    pub depth_format: Option<vk::Format>,
    /// Depth test with `LESS_OR_EQUAL`; ignored without a depth format.
    pub depth_test: bool,
    /// Whether passing fragments write depth; ignored without a depth format.
    pub depth_write: bool,
    /// Straight-alpha "over" blending (`SRC_ALPHA`, `ONE_MINUS_SRC_ALPHA`) on every colour
    /// attachment; off writes RGBA unblended.
    pub alpha_blend: bool,
    /// Constant and slope depth bias (pushes filled faces back behind lines drawn
    /// over them), or none.
    pub depth_bias: Option<(f32, f32)>,
    /// Samples per pixel of the attachments drawn into.
    pub samples: vk::SampleCountFlags,
    /// Specialization constants of every stage as (`constant_id`, 32-bit value; a
    /// `bool` is 0 or 1); an id a stage does not declare leaves it alone. A pass's
    /// switches, fixed per pipeline: a CPU rasteriser runs both sides of a branch on a
    /// uniform, so a switch read from a uniform costs what it turns off.
    pub constants: Vec<(u32, u32)>,
}

impl<'a> GraphicsPipelineDesc<'a> {
    /// A triangle-list pipeline with back-face culling (counter-clockwise front faces)
    /// and depth testing, ready to be adjusted field by field or with the setters.
    pub fn new(name: &'a str, vertex: &'a ShaderSpirv) -> Self {
        Self {
            name,
            vertex,
            geometry: None,
            fragment: None,
            vertex_layout: VertexLayout::default(),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            cull_mode: vk::CullModeFlags::BACK,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            polygon_mode: vk::PolygonMode::FILL,
            rasterizer_discard: false,
            color_formats: Vec::new(),
            depth_format: None,
            depth_test: true,
            depth_write: true,
            alpha_blend: false,
            depth_bias: None,
            samples: vk::SampleCountFlags::TYPE_1,
            constants: Vec::new(),
        }
    }

    /// Adds a geometry stage (needs the device's `geometryShader` feature).
    pub fn geometry(mut self, shader: &'a ShaderSpirv) -> Self {
        self.geometry = Some(shader);
        self
    }

    /// Adds a fragment stage.
    pub fn fragment(mut self, shader: &'a ShaderSpirv) -> Self {
        self.fragment = Some(shader);
        self
    }

    /// Sets the vertex input read from binding 0.
    pub fn vertex_layout(mut self, layout: VertexLayout) -> Self {
        self.vertex_layout = layout;
        self
    }

    /// Sets the dynamic-rendering attachment formats; leaves the sample count alone.
    pub fn targets(mut self, color: &[vk::Format], depth: Option<vk::Format>) -> Self {
        self.color_formats = color.to_vec();
        self.depth_format = depth;
        self
    }

    /// Draws into an offscreen target of `format` (its colour, depth and samples).
    pub fn target(mut self, format: super::TargetFormat) -> Self {
        self.color_formats = vec![format.color];
        self.depth_format = Some(format.depth);
        self.samples = format.samples;
        self
    }

    /// Adds specialization constants (`constant_id`, value), e.g.
    /// `ToneMap::constants`.
    pub fn specialize(mut self, constants: &[(u32, u32)]) -> Self {
        self.constants.extend_from_slice(constants);
        self
    }

    /// Turns rasterization off (`on`) for passes whose only output is transform feedback.
    pub fn rasterizer_discard(mut self, on: bool) -> Self {
        self.rasterizer_discard = on;
        self
    }

    /// Creates the pipeline for dynamic rendering (no render pass) with dynamic viewport
    /// and scissor; the shader modules are created for the call and destroyed after it.
    /// `layout` should be built from the interfaces of these same modules.
    pub fn build(&self, ctx: &Arc<Context>, layout: &PipelineLayout) -> Result<Pipeline> {
        let mut modules = vec![ShaderModule::new(ctx, self.vertex)?];
        if let Some(g) = self.geometry {
            modules.push(ShaderModule::new(ctx, g)?);
        }
        if let Some(f) = self.fragment {
            modules.push(ShaderModule::new(ctx, f)?);
        }
        let constants = Specialization::new(&self.constants);
        let specialization = constants.info();
        let stages: Vec<vk::PipelineShaderStageCreateInfo<'_>> = modules
            .iter()
            .map(|m| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(m.stage())
                    .module(m.raw())
                    .name(ENTRY)
                    .specialization_info(&specialization)
            })
            .collect();
        let vl = &self.vertex_layout;
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: vl.stride,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes: Vec<vk::VertexInputAttributeDescription> = vl
            .attributes
            .iter()
            .map(
                |&(location, format, offset)| vk::VertexInputAttributeDescription {
                    location,
                    binding: 0,
                    format,
                    offset,
                },
            )
            .collect();
        let vertex_input = if vl.attributes.is_empty() {
            vk::PipelineVertexInputStateCreateInfo::default()
        } else {
            vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&bindings)
                .vertex_attribute_descriptions(&attributes)
        };
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(self.topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .rasterizer_discard_enable(self.rasterizer_discard)
            .polygon_mode(self.polygon_mode)
            .cull_mode(self.cull_mode)
            .front_face(self.front_face)
            .line_width(1.0)
            .depth_bias_enable(self.depth_bias.is_some())
            .depth_bias_constant_factor(self.depth_bias.map_or(0.0, |b| b.0))
            .depth_bias_slope_factor(self.depth_bias.map_or(0.0, |b| b.1));
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(self.samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(self.depth_test && self.depth_format.is_some())
            .depth_write_enable(self.depth_write && self.depth_format.is_some())
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
        let blend_attachments: Vec<vk::PipelineColorBlendAttachmentState> = self
            .color_formats
            .iter()
            .map(|_| {
                let state = vk::PipelineColorBlendAttachmentState::default()
                    .color_write_mask(vk::ColorComponentFlags::RGBA);
                if self.alpha_blend {
                    state
                        .blend_enable(true)
                        .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
                        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                        .color_blend_op(vk::BlendOp::ADD)
                        .src_alpha_blend_factor(vk::BlendFactor::ONE)
                        .dst_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
                        .alpha_blend_op(vk::BlendOp::ADD)
                } else {
                    state
                }
            })
            .collect();
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&self.color_formats)
            .depth_attachment_format(self.depth_format.unwrap_or(vk::Format::UNDEFINED));
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.raw())
            .push_next(&mut rendering);
        // SAFETY: every pointer in `info` refers to locals alive for the call; the modules
        // are destroyed only after the pipeline is created.
        let raw = unsafe {
            ctx.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, result)| Error::Vulkan {
            call: "vkCreateGraphicsPipelines",
            result,
        })?[0];
        ctx.name(raw, self.name);
        ctx.count_pipeline();
        Ok(Pipeline {
            raw,
            bind_point: vk::PipelineBindPoint::GRAPHICS,
            ctx: ctx.clone(),
        })
    }
}

/// An owned graphics or compute pipeline.
pub struct Pipeline {
    raw: vk::Pipeline,
    bind_point: vk::PipelineBindPoint,
    ctx: Arc<Context>,
}

/// Specialization constants (`constant_id`, value) laid out for Vulkan, 4 bytes each.
struct Specialization {
    entries: Vec<vk::SpecializationMapEntry>,
    values: Vec<u32>,
}

impl Specialization {
    fn new(constants: &[(u32, u32)]) -> Self {
        Self {
            entries: (0u32..)
                .zip(constants)
                .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                    constant_id: id,
                    offset: 4 * i,
                    size: 4,
                })
                .collect(),
            values: constants.iter().map(|&(_, value)| value).collect(),
        }
    }

    fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default()
            .map_entries(&self.entries)
            .data(super::as_bytes(&self.values))
    }
}

impl Pipeline {
    /// A compute pipeline from one compute module.
    pub fn compute(
        ctx: &Arc<Context>,
        name: &str,
        shader: &ShaderSpirv,
        layout: &PipelineLayout,
    ) -> Result<Self> {
        Self::compute_specialized(ctx, name, shader, layout, &[])
    }

    /// A compute pipeline from one compute module with specialization constants
    /// (`constant_id`, value): code a constant rules out is compiled away, where a push
    /// constant's branch would still run (masked) on lavapipe.
    pub fn compute_specialized(
        ctx: &Arc<Context>,
        name: &str,
        shader: &ShaderSpirv,
        layout: &PipelineLayout,
        constants: &[(u32, u32)],
    ) -> Result<Self> {
        let module = ShaderModule::new(ctx, shader)?;
        let constants = Specialization::new(constants);
        let specialization = constants.info();
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module.raw())
            .name(ENTRY)
            .specialization_info(&specialization);
        let info = vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.raw());
        // SAFETY: the module and layout are alive for the call.
        let raw = unsafe {
            ctx.device
                .create_compute_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, result)| Error::Vulkan {
            call: "vkCreateComputePipelines",
            result,
        })?[0];
        ctx.name(raw, name);
        ctx.count_pipeline();
        Ok(Self {
            raw,
            bind_point: vk::PipelineBindPoint::COMPUTE,
            ctx: ctx.clone(),
        })
    }

    /// The `vk::Pipeline` handle; owned by `self` and destroyed on drop.
    pub fn raw(&self) -> vk::Pipeline {
        self.raw
    }

    /// Binds the pipeline and, if given, descriptor sets starting at set 0.
    pub fn bind(&self, cmd: vk::CommandBuffer, layout: &PipelineLayout, sets: &[&DescriptorSet]) {
        let raw_sets: Vec<vk::DescriptorSet> = sets.iter().map(|s| s.raw()).collect();
        // SAFETY: `cmd` is recording; pipeline, layout and sets belong to this device.
        unsafe {
            self.ctx
                .device
                .cmd_bind_pipeline(cmd, self.bind_point, self.raw);
            if !raw_sets.is_empty() {
                self.ctx.device.cmd_bind_descriptor_sets(
                    cmd,
                    self.bind_point,
                    layout.raw(),
                    0,
                    &raw_sets,
                    &[],
                );
            }
        }
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: the GPU is done with the pipeline (submissions wait).
        unsafe { self.ctx.device.destroy_pipeline(self.raw, None) };
    }
}

//! The dune surface pass (Onoue & Nishita section 3, the design card's fragment path):
//! the dune mesh, ripples bump mapped from our normal-map chain, sand grain, dune and
//! ripple shadows. Textures are made once per scene/light; the culled quad list per
//! frame.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{Vec3, Vec4};

use super::dune_shadow::DuneShadowPass;
use super::lit_mesh::{FrameUniforms, lit_vertex_layout, lit_vertices};
use super::ripple_maps::RippleMaps;
use super::tone_map::ToneMap;
use crate::error::Result;
use crate::gpu::{
    Buffer, BufferDesc, Commands, Context, Descriptor, DescriptorSet, GraphicsPipelineDesc, Image,
    ImageDesc, Pipeline, PipelineLayout, Pod, Sampler, TargetFormat, VertexLayout, vk,
};
use crate::model::dune_shadow::MARGIN_RANGE;
use crate::model::dune_world::{
    DesertWorld, LATTICE_PERIODS, RIPPLE_LATTICE_TILES, RIPPLE_SALT, RIPPLE_SHARPNESS, WAVES,
};
use crate::model::mesh::Mesh;
use crate::model::ripple_maps::{horizon_chain_toward, tile_azimuth};
use crate::model::sky_light::SkyIrradiance;
use crate::shaders::{DescriptorBinding, DescriptorKind, ShaderInterface, compiled};

/// Push constants of `dunes/surface.frag`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DunePush {
    /// x ripple tile size (world), y ripple strength, z grain tile size, w field period.
    pub tile: Vec4,
    /// xy cos/sin of the wind direction (zw unused).
    pub wind: Vec4,
    /// x, y the slopes (tangents) over which the ripples fade out on slip faces, z
    /// ripple-shadow softness, w the sun's angular radius (radians; the dune shadows'
    /// penumbra).
    pub shadows: Vec4,
    /// rgb sand albedo.
    pub albedo: Vec4,
    /// The air at the ground (aerial perspective): rgb extinction per metre, w the
    /// aerosols' phase asymmetry g.
    pub air_extinction: Vec4,
    /// rgb Rayleigh scattering per metre, w aerosol scattering per metre.
    pub air_scattering: Vec4,
    /// The footprints' detail field: world x, z of its corner and its size (m).
    pub detail_rect: Vec4,
    /// x the dune shadow map's range of sun margins (radians), y the slope range of the
    /// detail texture's encoding, w the dune grid's side (z unused).
    pub detail: Vec4,
}
// SAFETY: repr(C), eight Vec4 (128 bytes, the guaranteed push-constant size).
unsafe impl Pod for DunePush {}

/// What the dune shading does, fixed per pipeline as `surface.frag`'s specialization
/// constants (in this order): on lavapipe a switch read from a uniform costs what it
/// turns off (the per-pixel shadow march is paid for even while off).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct DuneSwitches {
    /// Level of detail over the ripple chain (off: level 0 everywhere).
    pub lod: bool,
    /// With `lod`: the paper's level per quad (`DuneSurfacePass::set_levels`).
    pub lod_per_quad: bool,
    /// Dune shadows.
    pub dune_shadows: bool,
    /// Dune shadows marched per pixel instead of read from the map.
    pub dune_shadows_marched: bool,
    /// Ripple shadows from the horizon map.
    pub ripple_shadows: bool,
    /// The footprints' detail field.
    pub footprints: bool,
    /// Draw the dune-shadow term alone (red) instead of shading (tests).
    pub shadow_mask: bool,
    /// The dunes' sky occlusion (`model::sky_light`); off, every point sees the whole
    /// sky.
    pub sky_occlusion: bool,
    /// The sand's specular sheen and the glints of its grains.
    pub sparkle: bool,
    /// Drawing the far rings (`model::dune_world::far_field`): one copy of the ripple
    /// tile, no sheen or glints, no footprints (all finer than a pixel there).
    pub far: bool,
    /// The world beyond the simulated period (`DuneWorldUniforms`); off, the period
    /// and the ripple tile repeated as they are.
    pub endless: bool,
    /// The avalanches' tongues (grainflows) on the slip faces, where the ripples fade.
    pub grainflows: bool,
    /// The bedrock where the sand runs out (`DuneWorldUniforms::bedrock`).
    pub bedrock: bool,
}

impl DuneSwitches {
    /// The switches of the far rings drawn with these.
    fn far_away(self) -> Self {
        Self {
            far: true,
            footprints: false,
            sparkle: false,
            grainflows: false,
            ..self
        }
    }

    /// The specialization constants, `constant_id` 0 up.
    fn constants(self) -> Vec<(u32, u32)> {
        [
            self.lod,
            self.lod_per_quad,
            self.dune_shadows,
            self.dune_shadows_marched,
            self.ripple_shadows,
            self.footprints,
            self.shadow_mask,
            self.sky_occlusion,
            self.sparkle,
            self.far,
            self.endless,
            self.grainflows,
            self.bedrock,
        ]
        .into_iter()
        .zip(0..)
        .map(|(on, id)| (id, u32::from(on)))
        .collect()
    }
}

const FRAME: DescriptorBinding = DescriptorBinding::new(0, 0, DescriptorKind::UniformBuffer);
const NORMALS: DescriptorBinding = DescriptorBinding::new(0, 1, DescriptorKind::SampledImage);
const FIELD: DescriptorBinding = DescriptorBinding::new(0, 2, DescriptorKind::SampledImage);
const GRAIN: DescriptorBinding = DescriptorBinding::new(0, 3, DescriptorKind::SampledImage);
const REPEAT: DescriptorBinding = DescriptorBinding::new(0, 4, DescriptorKind::Sampler);
const HEIGHTS: DescriptorBinding = DescriptorBinding::new(0, 5, DescriptorKind::SampledImage);
const DETAIL: DescriptorBinding = DescriptorBinding::new(0, 6, DescriptorKind::SampledImage);
const LEVELS: DescriptorBinding = DescriptorBinding::new(0, 7, DescriptorKind::StorageBuffer);
const SKY_LIGHT: DescriptorBinding = DescriptorBinding::new(0, 8, DescriptorKind::UniformBuffer);
const WORLD: DescriptorBinding = DescriptorBinding::new(0, 9, DescriptorKind::UniformBuffer);

/// `dunes/surface.vert`: the `FrameUniforms` buffer (binding 0), the
/// `DuneWorldUniforms` buffer (9) and `DunePush`.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_SURFACE_VERT,
    bindings: &[FRAME, WORLD],
    push_constant_bytes: size_of::<DunePush>() as u32,
};

/// `dunes/surface.frag`: the frame buffer, the `DuneTextures` images and their repeating
/// sampler (bindings 0-6), the per-quad levels storage buffer (7), the `DuneSkyLight`
/// buffer (8), the `DuneWorldUniforms` buffer (9) and `DunePush`.
pub static FRAGMENT_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::DUNES_SURFACE_FRAG,
    bindings: &[
        FRAME, NORMALS, FIELD, GRAIN, REPEAT, HEIGHTS, DETAIL, LEVELS, SKY_LIGHT, WORLD,
    ],
    push_constant_bytes: size_of::<DunePush>() as u32,
};

/// What the pass samples, made once per scene and again when the sun moves. Every
/// filtered texture is 8-bit (lavapipe filters those on a fixed-point fast path, 32-bit
/// floats off it; only the per-pixel shadow march's heights are floats) and what one
/// lookup needs shares one texel: a dune pixel reads the ripples' normal and horizon in
/// one trilinear fetch and the dune's normal and shadow in one bilinear fetch.
pub struct DuneTextures {
    /// The ripple tile's LOD chain, RGBA8 UNORM, every level given: rg the normal's x
    /// and y (`n * 0.5 + 0.5`, unit length: z follows), b the horizon toward the sun
    /// as an elevation angle over a right angle, a its spread over the texels a mip
    /// texel covers (`model::ripple_maps::horizon_chain_toward`).
    pub normals: Image,
    /// One period of the dune field at the shadow map's resolution, RGBA8 UNORM: rg
    /// the dune normal's x and z (`n * 0.5 + 0.5`, y up follows), b the dune shadow
    /// map's sun margin over [`MARGIN_RANGE`] (`m * 0.5 + 0.5`: above 0.5 the sun's
    /// centre is up).
    pub field: Image,
    /// The sand-grain tile, RGBA8 UNORM with a blitted mip chain.
    pub grain: Image,
    /// One period of dune heights in cell units (the per-pixel shadow march reads it).
    pub heights: Image,
    /// The footprints' detail texture (`model::footprints::detail_texture`; 1x1 flat
    /// when there are none).
    pub detail: Image,
}

/// The sky's light for `dunes/surface.frag` (binding 8), per sun.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DuneSkyLight {
    /// The sky's irradiance over pi (the shading's units) as nine spherical-harmonic
    /// coefficients (`SkyIrradiance`), rgb each.
    pub sh: [Vec4; 9],
    /// rgb the radiance of the sand that hides the sky from an occluded point in the
    /// sun.
    pub occluder: Vec4,
    /// rgb the same for a point in a dune's shadow.
    pub occluder_shaded: Vec4,
    /// rgb the circumsolar sky's irradiance over pi on a surface facing it.
    pub circumsolar: Vec4,
    /// xyz the circumsolar sky's mean direction.
    pub circumsolar_direction: Vec4,
}
// SAFETY: repr(C), thirteen Vec4.
unsafe impl Pod for DuneSkyLight {}

impl DuneSkyLight {
    /// The buffer's contents for the sky `irradiance` and the occluders' radiance
    /// (`[from a sunlit point, from a shaded one]`).
    pub fn new(irradiance: &SkyIrradiance, occluder: [Vec3; 2]) -> Self {
        let pi = std::f32::consts::PI;
        Self {
            sh: irradiance.coefficients.map(|c| (c / pi).extend(0.0)),
            occluder: occluder[0].extend(0.0),
            occluder_shaded: occluder[1].extend(0.0),
            circumsolar: (irradiance.circumsolar / pi).extend(0.0),
            circumsolar_direction: irradiance.circumsolar_direction.extend(0.0),
        }
    }
}

/// `dunes/world.glsl`'s block: the desert beyond the simulated period
/// (`model::dune_world::DesertWorld`).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct DuneWorldUniforms {
    /// xy wave vector, z phase, w amplitude: `DesertWorld::waves`.
    pub waves: [Vec4; 2 * WAVES],
    /// x period, y the lattice's ramp, z the depth of a copy of no weight, w the
    /// lattice's spacing (metres).
    pub params: Vec4,
    /// The ripple tile's lattice: x its spacing (m), y the weights' power, zw the
    /// salt of its corners' hash.
    pub ripples: Vec4,
    /// The bedrock under the sand (`Bedrock`): x its height (metres, the dune
    /// heights'), y the depth of sand that hides it (m; 0: none drawn), zw unused.
    pub bedrock: Vec4,
    /// rgb the bedrock's albedo (linear), w unused.
    pub bedrock_albedo: Vec4,
}
// SAFETY: repr(C), ten Vec4.
unsafe impl Pod for DuneWorldUniforms {}

impl DuneWorldUniforms {
    /// `world` as the shader reads it; `None`: the period and the ripple tile
    /// repeated as they are (the pipelines' `DuneSwitches::endless` off, which read
    /// none of it).
    pub fn new(
        world: Option<&DesertWorld>,
        period: f32,
        ripple_tile: f32,
        bedrock: Option<Bedrock>,
    ) -> Self {
        let (bedrock, bedrock_albedo) = bedrock.map_or((Vec4::ZERO, Vec4::ZERO), |b| {
            (
                Vec4::new(b.height_m, b.cover_m, 0.0, 0.0),
                b.albedo.extend(0.0),
            )
        });
        let ripples = Vec4::new(
            RIPPLE_LATTICE_TILES * ripple_tile,
            RIPPLE_SHARPNESS as f32,
            RIPPLE_SALT.x as f32,
            RIPPLE_SALT.y as f32,
        );
        match world {
            Some(w) => Self {
                waves: w
                    .waves()
                    .map(|v| Vec4::new(v.k.x, v.k.y, v.phase, v.amplitude)),
                params: Vec4::new(w.period, w.ramp, w.depth, LATTICE_PERIODS * w.period),
                ripples,
                bedrock,
                bedrock_albedo,
            },
            None => Self {
                waves: [Vec4::ZERO; 2 * WAVES],
                params: Vec4::new(period, 0.0, 0.0, period),
                ripples,
                bedrock,
                bedrock_albedo,
            },
        }
    }
}

/// The floor the sand lies on, drawn where it runs out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bedrock {
    /// Its height in the dune heights' metres.
    pub height_m: f32,
    /// The depth of sand that hides it (metres): bare rock at none, sand at this much.
    pub cover_m: f32,
    /// Its albedo, linear RGB.
    pub albedo: Vec3,
}

impl Bedrock {
    /// How much the sand hides the rock at a surface `height_m` high: 0 on bare rock,
    /// 1 under `cover_m` of sand or more (surface.frag's smoothstep, its CPU twin).
    pub fn sand(&self, height_m: f32) -> f32 {
        let t = ((height_m - self.height_m) / self.cover_m).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }
}

/// The footprints' detail texture: RGBA8 texels, width, height.
pub struct DetailTexels {
    /// Row-major RGBA8 texels, 4 bytes each, `width` x `height` of them.
    pub rgba: Vec<u8>,
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
}

/// The light and the dune field `DuneTextures` bake in.
pub struct DuneBake<'a> {
    /// World direction toward the sun.
    pub sun: Vec3,
    /// The wind, radians from world +x toward +z (the ripple tile's +x).
    pub wind_radians: f32,
    /// The dune normals at the shadow map's texels (`model::dune_mesh::normal_texels`).
    pub dune_normals: &'a [Vec3],
    /// The field's sky visibility at the same texels
    /// (`model::sky_light::visibility_texels`).
    pub sky: &'a [f32],
}

/// A value in -1..=1 as an 8-bit unorm byte (`v * 0.5 + 0.5`), as the dune textures
/// store normals, slopes and margins.
pub fn signed_byte(v: f32) -> u8 {
    ((v.clamp(-1.0, 1.0) * 0.5 + 0.5) * 255.0).round() as u8
}

/// A value in 0..=1 as an 8-bit unorm byte.
pub fn unit_byte(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

impl DuneTextures {
    /// Packs the GPU-built ripple maps and dune shadow map, with the horizon toward
    /// `bake.sun` and the dune normals, into sampled images.
    pub fn new(
        ctx: &Arc<Context>,
        maps: &RippleMaps,
        shadow: &DuneShadowPass,
        bake: &DuneBake<'_>,
        grain_rgba: &[u8],
        grain_size: u32,
        detail: Option<&DetailTexels>,
    ) -> Result<Self> {
        let s = maps.size;
        let normals = maps.levels.read::<[f32; 4]>()?;
        let phi = tile_azimuth(bake.sun.to_array(), bake.wind_radians);
        let horizon_slopes = maps.horizon_slopes()?;
        let horizon = horizon_chain_toward(&horizon_slopes, s as usize, phi);
        let right_angle = std::f32::consts::FRAC_PI_2;
        let packed: Vec<u8> = normals
            .iter()
            .zip(horizon.iter().flatten())
            .flat_map(|(n, h)| {
                [
                    signed_byte(n[0]),
                    signed_byte(n[1]),
                    unit_byte(h[0] / right_angle),
                    unit_byte(h[1] / right_angle),
                ]
            })
            .collect();
        let byte_offsets: Vec<u64> = maps
            .level_offsets
            .iter()
            .map(|&o| u64::from(o) * 4)
            .collect();
        let margins = shadow.margin.read::<f32>()?;
        if bake.dune_normals.len() != margins.len() {
            return Err(crate::error::Error::internal(
                "dune textures",
                format!(
                    "{} dune normals for a {}-texel shadow map",
                    bake.dune_normals.len(),
                    margins.len()
                ),
            ));
        }
        if bake.sky.len() != margins.len() {
            return Err(crate::error::Error::internal(
                "dune textures",
                format!(
                    "{} sky occlusion texels for a {}-texel shadow map",
                    bake.sky.len(),
                    margins.len()
                ),
            ));
        }
        let field: Vec<u8> = bake
            .dune_normals
            .iter()
            .zip(&margins)
            .zip(bake.sky)
            .flat_map(|((n, &m), &sky)| {
                [
                    signed_byte(n.x),
                    signed_byte(n.z),
                    signed_byte(m / MARGIN_RANGE),
                    unit_byte(sky),
                ]
            })
            .collect();
        let rgba8 = |w, h| {
            ImageDesc::new_2d(
                w,
                h,
                vk::Format::R8G8B8A8_UNORM,
                vk::ImageUsageFlags::SAMPLED,
            )
        };
        let staged = |name: &str, bytes: &[u8]| {
            Buffer::with_data(
                ctx,
                &format!("{name} staging"),
                vk::BufferUsageFlags::TRANSFER_SRC,
                bytes,
            )
        };
        Ok(Self {
            normals: Image::sampled_from_buffer(
                ctx,
                "ripple normal and horizon chain",
                rgba8(s, s),
                &staged("ripple chain", &packed)?,
                &byte_offsets,
            )?,
            // Mipmapped: beyond the 3 x 3 periods the desert reaches the horizon.
            field: Image::sampled_from_buffer_with_mips(
                ctx,
                "dune normals and shadow",
                rgba8(shadow.res, shadow.res),
                &staged("dune field", &field)?,
                &[0],
                true,
            )?,
            grain: Image::upload_rgba8(
                ctx,
                "sand grain",
                grain_size,
                grain_size,
                grain_rgba,
                true,
            )?,
            heights: Image::sampled_from_buffer(
                ctx,
                "dune heights",
                ImageDesc::new_2d(
                    shadow.n,
                    shadow.n,
                    vk::Format::R32_SFLOAT,
                    vk::ImageUsageFlags::SAMPLED,
                ),
                &shadow.heights,
                &[0],
            )?,
            detail: match detail {
                Some(d) => {
                    Image::upload_rgba8(ctx, "footprint detail", d.width, d.height, &d.rgba, true)?
                }
                // Flat, untrodden, lit.
                None => {
                    Image::upload_rgba8(ctx, "no footprints", 1, 1, &[128, 128, 0, 255], false)?
                }
            },
        })
    }
}

/// The dune mesh in GPU buffers: vertices once, visible-quad indices per frame.
pub struct DuneGeometry {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
    /// The first indices, the triangles over the footprints' detail field: the rest
    /// are drawn without the footprints' texture fetch (`DuneSurfacePass::draw`).
    detail_count: u32,
    /// Where the far rings' indices start (their cheaper pipeline draws them).
    far_first: u32,
}

impl DuneGeometry {
    /// Uploads `mesh`'s vertices and makes a host-visible index buffer the size of all
    /// its indices; nothing is visible until `set_visible`.
    pub fn new(ctx: &Arc<Context>, mesh: &Mesh) -> Result<Self> {
        let vertices = lit_vertices(mesh);
        Ok(Self {
            vertices: Buffer::with_data(
                ctx,
                "dune vertices",
                vk::BufferUsageFlags::VERTEX_BUFFER,
                &vertices,
            )?,
            indices: Buffer::new(
                ctx,
                "dune visible quads",
                BufferDesc::upload(
                    (mesh.indices.len().max(1) * 4) as u64,
                    vk::BufferUsageFlags::INDEX_BUFFER,
                ),
            )?,
            index_count: 0,
            detail_count: 0,
            far_first: 0,
        })
    }

    /// Sets the quads to draw (a subset of the mesh's indices).
    pub fn set_visible(&mut self, indices: &[u32]) -> Result<()> {
        self.set_visible_split(indices, indices.len(), indices.len())
    }

    /// `set_visible`, the first `detail` indices the triangles that reach the
    /// footprints' detail field (the rest are shaded without it), and those from
    /// `far` on the far rings' (shaded as far away).
    pub fn set_visible_split(&mut self, indices: &[u32], detail: usize, far: usize) -> Result<()> {
        if !indices.is_empty() {
            self.indices.write(0, indices)?;
        }
        self.index_count = indices.len() as u32;
        self.far_first = far.min(indices.len()) as u32;
        self.detail_count = detail.min(self.far_first as usize) as u32;
        Ok(())
    }

    /// Triangles the last `set_visible` selected (indices / 3).
    pub fn visible_triangles(&self) -> u32 {
        self.index_count / 3
    }
}

/// The lit-mesh vertices' positions alone: the dune shading reads its normals from
/// `DuneTextures::field`.
fn positions_only() -> VertexLayout {
    let mut layout = lit_vertex_layout();
    layout.attributes.truncate(1);
    layout
}

/// The dune surface pipelines (no culling; one per `DuneSwitches` asked for), its
/// frame uniforms and per-quad levels, and one descriptor set over a `DuneTextures`.
pub struct DuneSurfacePass {
    set: DescriptorSet,
    _sampler: Sampler,
    frame: Buffer,
    /// The paper's per-quad ripple levels (`model::dune_mesh::quad_levels`), when LOD
    /// is chosen per quad.
    levels: Buffer,
    /// `DuneSkyLight`, per sun.
    sky_light: Buffer,
    /// `DuneWorldUniforms`: per scene, and again when the viewer toggles the world.
    world: Buffer,
    /// The switches the next draws use, and a pipeline for each set of switches
    /// used so far (each one costs lavapipe a shader compilation).
    switches: DuneSwitches,
    pipelines: HashMap<DuneSwitches, Pipeline>,
    target: TargetFormat,
    tone: ToneMap,
    layout: PipelineLayout,
    ctx: Arc<Context>,
}

impl DuneSurfacePass {
    /// For `quads` dune quads (the tiled field's), drawing with `switches`,
    /// tone-mapping with `tone`, in `world`.
    pub fn new(
        ctx: &Arc<Context>,
        target: TargetFormat,
        tone: ToneMap,
        textures: &DuneTextures,
        quads: usize,
        switches: DuneSwitches,
        world: &DuneWorldUniforms,
    ) -> Result<Self> {
        let layout = PipelineLayout::new(
            ctx,
            "dune surface layout",
            &[&VERTEX_INTERFACE, &FRAGMENT_INTERFACE],
        )?;
        let frame = Buffer::new(
            ctx,
            "dune frame uniforms",
            BufferDesc::upload(
                size_of::<FrameUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        // The paper's LOD has four levels (e.g. 256, 128, 64, 32): levels 0..=3 only,
        // so far ripples keep their coarse relief instead of fading to a flat 1x1.
        let repeat = Sampler::linear_repeat_max_lod(ctx, "dune repeat sampler", 3.0)?;
        let set = layout.allocate_set("dune surface set", 0)?;
        set.write("frame", Descriptor::Buffer(&frame))?;
        set.write("repeat_sampler", Descriptor::Sampler(&repeat))?;
        let levels = Buffer::new(
            ctx,
            "dune quad levels",
            BufferDesc::upload(
                (quads.max(1) * 4) as u64,
                vk::BufferUsageFlags::STORAGE_BUFFER,
            ),
        )?;
        set.write("quads", Descriptor::Buffer(&levels))?;
        let sky_light = Buffer::new(
            ctx,
            "dune sky light",
            BufferDesc::upload(
                size_of::<DuneSkyLight>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        set.write("skylight", Descriptor::Buffer(&sky_light))?;
        let mut world_buffer = Buffer::new(
            ctx,
            "dune world",
            BufferDesc::upload(
                size_of::<DuneWorldUniforms>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER,
            ),
        )?;
        world_buffer.write(0, std::slice::from_ref(world))?;
        set.write("world", Descriptor::Buffer(&world_buffer))?;
        let mut pass = Self {
            set,
            _sampler: repeat,
            frame,
            levels,
            sky_light,
            world: world_buffer,
            switches,
            pipelines: HashMap::new(),
            target,
            tone,
            layout,
            ctx: ctx.clone(),
        };
        pass.set_textures(textures)?;
        pass.set_switches(switches)?;
        Ok(pass)
    }

    /// Samples `textures` from the next draw on (made again when the sun moves): the
    /// descriptors are rewritten, the pipelines kept. Call between frames, when no
    /// submission reading the old textures is pending.
    pub fn set_textures(&mut self, textures: &DuneTextures) -> Result<()> {
        for (name, image) in [
            ("ripple_normals", &textures.normals),
            ("dune_field", &textures.field),
            ("sand_grain", &textures.grain),
            ("dune_heights", &textures.heights),
            ("detail_map", &textures.detail),
        ] {
            self.set.write(name, Descriptor::Image(image))?;
        }
        Ok(())
    }

    /// The world beyond the period for the next draws (the viewer's toggle); call
    /// between frames.
    pub fn set_world(&mut self, world: &DuneWorldUniforms) -> Result<()> {
        self.world.write(0, std::slice::from_ref(world))
    }

    /// The switches of the next draws; builds their pipeline the first time.
    pub fn set_switches(&mut self, switches: DuneSwitches) -> Result<()> {
        // With footprints, the one without too (for the triangles away from them);
        // and the far rings'.
        if switches.footprints {
            self.add_pipeline(DuneSwitches {
                footprints: false,
                ..switches
            })?;
        }
        self.add_pipeline(switches.far_away())?;
        self.add_pipeline(switches)?;
        self.switches = switches;
        Ok(())
    }

    /// Builds the pipeline for `switches` unless it exists.
    fn add_pipeline(&mut self, switches: DuneSwitches) -> Result<()> {
        if !self.pipelines.contains_key(&switches) {
            let mut desc = GraphicsPipelineDesc::new("dune surface", VERTEX_INTERFACE.shader)
                .fragment(FRAGMENT_INTERFACE.shader)
                .vertex_layout(positions_only())
                .target(self.target);
            // Back faces are dropped per quad on the CPU when culling is on (the
            // paper's comparison needs them drawn when it is off).
            desc.cull_mode = vk::CullModeFlags::NONE;
            desc.constants = switches.constants();
            desc = desc.specialize(&self.tone.constants());
            let pipeline = desc.build(&self.ctx, &self.layout)?;
            self.pipelines.insert(switches, pipeline);
        }
        Ok(())
    }

    /// Sets the camera and lights for the next submission (call between frames).
    pub fn set_frame(&mut self, frame: &FrameUniforms) -> Result<()> {
        self.frame.write(0, std::slice::from_ref(frame))
    }

    /// The sky's light for the next frame (call between frames).
    pub fn set_sky_light(&mut self, light: &DuneSkyLight) -> Result<()> {
        self.sky_light.write(0, std::slice::from_ref(light))
    }

    /// The per-quad levels for the next frame (call between frames).
    pub fn set_levels(&mut self, levels: &[f32]) -> Result<()> {
        self.levels.write(0, levels)
    }

    /// Draws the visible dune quads inside an open rendering scope.
    pub fn draw(&self, cmd: &Commands<'_>, geometry: &DuneGeometry, push: &DunePush) -> Result<()> {
        if geometry.index_count == 0 {
            return Ok(());
        }
        // With footprints, the triangles away from their detail field are drawn by the
        // pipeline without them: a CPU rasteriser would fetch the detail texture in
        // every pixel, inside the field or not.
        let split = if self.switches.footprints {
            geometry.detail_count
        } else {
            0
        };
        let far = geometry.far_first;
        let ranges = [
            (self.switches, 0, split),
            (
                DuneSwitches {
                    footprints: false,
                    ..self.switches
                },
                split,
                far - split,
            ),
            (self.switches.far_away(), far, geometry.index_count - far),
        ];
        cmd.bind_vertex_buffer(&geometry.vertices, 0);
        cmd.bind_index_buffer(&geometry.indices);
        for (switches, first, count) in ranges {
            if count == 0 {
                continue;
            }
            let pipeline = self.pipelines.get(&switches).ok_or_else(|| {
                crate::error::Error::internal("dune surface", "no pipeline for its switches")
            })?;
            cmd.bind_pipeline(pipeline, &self.layout, &[&self.set]);
            cmd.push_constants(&self.layout, push)?;
            cmd.draw_indexed_range(first, count);
        }
        Ok(())
    }
}

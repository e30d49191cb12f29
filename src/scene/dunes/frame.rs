//! The desert's frame (Onoue & Nishita): both sand simulations run, the ripple maps
//! and the dune shadow map built on the GPU once (the shadow map again whenever the sun
//! moves), then each frame the bump-mapped dunes, the sky and the dust.

use std::collections::BTreeMap;
use std::sync::Arc;

use glam::Vec3;

use super::{
    DuneLaw, DuneShadowMethod, DunesScene, LodChoice, PRESETS, SAND_ALBEDO, Shadows,
    default_camera, preset,
};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::export::asset::Asset;
use crate::frame::plugin::Job;
use crate::frame::{
    Exportable, GalleryShot, Interactive, Measured, OutputDef, Progress, Scene, SceneDef, Time,
};
use crate::gpu::{Commands, Context, GpuTimer, OffscreenTarget, Span};
use crate::input::Key;
use crate::model::atmosphere::Atmosphere;
use crate::model::dune_mesh::{
    DuneLod, dune_mesh_grid, dune_mesh_tiled, normal_texels, quad_levels, tiled_heights,
    visible_quads,
};
use crate::model::dune_shadow::{DuneGrid, MARGIN_RANGE, SUN_RADIUS_RADIANS};
use crate::model::dune_wind::WindDunes;
use crate::model::dune_world::{DesertWorld, FAR_RINGS, FarField, far_field, world_tiles};
use crate::model::dust::{DustCloud, DustGround};
use crate::model::footprints::{self, DetailField, FootprintParams};
use crate::model::mesh::Mesh;
use crate::model::pavement::pavement;
use crate::model::sand::{Heightfield, SandSim};
use crate::model::sand_grain::grain_texture;
use crate::model::sky_light::{SkyIrradiance, visibility_texels};
use crate::params::ParamSet;
use crate::render::atmosphere::{
    AtmosphereSkyPass, AtmosphereSkyPush, SKY_VIEW_HEIGHT, SKY_VIEW_WIDTH, SkyViewPass,
};
use crate::render::dune_shadow::DuneShadowPass;
use crate::render::dune_surface::{
    Bedrock, DetailTexels, DuneBake, DuneGeometry, DunePush, DuneSkyLight, DuneSurfacePass,
    DuneSwitches, DuneTextures, DuneWorldUniforms, signed_byte, unit_byte,
};
use crate::render::dust::{DustLight, DustPass};
use crate::render::lighting::Lighting;
use crate::render::ripple_maps::{HorizonWalk, RippleMaps};
use crate::render::tone_map::ToneMap;

/// The simulated terrain: dune heights (world metres) and the ripple tile.
#[derive(Clone)]
pub struct Terrain {
    /// One period of dune heights in metres, lowest at 0: `dune_size` squared, row by
    /// row.
    pub dune_heights: Vec<f32>,
    /// The ripple tile as drawn, `ripple_size` texels a side, in model units: the
    /// simulated field, mirrored along the wind with `ripples_mirrored`. Nishimori &
    /// Ouchi's law at the paper's values makes ripples whose steep faces face upwind
    /// and which creep upwind (`model::sand` test
    /// `the_published_ripple_law_mirrors_real_ripples`); mirrored, they have real
    /// ripples' gentle stoss slope upwind and steep lee downwind, and move downwind as
    /// the sand forms.
    pub ripples: Heightfield,
    /// The simulated dune field as the simulation left it, in model units.
    pub dune_field: Heightfield,
    /// The bedrock's height in the metres of `dune_heights` (the wind law's sand lies
    /// on it, at or below the lowest sand); `None` under the paper's law, whose sand
    /// has no floor.
    pub bedrock_m: Option<f32>,
}

/// Runs both simulations; `progress(done, total)` over all steps.
pub fn simulate(scene: &DunesScene, progress: &mut dyn FnMut(u32, u32)) -> Result<Terrain> {
    simulate_frames(scene, 1, progress, &mut |_, _| Ok(()))
}

/// Runs both simulations in `frames` equal chunks and hands the terrain after each to
/// `each(index, terrain)` (the ripples and dunes forming over time, for an animation,
/// one snapshot alive at a time); returns the final terrain.
pub fn simulate_frames(
    scene: &DunesScene,
    frames: u32,
    progress: &mut dyn FnMut(u32, u32),
    each: &mut dyn FnMut(u32, &Terrain) -> Result<()>,
) -> Result<Terrain> {
    scene.validate()?;
    let frames = frames.max(1);
    let total = scene.ripple_steps + scene.dune_steps;
    let mut ripples = SandSim::new(
        Heightfield::random(scene.ripple_size, scene.ripple_size, 0.0, 1.0, scene.seed),
        scene.ripple_params(),
    )?;
    let mut dunes = DuneSim::new(scene)?;
    let (mut ripple_done, mut dune_done) = (0u32, 0u32);
    let mut last = None;
    for f in 1..=frames {
        let ripple_to = (u64::from(scene.ripple_steps) * u64::from(f) / u64::from(frames)) as u32;
        let dune_to = (u64::from(scene.dune_steps) * u64::from(f) / u64::from(frames)) as u32;
        let base = ripple_done + dune_done;
        ripples.run(ripple_to - ripple_done, &mut |d| progress(base + d, total));
        ripple_done = ripple_to;
        let base = ripple_done + dune_done;
        dunes.run(dune_to - dune_done, &mut |d| progress(base + d, total));
        dune_done = dune_to;
        let terrain = terrain_of(scene, ripples.field().clone(), dunes.field());
        each(f - 1, &terrain)?;
        last = Some(terrain);
    }
    last.ok_or_else(|| Error::internal("simulation", "produced no terrain"))
}

/// The dune simulation of the scene's law.
enum DuneSim {
    Paper(SandSim),
    Wind(WindDunes),
}

impl DuneSim {
    fn new(scene: &DunesScene) -> Result<Self> {
        Ok(match scene.dune_law {
            DuneLaw::Paper => DuneSim::Paper(SandSim::new(
                Heightfield::random(
                    scene.dune_size,
                    scene.dune_size,
                    scene.dune_sand,
                    1.0,
                    // The dune field's own stream of the seed, salted so that the
                    // default seed's field gives fig12's foreground the relief
                    // tests/gpu/dunes.rs asks for rather than one smooth slope.
                    scene.seed ^ 0xD0E6,
                ),
                scene.dune_params(),
            )?),
            DuneLaw::Wind => DuneSim::Wind(WindDunes::new(
                scene.dune_size,
                scene.supply_slabs(),
                scene.wind_dune_params(),
                scene.seed ^ 0xD0E6,
            )?),
        })
    }

    fn run(&mut self, steps: u32, progress: &mut dyn FnMut(u32)) {
        match self {
            DuneSim::Paper(sim) => sim.run(steps, progress),
            DuneSim::Wind(sim) => sim.run(steps, progress),
        }
    }

    /// The field, in the paper law's units of sand or (wind law) the surface drawn, in
    /// cell widths.
    fn field(&self) -> Heightfield {
        match self {
            DuneSim::Paper(sim) => sim.field().clone(),
            DuneSim::Wind(sim) => sim.surface(),
        }
    }
}

/// World-unit dune heights (lowest at 0) from the simulated fields, and the ripple
/// tile as drawn (`Terrain::ripples`).
fn terrain_of(scene: &DunesScene, ripples: Heightfield, dune_field: Heightfield) -> Terrain {
    let scale = match scene.dune_law {
        DuneLaw::Paper => scene.dune_params().vertical_scale as f32 * scene.cell,
        DuneLaw::Wind => scene.cell,
    };
    let min = dune_field.data.iter().copied().fold(f64::MAX, f64::min);
    let dune_heights = dune_field
        .data
        .iter()
        .map(|&h| (h - min) as f32 * scale)
        .collect();
    Terrain {
        bedrock_m: (scene.dune_law == DuneLaw::Wind).then(|| -(min as f32) * scale),
        dune_heights,
        ripples: if scene.ripples_mirrored {
            mirrored_along_the_wind(&ripples)
        } else {
            ripples
        },
        dune_field,
    }
}

/// `field` mirrored along x (the wind): column x becomes column `width - 1 - x`.
fn mirrored_along_the_wind(field: &Heightfield) -> Heightfield {
    let w = field.width;
    Heightfield {
        data: (0..field.data.len())
            .map(|i| field.data[i - i % w + (w - 1 - i % w)])
            .collect(),
        ..field.clone()
    }
}

/// The desert's passes — sky, bump-mapped dunes with their precomputed ripple and
/// shadow maps, dust — as a [`Scene`].
pub struct DunesFrame {
    /// The sun and the toggles, changed by the viewer's keys.
    scene: DunesScene,
    maps: RippleMaps,
    shadow: DuneShadowPass,
    grain: Vec<u8>,
    // Sampled by `surface`; made again, and rebound, when the sun moves.
    _textures: DuneTextures,
    surface: DuneSurfacePass,
    /// The air, its sky-view table (again whenever the sun moves) and the sky from it.
    atmosphere: Atmosphere,
    sky_view: SkyViewPass,
    sky: AtmosphereSkyPass,
    /// The sun, sky and exposure the table gave, and the sun they are for.
    light: Option<(Vec3, DesertLight)>,
    dust: DustPass,
    dust_blobs: usize,
    /// The terrain's bedrock height (`Terrain::bedrock_m`): the viewer's key has one to
    /// show only under the wind law.
    bedrock_m: Option<f32>,
    /// The dust as released and as it drifts (the viewer advances it a step a frame).
    dust_cloud: Option<(DustCloud, DustCloud)>,
    /// The dust moved in the last `set_frame`.
    dust_moved: bool,
    /// One period of dune heights (metres), which the dust hugs.
    dune_heights: Vec<f32>,
    /// The dune normals at the shadow map's texels, baked with it.
    dune_normals: Vec<Vec3>,
    /// The field's sky visibility at the same texels (the sun does not change it).
    sky_occlusion: Vec<f32>,
    /// The walk's footprints, if any: their detail field over the dunes.
    prints: Option<DetailField>,
    geometry: DuneGeometry,
    /// Three periods each way: the field reaches toward the horizon without a seam.
    mesh: Mesh,
    /// The mesh's chunks, simplified far away (`--mesh-lod`).
    lod: DuneLod,
    /// Beyond it to the horizon (`--endless`): its vertices follow the mesh's in
    /// the geometry's buffer.
    far: Option<FarField>,
    /// The sun the shadow map was made for.
    sun: Vec3,
    /// GPU time of the precomputations (ripple maps, dune shadow map).
    precompute: Vec<Span>,
    view: Option<DunesView>,
    /// Draw the dune-shadow term instead of the shaded desert (`show_shadow_mask`).
    shadow_mask: bool,
    message: String,
    /// The simulated terrain, kept when the frame was made from the registry so that
    /// `asset` can export one period of it (`--mesh`).
    terrain: Option<Arc<Terrain>>,
}

/// What `set_frame` fixes for the next frame.
struct DunesView {
    view_proj: glam::Mat4,
    fov_y_degrees: f32,
    eye: Vec3,
    target: Vec3,
    push: DunePush,
    sky: AtmosphereSkyPush,
    dust: bool,
}

/// The sand grain texture (and the bedrock's pavement on it): its side in texels and
/// the metres one tile covers, about 2.7 mm a texel.
pub(super) const GRAIN_SIZE: u32 = 512;
pub(super) const GRAIN_TILE_M: f32 = 1.4;

/// The ripple shadows' edge: half the width of the transition from lit to shadowed
/// around the horizon, radians (about 2.3 degrees; the mips' spread widens it).
const RIPPLE_SHADOW_SOFTNESS: f32 = 0.04;

/// The slopes (tangents) over which the ripples fade out, from none to all: the sand's
/// angle of repose less 12 and less 4 degrees (33, dry sand's, with `--repose off`).
/// Near it the slip faces avalanche, and an avalanche leaves no ripples behind.
fn slip_faces(scene: &DunesScene) -> glam::Vec2 {
    let repose = scene.repose.0.unwrap_or(33.0) as f32;
    let tan = |degrees: f32| degrees.clamp(0.0, 89.0).to_radians().tan();
    glam::Vec2::new(tan(repose - 12.0), tan(repose - 4.0))
}

/// The desert's tone mapping, for every pass that draws it.
const DESERT_TONE_MAP: ToneMap = ToneMap::Aces;

/// What the dune shading does for `scene`, with or without footprints, or drawing the
/// dune-shadow term alone (`show_shadow_mask`).
fn switches(scene: &DunesScene, footprints: bool, shadow_mask: bool) -> DuneSwitches {
    DuneSwitches {
        lod: scene.lod,
        lod_per_quad: scene.lod && scene.lod_choice == LodChoice::Quad,
        dune_shadows: scene.shadows != Shadows::None,
        dune_shadows_marched: (scene.dune_shadows == DuneShadowMethod::Pixel),
        ripple_shadows: scene.shadows == Shadows::DuneAndRipple && scene.ripples,
        footprints,
        shadow_mask,
        sky_occlusion: scene.sky_occlusion,
        sparkle: scene.sparkle,
        far: false,
        endless: scene.endless,
        grainflows: scene.grainflows,
        bedrock: scene.draws_bedrock(),
    }
}

/// The bedrock as the dune shader reads it (`DuneWorldUniforms::bedrock`) under a
/// terrain whose floor lies at `bedrock_m` (`Terrain::bedrock_m`): where the wind law's
/// sand runs out (drawn where the scene's switch turns it on, so that the viewer's key
/// can).
pub(super) fn bedrock(bedrock_m: Option<f32>) -> Option<Bedrock> {
    bedrock_m.map(|height_m| Bedrock {
        height_m,
        cover_m: super::BEDROCK_COVER_M,
        albedo: super::BEDROCK_ALBEDO,
    })
}

/// The grain texture of a scene (RGBA8): r the sand's grain, and on the same tile the
/// bedrock's desert pavement (`model::pavement`): g its tone over 2, b and a its
/// slopes (d height / dx, dz) over `PAVEMENT_SLOPE_RANGE`, as `n * 0.5 + 0.5`.
pub(super) fn sand_grain(scene: &DunesScene) -> Vec<u8> {
    let mut texels = grain_texture(scene.seed ^ 0x6A11, GRAIN_SIZE as usize);
    let floor = pavement(scene.seed ^ 0x9EB1, GRAIN_SIZE as usize);
    for ((texel, tone), slope) in texels
        .chunks_exact_mut(4)
        .zip(&floor.tone)
        .zip(&floor.slope)
    {
        texel[1] = unit_byte(tone * 0.5);
        texel[2] = signed_byte(slope[0] / PAVEMENT_SLOPE_RANGE);
        texel[3] = signed_byte(slope[1] / PAVEMENT_SLOPE_RANGE);
    }
    texels
}

/// The steepest pavement slope the grain texture holds (surface.frag's twin).
pub(super) const PAVEMENT_SLOPE_RANGE: f32 = 4.0;
const SHADOW_RES: u32 = 256;

impl DunesFrame {
    /// Builds the ripple maps, the dune shadow map for the scene's sun, the textures,
    /// the sky and the dust (released and advanced to `dust_step`) from `terrain`.
    pub fn new(ctx: &Arc<Context>, scene: DunesScene, terrain: &Terrain) -> Result<Self> {
        scene.validate()?;
        let n = scene.dune_size;
        let maps = RippleMaps::build(
            ctx,
            &terrain.ripples,
            scene.ripple_height_scale,
            scene.drawn_ripple_height_scale(),
            HorizonWalk::Linear,
        )?;
        let mut precompute = maps.spans.clone();
        let heights_cells: Vec<f32> = terrain
            .dune_heights
            .iter()
            .map(|h| h / scene.cell)
            .collect();
        let shadow = DuneShadowPass::new(ctx, n as u32, &heights_cells, SHADOW_RES)?;
        let sun = scene.sun_direction();
        precompute.extend(shadow_map(ctx, &shadow, sun)?);
        let grain = sand_grain(&scene);
        let prints = scene
            .footprints
            .0
            .as_ref()
            .map(|path| footprints::walk(&FootprintParams::walk(path.clone())));
        let dune_normals = normal_texels(n, scene.cell, &terrain.dune_heights, SHADOW_RES as usize);
        let sky_occlusion =
            visibility_texels(n, &heights_cells, &dune_normals, SHADOW_RES as usize);
        let textures = DuneTextures::new(
            ctx,
            &maps,
            &shadow,
            &DuneBake {
                sun,
                wind_radians: scene.ripple_wind_degrees().to_radians(),
                dune_normals: &dune_normals,
                sky: &sky_occlusion,
            },
            &grain,
            GRAIN_SIZE,
            detail_texels(prints.as_ref(), sun).as_ref(),
        )?;
        let (world, world_uniforms) =
            desert_world(&scene, &terrain.dune_heights, terrain.bedrock_m);
        let surface = DuneSurfacePass::new(
            ctx,
            ctx.frame_format(),
            DESERT_TONE_MAP,
            &textures,
            9 * n * n,
            switches(&scene, prints.is_some(), false),
            &world_uniforms,
        )?;
        // The dust: released whether or not it is shown (the viewer's `u` shows it).
        let cloud = scene.dust_params().as_ref().map(|params| {
            let height = dune_height(n, scene.cell, &terrain.dune_heights);
            let ground = DustGround {
                ripples: &terrain.ripples,
                tile: scene.ripple_tile,
                wind_radians: scene.ripple_wind_degrees().to_radians(),
                period: scene.field_size(),
                dune_height: &height,
            };
            let released = DustCloud::release(params, &ground, scene.seed);
            let mut cloud = released.clone();
            cloud.advance(scene.dust_step, &height);
            (released, cloud)
        });
        let blobs = cloud.as_ref().map_or(&[][..], |(_, c)| c.blobs());
        let (mesh, lod, far) = world_geometry(&scene, &terrain.dune_heights, world.as_ref());
        let atmosphere = scene.atmosphere();
        let multiple = scene
            .multiple_scattering
            .then(|| atmosphere.multiple_scattering());
        let sky_view = SkyViewPass::new(ctx, multiple.as_ref())?;
        Ok(Self {
            geometry: DuneGeometry::new(ctx, &with_far(&mesh, far.as_ref()))?,
            mesh,
            lod,
            far,
            dust: DustPass::new(
                ctx,
                ctx.frame_format(),
                DESERT_TONE_MAP,
                blobs,
                &terrain.dune_heights,
                n as u32,
            )?,
            dust_blobs: blobs.len(),
            bedrock_m: terrain.bedrock_m,
            dust_cloud: cloud,
            dust_moved: false,
            prints,
            dune_heights: terrain.dune_heights.clone(),
            dune_normals,
            sky_occlusion,
            sky: AtmosphereSkyPass::new(ctx, ctx.frame_format(), DESERT_TONE_MAP, &sky_view)?,
            sky_view,
            atmosphere,
            light: None,
            surface,
            _textures: textures,
            grain,
            shadow,
            maps,
            sun,
            precompute,
            view: None,
            shadow_mask: false,
            message: String::new(),
            terrain: None,
            scene,
        })
    }

    /// Draws the world beyond the period as the scene now asks (`--endless`, the
    /// viewer's `f`): its geometry and the shading's copies of the field made again.
    /// Call between frames, when no submission reading the old geometry is pending.
    fn rebuild_world(&mut self, ctx: &Arc<Context>) -> Result<()> {
        let (world, uniforms) = desert_world(&self.scene, &self.dune_heights, self.bedrock_m);
        let (mesh, lod, far) = world_geometry(&self.scene, &self.dune_heights, world.as_ref());
        // Everything that can fail first, so that a failure leaves the old world whole.
        let geometry = DuneGeometry::new(ctx, &with_far(&mesh, far.as_ref()))?;
        self.surface.set_world(&uniforms)?;
        self.geometry = geometry;
        self.mesh = mesh;
        self.lod = lod;
        self.far = far;
        Ok(())
    }

    /// Triangles drawn after culling, and in all (the far rings' too).
    pub fn triangles(&self) -> (u32, u32) {
        let far = self.far.as_ref().map_or(0, |f| f.mesh.indices.len());
        (
            self.geometry.visible_triangles(),
            ((self.mesh.indices.len() + far) / 3) as u32,
        )
    }

    /// The ripple tile's normal chain and horizon map.
    pub fn ripple_maps(&self) -> &RippleMaps {
        &self.maps
    }

    /// GPU time of the precomputations: the ripple maps and the latest dune shadow map.
    pub fn precompute(&self) -> &[Span] {
        &self.precompute
    }

    /// Draws, instead of the shaded desert, the dune-shadow term in red (1 lit, 0
    /// shadowed) with blue = 1 and green = 0 on the terrain: how the tests compare the
    /// shadow map with the per-pixel march pixel by pixel.
    pub fn show_shadow_mask(&mut self, on: bool) {
        self.shadow_mask = on;
    }

    /// Moves the dust to `time`: step `dust_step + n` for `Time::At(n)`, one step on
    /// for each `Time::Tick` (the viewer blows it along).
    fn advance_dust(&mut self, time: Time) -> Result<()> {
        self.dust_moved = false;
        let (Some((released, cloud)), Some(_)) = (&mut self.dust_cloud, self.scene.dust_params())
        else {
            return Ok(());
        };
        let scene = &self.scene;
        let height = dune_height(scene.dune_size, scene.cell, &self.dune_heights);
        let target = match time {
            Time::At(n) => scene.dust_step.saturating_add(n),
            Time::Tick => cloud.steps().saturating_add(1),
        };
        self.dust_moved = target != cloud.steps();
        if target < cloud.steps() {
            // Back in time: released again (each blob's stream is its own, so this
            // lands on the same positions).
            *cloud = released.clone();
        }
        if target > cloud.steps() {
            cloud.advance(target - cloud.steps(), &height);
            self.dust.set_blobs(cloud.blobs())?;
        }
        Ok(())
    }

    /// The viewer's keys.
    pub const CONTROLS: &'static [&'static str] = &[
        "left/right sun azimuth  up/down sun elevation  l lod  k culling",
        "o shadows none/dune/dune+ripple  j ripples  u dust",
        "y sky occlusion  g sheen and glints  i grainflows  b bedrock",
        "f the desert beyond the period: endless / the period's copies",
    ];
}

impl Scene for DunesFrame {
    fn name(&self) -> &'static str {
        "dunes"
    }

    /// The scene's sun and toggles and the camera for the next frame; a moved sun
    /// rebuilds the dune shadow map first.
    fn set_frame(
        &mut self,
        ctx: &Arc<Context>,
        camera: &Camera,
        aspect: f32,
        time: Time,
    ) -> Result<()> {
        self.advance_dust(time)?;
        let scene = &self.scene;
        let sun = scene.sun_direction();
        if (sun - self.sun).length() > 1e-6 {
            self.precompute = shadow_map(ctx, &self.shadow, sun)?;
            let textures = DuneTextures::new(
                ctx,
                &self.maps,
                &self.shadow,
                &DuneBake {
                    sun,
                    wind_radians: self.scene.ripple_wind_degrees().to_radians(),
                    dune_normals: &self.dune_normals,
                    sky: &self.sky_occlusion,
                },
                &self.grain,
                GRAIN_SIZE,
                detail_texels(self.prints.as_ref(), sun).as_ref(),
            )?;
            // The same pipelines, pointed at the new textures.
            self.surface.set_textures(&textures)?;
            self._textures = textures;
            self.sun = sun;
        }
        if self
            .light
            .is_none_or(|(lit_for, _)| (sun - lit_for).length() > 1e-6)
        {
            let (light, span) = desert_light(ctx, &self.atmosphere, &self.sky_view, camera, sun)?;
            self.precompute.retain(|p| p.name != span.name);
            self.precompute.push(span);
            self.light = Some((sun, light));
        }
        let light = self
            .light
            .map(|(_, l)| l)
            .ok_or_else(|| Error::internal("dunes", "no light"))?;
        let frame = light
            .lighting(sun, scene.exposure)
            .frame_uniforms(camera, aspect);
        self.surface.set_frame(&frame)?;
        self.surface
            .set_sky_light(&DuneSkyLight::new(&light.irradiance, light.occluder()))?;
        self.surface
            .set_switches(switches(scene, self.prints.is_some(), self.shadow_mask))?;
        let wind = scene.ripple_wind_degrees().to_radians();
        let push = DunePush {
            tile: glam::Vec4::new(
                scene.ripple_tile,
                if scene.ripples {
                    scene.ripple_strength
                } else {
                    0.0
                },
                GRAIN_TILE_M,
                scene.field_size(),
            ),
            wind: glam::Vec4::new(wind.cos(), wind.sin(), 0.0, 0.0),
            shadows: slip_faces(scene)
                .extend(RIPPLE_SHADOW_SOFTNESS)
                .extend(SUN_RADIUS_RADIANS),
            albedo: SAND_ALBEDO.extend(1.0),
            air_extinction: self
                .atmosphere
                .extinction(0.0)
                .extend(self.atmosphere.mie_g),
            air_scattering: self
                .atmosphere
                .rayleigh
                .extend(self.atmosphere.mie_scattering),
            detail_rect: self.prints.as_ref().map_or(glam::Vec4::ZERO, |d| {
                glam::Vec4::new(
                    d.origin[0],
                    d.origin[1],
                    d.width as f32 * d.cell,
                    d.height as f32 * d.cell,
                )
            }),
            detail: glam::Vec4::new(
                MARGIN_RANGE,
                footprints::SLOPE_RANGE,
                0.0,
                scene.dune_size as f32,
            ),
        };
        let sky = AtmosphereSkyPush {
            inverse_view_proj: frame.view_proj.inverse(),
            sun: sun.extend(scene.sun_azimuth.to_radians()),
            camera: camera.eye.extend(frame.params.x),
            disk: light.disk.extend(SUN_RADIUS_RADIANS.cos()),
        };
        self.view = Some(DunesView {
            view_proj: frame.view_proj,
            fov_y_degrees: camera.fov_y_degrees,
            eye: camera.eye,
            target: camera.target,
            push,
            sky,
            dust: scene.dust,
        });
        let pi = std::f32::consts::PI;
        self.dust.set_light(&DustLight {
            sun_dir: sun.extend(0.0),
            sun: (pi * light.sun).extend(DUST_PHASE_G),
            // The mean radiance all round: the sky above, the sand below.
            sky: (0.5 * (light.sky + light.ground)).extend(DUST_OPACITY),
            albedo: DUST_ALBEDO.extend(scene.dust_params().map_or(1.0, |d| d.fade)),
            eye: camera.eye.extend(scene.cell),
            tone: glam::Vec4::new(frame.params.x, 0.0, scene.dune_size as f32, 0.0),
        })?;
        Ok(())
    }

    /// Records the frame into `target` (span "dunes").
    fn record(
        &mut self,
        cmd: &Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        let v = self
            .view
            .as_ref()
            .ok_or_else(|| Error::internal("dunes", "set_frame must come before record"))?;
        // The quads to draw: culled, and simplified far away, for this target's size.
        let quads = if self.scene.cull && self.scene.mesh_lod > 0.0 {
            let focal = target.height() as f32 / (2.0 * (0.5 * v.fov_y_degrees.to_radians()).tan());
            let steps = self
                .lod
                .steps(v.eye, self.scene.cell, focal, self.scene.mesh_lod);
            self.lod.quads(&self.mesh, &steps, v.eye, v.view_proj, true)
        } else {
            visible_quads(&self.mesh, v.eye, v.view_proj, self.scene.cull)
        };
        let (mut quads, detail) = match &self.prints {
            Some(prints) => over_detail_first(&self.mesh, quads, prints),
            None => (quads, 0),
        };
        let near = quads.len();
        if let Some(far) = &self.far {
            if self.scene.cull {
                far.visible(self.mesh.positions.len() as u32, v.view_proj, &mut quads);
            } else {
                let first = self.mesh.positions.len() as u32;
                quads.extend(far.mesh.indices.iter().map(|i| i + first));
            }
        }
        self.geometry.set_visible_split(&quads, detail, near)?;
        if self.scene.lod && self.scene.lod_choice == LodChoice::Quad {
            // Texels of the ripple tile across one dune quad (the paper: 64).
            let texels = self.scene.cell / self.scene.ripple_tile * self.scene.ripple_size as f32;
            let levels = quad_levels(
                &self.mesh,
                3 * self.scene.dune_size,
                v.view_proj,
                (target.width(), target.height()),
                texels,
            );
            self.surface.set_levels(&levels)?;
        }
        timer.span(cmd, "dunes", |cmd| {
            target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
            // Dunes first, then the sky where no dune covers (the depth test keeps it
            // there), then the dust, translucent over both.
            self.surface.draw(cmd, &self.geometry, &v.push)?;
            self.sky.draw(cmd, &v.sky)?;
            if v.dust {
                self.dust.draw(cmd, v.view_proj, v.eye, v.target)?;
            }
            target.end(cmd);
            Ok(())
        })
    }

    /// The dust blew on.
    fn animated(&self) -> bool {
        self.dust_moved
    }

    fn status(&self) -> Vec<String> {
        let s = &self.scene;
        let on = |b: bool| if b { "on" } else { "off" };
        let (visible, total) = self.triangles();
        vec![
            format!(
                "sun elevation {:.0} deg azimuth {:.0} deg  shadows {}  ripples {}",
                s.sun_elevation,
                s.sun_azimuth,
                s.shadows,
                on(s.ripples)
            ),
            format!(
                "lod {}  culling {} ({visible}/{total} triangles)  dust {}",
                on(s.lod),
                on(s.cull),
                on(s.dust)
            ),
        ]
    }

    fn interactive(&mut self) -> Option<&mut dyn Interactive> {
        Some(self)
    }

    fn measured(&self) -> Option<&dyn Measured> {
        Some(self)
    }

    fn exportable(&self) -> Option<&dyn Exportable> {
        Some(self)
    }
}

impl Interactive for DunesFrame {
    fn key(&mut self, ctx: &Arc<Context>, key: Key) -> Result<bool> {
        let s = &mut self.scene;
        match key {
            Key::Left => s.sun_azimuth = (s.sun_azimuth - 10.0).rem_euclid(360.0),
            Key::Right => s.sun_azimuth = (s.sun_azimuth + 10.0).rem_euclid(360.0),
            Key::Up => s.sun_elevation = (s.sun_elevation + 2.0).min(90.0),
            Key::Down => s.sun_elevation = (s.sun_elevation - 2.0).max(-2.0),
            Key::Char('l') => s.lod = !s.lod,
            Key::Char('k') => s.cull = !s.cull,
            Key::Char('j') => s.ripples = !s.ripples,
            Key::Char('y') => s.sky_occlusion = !s.sky_occlusion,
            Key::Char('g') => s.sparkle = !s.sparkle,
            Key::Char('i') => s.grainflows = !s.grainflows,
            Key::Char('f') => {
                s.endless = !s.endless;
                self.rebuild_world(ctx)?;
            }
            Key::Char('b') => {
                if self.bedrock_m.is_none() {
                    self.message = "no bedrock under this sand (the paper's law has none)".into();
                    return Ok(true);
                }
                s.bedrock = !s.bedrock;
            }
            Key::Char('o') => {
                s.shadows = match s.shadows {
                    Shadows::None => Shadows::Dune,
                    Shadows::Dune => Shadows::DuneAndRipple,
                    Shadows::DuneAndRipple => Shadows::None,
                }
            }
            Key::Char('u') => {
                if self.dust_blobs == 0 {
                    self.message = "no dust in this scene (start it with --dust)".into();
                    return Ok(true);
                }
                s.dust = !s.dust;
            }
            _ => return Ok(false),
        }
        self.message.clear();
        Ok(true)
    }

    fn controls(&self) -> &'static [&'static str] {
        Self::CONTROLS
    }

    fn message(&self) -> &str {
        &self.message
    }
}

impl Measured for DunesFrame {
    /// The precomputations' GPU times and the triangles drawn.
    fn metrics(&self) -> Result<BTreeMap<String, f64>> {
        let mut m: BTreeMap<String, f64> = self
            .precompute
            .iter()
            .map(|p| {
                (
                    format!("{}_gpu_ms", p.name.replace(' ', "_")),
                    p.milliseconds,
                )
            })
            .collect();
        m.insert("triangles_drawn".into(), f64::from(self.triangles().0));
        Ok(m)
    }
}

impl Exportable for DunesFrame {
    /// One period of the field (it tiles), textured with the sand and the ripples.
    fn asset(&self, _ctx: &Arc<Context>, title: &str) -> Result<Option<Asset>> {
        Ok(self.terrain.as_ref().map(|terrain| {
            let s = &self.scene;
            let mesh = dune_mesh_tiled(s.dune_size, s.cell, &terrain.dune_heights, 1);
            super::export::export(s, terrain, &mesh, &self.grain, title)
        }))
    }
}

/// Mineral dust's single-scattering albedo (Saharan dust measures about 0.97 at 670
/// nm, 0.93 at 550 and 0.85 at 440: iron oxides absorb the blue) and its phase
/// function's asymmetry g (about 0.7: grains scatter mostly forward).
const DUST_ALBEDO: Vec3 = Vec3::new(0.97, 0.93, 0.85);
const DUST_PHASE_G: f32 = 0.7;
/// Opacity at a blob's centre.
const DUST_OPACITY: f32 = 0.4;

/// `indices` (triangles of `mesh`) reordered so that those whose extent in x, z
/// reaches `prints`' rectangle come first, and how many indices they take: the dune
/// shading fetches the footprints only for those.
fn over_detail_first(mesh: &Mesh, indices: Vec<u32>, prints: &DetailField) -> (Vec<u32>, usize) {
    let lo = glam::Vec2::from(prints.origin);
    let hi = lo + glam::Vec2::new(prints.width as f32, prints.height as f32) * prints.cell;
    let (mut near, mut far): (Vec<u32>, Vec<u32>) = (Vec::new(), Vec::with_capacity(indices.len()));
    for tri in indices.chunks_exact(3) {
        let corners = tri.iter().map(|&i| {
            let p = mesh.positions[i as usize];
            glam::Vec2::new(p.x, p.z)
        });
        let (min, max) = corners.fold(
            (glam::Vec2::splat(f32::MAX), glam::Vec2::splat(f32::MIN)),
            |(min, max), p| (min.min(p), max.max(p)),
        );
        let reaches = min.x <= hi.x && max.x >= lo.x && min.y <= hi.y && max.y >= lo.y;
        if reaches { &mut near } else { &mut far }.extend_from_slice(tri);
    }
    let detail = near.len();
    near.extend(far);
    (near, detail)
}

/// The mesh with the far rings' vertices and triangles after its own, as the
/// geometry's buffers hold them.
fn with_far(mesh: &Mesh, far: Option<&FarField>) -> Mesh {
    let mut all = mesh.clone();
    if let Some(far) = far {
        all.append(&far.mesh);
    }
    all
}

/// The world beyond the period of `scene` over one period's `heights` (none unless
/// `--endless`), and the uniforms the shading reads it and the bedrock at `bedrock_m`
/// from.
fn desert_world(
    scene: &DunesScene,
    heights: &[f32],
    bedrock_m: Option<f32>,
) -> (Option<DesertWorld>, DuneWorldUniforms) {
    let world = scene
        .endless
        .then(|| DesertWorld::new(scene.field_size(), heights));
    let uniforms = DuneWorldUniforms::new(
        world.as_ref(),
        scene.field_size(),
        scene.ripple_tile,
        bedrock(bedrock_m),
    );
    (world, uniforms)
}

/// The drawn field of `scene` over one period's `heights`: the 3 x 3 periods (the
/// middle one and, in `world`, its neighbours beyond; else its copies), their
/// simplified chunks, and in `world` the far rings to the horizon.
fn world_geometry(
    scene: &DunesScene,
    heights: &[f32],
    world: Option<&DesertWorld>,
) -> (Mesh, DuneLod, Option<FarField>) {
    let n = scene.dune_size;
    let grid = match world {
        Some(w) => world_tiles(n, scene.cell, heights, w),
        None => tiled_heights(n, heights, 3),
    };
    let mesh = dune_mesh_grid(n, scene.cell, 3, &grid);
    let lod = DuneLod::new(n, 3, &grid);
    let far = world.map(|w| far_field(n, scene.cell, heights, w, FAR_RINGS));
    (mesh, lod, far)
}

/// The footprints' detail texture for `sun`.
fn detail_texels(prints: Option<&DetailField>, sun: Vec3) -> Option<DetailTexels> {
    prints.map(|d| DetailTexels {
        rgba: footprints::detail_texture(d, sun.to_array()),
        width: d.width as u32,
        height: d.height as u32,
    })
}

/// The dune surface's height (metres) at world (x, z), the field periodic with `n`
/// vertices of `cell` metres a side.
fn dune_height(n: usize, cell: f32, heights: &[f32]) -> impl Fn(f32, f32) -> f32 + '_ {
    move |x, z| DuneGrid { n, heights }.sample(x / cell, z / cell)
}

/// What the atmosphere gives the terrain for one sun, in the shading's units
/// (`surface.frag` shades albedo x (sun cos + ambient), so irradiances enter over pi).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DesertLight {
    /// Sunlight at the ground over pi: a white Lambertian surface facing the sun
    /// shows this radiance.
    pub sun: Vec3,
    /// The sky's irradiance on a horizontal surface over pi.
    pub sky: Vec3,
    /// The sand's radiance from below (sunlit and skylit ground).
    pub ground: Vec3,
    /// Radiance of the sun's disk.
    pub disk: Vec3,
    /// Luminance of a horizontal white surface (sun plus sky), what exposure adapts to.
    pub adapt: f32,
    /// The sky's irradiance from every direction (the sky-view table's harmonics).
    pub irradiance: SkyIrradiance,
}

impl DesertLight {
    /// The radiance of the sand that hides part of the sky from a point between dunes,
    /// `[seen from a sunlit point, from one in a dune's shadow]`: from a sunlit point
    /// its faces are as often in the sun as not, so half the sunlit sand's and half
    /// the skylit's; from a point in a dune's shadow the sand toward the sun is that
    /// dune's lee, turned from the sun, so a quarter sunlit (the sand on the other
    /// sides) and the rest skylit.
    pub fn occluder(&self) -> [Vec3; 2] {
        let skylit = SAND_ALBEDO * self.sky;
        [
            0.5 * (self.ground + skylit),
            0.25 * self.ground + 0.75 * skylit,
        ]
    }

    /// The frame's lighting: the exposure adapts to the light (a camera's automatic
    /// exposure) times `exposure`.
    pub fn lighting(&self, sun: Vec3, exposure: f32) -> Lighting {
        Lighting {
            sun_direction: sun,
            point: false,
            sun_color: self.sun,
            sky_color: self.sky,
            ground_color: self.ground,
            exposure: exposure * auto_exposure(self.adapt),
            tonemap: DESERT_TONE_MAP,
        }
    }
}

/// Exposure for a scene whose horizontal white surface shows luminance `adapt` (a
/// camera's automatic exposure, metering the light rather than the picture). Only
/// partial: the exponent below 1 keeps dusk darker than noon and the sky around a low
/// sun from washing out, as in a photograph.
fn auto_exposure(adapt: f32) -> f32 {
    adapt.max(1e-6).powf(-0.6)
}

/// Integrates the sky-view table on the GPU for `sun` seen from `camera`'s height and
/// derives the terrain's light from it; the light and the table's span.
pub(super) fn desert_light(
    ctx: &Arc<Context>,
    air: &Atmosphere,
    pass: &SkyViewPass,
    camera: &Camera,
    sun: Vec3,
) -> Result<(DesertLight, Span)> {
    let elevation = sun.y.clamp(-1.0, 1.0).asin();
    // Twice: the sky's irradiance (from the upper half of the first table, which the
    // ground does not change) lights the ground the second shows below the horizon.
    let mut ground_sky = Vec3::ZERO;
    let mut spans = Vec::new();
    let mut table = Vec::new();
    for _ in 0..2 {
        let mut timer = GpuTimer::new(ctx, "sky view timer", 2)?;
        ctx.submit_and_wait("sky view table", |cmd| {
            timer.reset(cmd);
            timer.span(cmd, "sky view", |cmd| {
                pass.record(cmd, air, camera.eye.y, elevation, ground_sky)
            })
        })?;
        spans.extend(timer.read()?);
        table = pass.read()?;
        ground_sky = Atmosphere::sky_irradiance(&table, SKY_VIEW_WIDTH, SKY_VIEW_HEIGHT)
            / air.sun_irradiance;
    }
    let span = Span {
        name: "sky view".into(),
        milliseconds: spans.iter().map(|s| s.milliseconds).sum(),
    };
    let pi = std::f32::consts::PI;
    let sky = ground_sky * air.sun_irradiance / pi;
    let sunlight = air.sunlight(camera.eye.y.max(0.0), sun);
    let sun_over_pi = sunlight / pi;
    let solid_angle = 2.0 * pi * (1.0 - SUN_RADIUS_RADIANS.cos());
    let horizontal = sun_over_pi * sun.y.max(0.0) + sky;
    let luminance = |c: Vec3| c.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    Ok((
        DesertLight {
            sun: sun_over_pi,
            sky,
            ground: SAND_ALBEDO * horizontal,
            disk: sunlight / solid_angle,
            adapt: luminance(horizontal),
            irradiance: SkyIrradiance::from_sky_view(&table, SKY_VIEW_WIDTH, SKY_VIEW_HEIGHT, sun),
        },
        span,
    ))
}

/// Marches the dune shadow map for `sun` on the GPU; its span.
fn shadow_map(ctx: &Arc<Context>, shadow: &DuneShadowPass, sun: Vec3) -> Result<Vec<Span>> {
    let horizontal = Vec3::new(sun.x, 0.0, sun.z);
    let rise = sun.y / horizontal.length().max(1e-6);
    let dir = horizontal.normalize_or(Vec3::X);
    let mut timer = GpuTimer::new(ctx, "dune shadow timer", 2)?;
    ctx.submit_and_wait("dune shadow map", |cmd| {
        timer.reset(cmd);
        timer.span(cmd, "dune shadow map", |cmd| {
            shadow.record(cmd, [dir.x, dir.z], rise)
        })
    })?;
    timer.read()
}

/// `--heightmap`: the dune field and the ripple tile for terrain tools.
const HEIGHTMAP: OutputDef = OutputDef {
    flag: "heightmap",
    value_name: "FILE.png|FILE.exr",
    extensions: crate::export::heightmap::HEIGHTMAP_FORMATS,
    help: "The dune field's heights as a 16-bit PNG (its range in tEXt chunks) or a float \
           EXR in metres, with the ripple tile beside it as FILE-ripples.png/.exr, each \
           with a JSON sidecar (range, orientation, periodicity, import settings)",
    beside: &["{stem}.json", "{stem}-ripples.{ext}", "{stem}-ripples.json"],
};

/// `--forming`: the desert forming, the simulations run again in chunks.
const FORMING: OutputDef = OutputDef {
    flag: "forming",
    value_name: "FILE.gif",
    extensions: &["gif"],
    help: "The ripples and dunes forming over time as an animated GIF: the simulations \
           run again in --gif-frames chunks (default 12), a frame after each",
    beside: &[],
};

/// Onoue & Nishita's desert as a scene of the registry.
pub struct DunesDef;

impl SceneDef for DunesDef {
    type Params = DunesScene;
    type Model = Terrain;

    fn name(&self) -> &'static str {
        "dunes"
    }

    fn about(&self) -> &'static str {
        "Simulate dunes and wind ripples (Nishimori–Ouchi) and render the desert with \
         bump-mapped ripples, LOD, culling, dune and ripple shadows, dust and footprints \
         (Onoue & Nishita). With --dust, its animation (--gif) is the dust blowing."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        PRESETS
    }

    fn preset(&self, name: &str) -> Result<DunesScene> {
        preset(name)
    }

    fn set_seed(&self, params: &mut DunesScene, seed: u64) {
        params.seed = seed;
    }

    fn model(&self, params: &DunesScene, progress: Progress<'_>) -> Result<Terrain> {
        simulate(params, &mut |d, t| progress("simulation steps", d, t))
    }

    fn made(&self, params: &DunesScene, model: &Terrain) -> Result<serde_json::Value> {
        let summary = |map: &crate::export::heightmap::Heightmap| {
            let n = map.heights_m.len().max(1) as f64;
            let (lo, hi) = map
                .heights_m
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &h| {
                    (lo.min(h), hi.max(h))
                });
            // The heights are f32 in the model: their shortest decimals.
            let short = |x: f64| crate::text::json_f32(x as f32);
            serde_json::json!({
                "samples": [map.width, map.height],
                "cell_m": short(map.cell_m),
                "period_m": short(map.width as f64 * map.cell_m),
                "height_min_m": short(lo),
                "height_max_m": short(hi),
                "height_mean_m": short(map.heights_m.iter().sum::<f64>() / n),
            })
        };
        Ok(serde_json::json!({
            "dune_field": summary(&super::export::dune_heightmap(params, model)),
            "ripple_tile": summary(&super::export::ripple_heightmap(params, model)),
            "simulation_steps": { "dunes": params.dune_steps, "ripples": params.ripple_steps },
        }))
    }

    fn camera(&self, params: &DunesScene, model: &Terrain) -> Camera {
        default_camera(params, model)
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        params: &DunesScene,
        model: &Arc<Terrain>,
        _realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        let mut frame = DunesFrame::new(ctx, params.clone(), model)?;
        frame.terrain = Some(Arc::clone(model));
        Ok(Box::new(frame))
    }

    /// The still shows the dust at `dust_step`.
    fn still_time(&self, _params: &DunesScene) -> Time {
        Time::At(0)
    }

    /// With dust: the dust blowing over the final desert, two time steps a frame.
    fn animation(
        &self,
        params: &DunesScene,
        _model: &Terrain,
        camera: &Camera,
        frames: Option<u32>,
    ) -> Vec<(Camera, Time)> {
        if !params.dust {
            return Vec::new();
        }
        (0..frames.unwrap_or(12))
            .map(|i| (camera.clone(), Time::At(2 * i)))
            .collect()
    }

    fn outputs(&self) -> &'static [OutputDef] {
        &[HEIGHTMAP, FORMING]
    }

    fn write_output(
        &self,
        output: &OutputDef,
        path: Option<&std::path::Path>,
        job: &Job<'_, DunesScene, Terrain>,
        _report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        let path = path.ok_or_else(|| Error::internal("dunes", "an output needs a path"))?;
        if output.flag == HEIGHTMAP.flag {
            let mut lines = Vec::new();
            for (target, map, what) in [
                (
                    path.to_path_buf(),
                    super::export::dune_heightmap(job.params, job.model),
                    "dune field",
                ),
                (
                    ripple_tile_path(path),
                    super::export::ripple_heightmap(job.params, job.model),
                    "ripple tile",
                ),
            ] {
                let (range, files) = crate::export::heightmap::write_heightmap(&target, &map)?;
                let files: Vec<_> = files.iter().map(|f| f.display().to_string()).collect();
                lines.push(format!(
                    "wrote {} ({what}; {})",
                    files.join(" and "),
                    range.line()
                ));
            }
            return Ok(lines);
        }
        // The desert forming: the same seed gives the same final terrain.
        let (Some(ctx), Some(camera)) = (job.ctx, job.camera) else {
            return Err(Error::internal(
                "dunes",
                "--forming needs a device and a camera",
            ));
        };
        let frames = job.frames.unwrap_or(12);
        let mut gif = crate::export::gif::GifStream::create(path, 150)?;
        let mut runner = crate::frame::FrameRunner::new(ctx, job.size)?;
        simulate_frames(job.params, frames, &mut |_, _| {}, &mut |_, snapshot| {
            let mut frame = DunesFrame::new(ctx, job.params.clone(), snapshot)?;
            gif.push(&runner.render(&mut frame, camera, Time::At(0))?.0)
        })?;
        let written = gif.finish()?;
        Ok(vec![format!("wrote {} ({written} frames)", path.display())])
    }

    /// Five of the seven dune figures keep the gallery quick: each simulates anew.
    fn gallery(&self) -> Vec<GalleryShot> {
        let shot = |name, preset, description| GalleryShot {
            name,
            preset,
            set: &[],
            animated: false,
            files: &[],
            description,
        };
        vec![
            shot("dunes-fig12", "fig12", "dunes without wind ripples"),
            shot(
                "dunes-fig13",
                "fig13",
                "dunes with wind ripples (bump mapped, LOD)",
            ),
            shot("dunes-fig15", "fig15", "low sun, dune shadows"),
            shot("dunes-fig17", "fig17", "dune shadows and ripple shadows"),
            shot(
                "dunes-fig18",
                "fig18",
                "a walker's view: ripples at their natural scale, footprints, sand dust",
            ),
            shot(
                "dunes-barchans",
                "barchans",
                "barchans: one wind, little sand",
            ),
            shot(
                "dunes-transverse",
                "transverse",
                "transverse ridges: one wind, much sand",
            ),
            shot(
                "dunes-linear",
                "linear",
                "linear dunes: two winds 140 degrees apart",
            ),
            shot(
                "dunes-star",
                "star",
                "star dunes: winds from three directions",
            ),
        ]
    }

    fn controls(&self) -> &'static [&'static str] {
        DunesFrame::CONTROLS
    }

    fn bench(&self) -> Option<Box<dyn crate::frame::BenchScene>> {
        Some(Box::new(super::bench::DunesBench::default()))
    }
}

/// Where the ripple tile of `--heightmap FILE.ext` goes: FILE-ripples.ext.
pub fn ripple_tile_path(path: &std::path::Path) -> std::path::PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_else(|| "png".to_owned());
    path.with_file_name(format!("{stem}-ripples.{ext}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Ripples and dust follow the wind that blew last: +x under the paper's law
    /// whatever `winds` says, the last of the regime's winds under the wind law (the
    /// linear preset's second, the star preset's third), turned by `wind_direction`.
    #[test]
    fn the_ripples_wind_is_the_wind_that_blew_last() {
        let at = |name: &str| preset(name).expect("preset").ripple_wind_degrees();
        assert_eq!(at("fig17"), 0.0);
        assert_eq!(at("barchans"), 0.0);
        assert_eq!(at("linear"), -70.0);
        assert_eq!(at("star"), 240.0);
        let turned = DunesScene {
            wind_direction: 15.0,
            ..preset("linear").expect("preset")
        };
        assert_eq!(turned.ripple_wind_degrees(), -55.0);
        let paper = DunesScene {
            dune_law: super::super::DuneLaw::Paper,
            winds: "90".parse().expect("winds"),
            ..DunesScene::default()
        };
        assert_eq!(paper.ripple_wind_degrees(), 0.0);
    }

    /// `--dune-isotropic` reaches the wind law, off in every preset (their fields were
    /// made on Werner's lattice).
    #[test]
    fn the_isotropic_lattice_is_asked_for() {
        for (name, _) in PRESETS {
            assert!(!preset(name).expect("preset").wind_dune_params().isotropic);
        }
        let scene = DunesScene {
            dune_isotropic: true,
            ..DunesScene::default()
        };
        assert!(scene.wind_dune_params().isotropic);
    }

    /// Every preset's dune field off the grid: at most 35 % of the slip faces' brinks
    /// continue in the same column in the next row of the model's field (the paper's
    /// law gives 80-90 %), at most 45 % on the surface drawn (straight transverse
    /// crests across the grid's +x wind give 37 %); the crests no more than 6 cells
    /// upwind of the brinks (nature: at the brink).
    #[test]
    fn every_presets_crests_lie_off_the_grid() {
        use crate::model::dune_wind::brinks;
        let mut seen = std::collections::BTreeSet::new();
        for (name, _) in PRESETS {
            let scene = preset(name).expect("preset");
            if !seen.insert(
                format!("{:?}", scene.wind_dune_params())
                    + &format!("{} {}", scene.sand_supply, scene.dune_size),
            ) {
                continue;
            }
            let mut sim = DuneSim::new(&scene).expect("sim");
            sim.run(scene.dune_steps, &mut |_| {});
            let DuneSim::Wind(wind) = &sim else {
                panic!("{name} uses the paper's law");
            };
            let (model, drawn) = (brinks(&wind.heights()), brinks(&wind.surface()));
            eprintln!("{name}: model {model:?}, drawn {drawn:?}");
            assert!(model.count >= 50, "{name}: {} brinks", model.count);
            assert!(
                model.same_column <= 0.35,
                "{name}: {:.3}",
                model.same_column
            );
            assert!(
                drawn.same_column <= 0.45,
                "{name}: drawn {:.3}",
                drawn.same_column
            );
            assert!(
                model.crest_to_brink <= 6.0,
                "{name}: {:.1}",
                model.crest_to_brink
            );
        }
    }

    #[test]
    fn mirrored_ripples_are_the_simulated_tile_reversed_along_the_wind() {
        let scene = DunesScene {
            ripple_size: 16,
            ripple_steps: 3,
            dune_size: 8,
            dune_steps: 0,
            ripples_mirrored: false,
            ..DunesScene::default()
        };
        let plain = simulate(&scene, &mut |_, _| {}).expect("simulate");
        let mirrored = simulate(
            &DunesScene {
                ripples_mirrored: true,
                ..scene
            },
            &mut |_, _| {},
        )
        .expect("simulate");
        for (a, b) in plain
            .ripples
            .data
            .chunks(16)
            .zip(mirrored.ripples.data.chunks(16))
        {
            let reversed: Vec<f64> = a.iter().rev().copied().collect();
            assert_eq!(b, &reversed[..]);
        }
        assert_eq!(plain.dune_heights, mirrored.dune_heights);
    }

    #[test]
    fn triangles_over_the_detail_field_come_first_and_none_is_lost() {
        // A 10 x 10 grid over -5..5 m, the detail field over 1..2.5 x -3..-2 m.
        let mesh = Mesh::height_grid(5.0, 0.0, 10, true, |_, _| 0.0);
        let prints = DetailField {
            origin: [1.0, -3.0],
            cell: 0.5,
            width: 3,
            height: 2,
            data: vec![0.0; 6],
            compacted: 0.0,
            trodden: vec![0.0; 6],
        };
        let (indices, detail) = over_detail_first(&mesh, mesh.indices.clone(), &prints);
        let key = |t: &[u32]| {
            let mut t = t.to_vec();
            t.sort_unstable();
            t
        };
        let mut before: Vec<Vec<u32>> = mesh.indices.chunks(3).map(key).collect();
        let mut after: Vec<Vec<u32>> = indices.chunks(3).map(key).collect();
        before.sort();
        after.sort();
        assert_eq!(before, after, "the same triangles");
        assert_eq!(detail % 3, 0);
        let reaches = |t: &[u32]| {
            let xs = t.iter().map(|&i| mesh.positions[i as usize]);
            let (lo, hi) = xs.fold(
                (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
                |(a, b), p| (a.min(p), b.max(p)),
            );
            lo.x <= 2.5 && hi.x >= 1.0 && lo.z <= -2.0 && hi.z >= -3.0
        };
        assert!(indices[..detail].chunks(3).all(reaches));
        assert!(!indices[detail..].chunks(3).any(reaches));
        // The 1 m cells it overlaps or touches: x 0..3 and z -4..-1, 3 x 3 of them
        // (a triangle's extent is its cell's), two triangles each.
        assert_eq!(detail / 3, 2 * 3 * 3, "{detail}");
    }
}

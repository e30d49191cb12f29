//! The speleothem scene: a cave chamber (floor and ceiling) lit by a lamp, the
//! speleothems of a growth plan grown on the GPU and shaded; presets reproducing the
//! panels of Tortelli & Walter's Figure 9.

use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, Vec3, Vec4};

use super::camera::{Camera, Lighting};
use super::size::Size;
use crate::error::{Error, Result};
use crate::gpu::{COLOR_FORMAT, Context, DEPTH_FORMAT, GpuTimer, OffscreenTarget};
use crate::model::mesh::Mesh;
use crate::model::noise::fbm;
pub use crate::model::speleothem::plan::GrowthScene;
use crate::model::speleothem::plan::{GrowthParams, StepMode};
use crate::model::speleothem::table2::{Co2, DripInterval, Mineral, Pil};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::render::RenderedFrame;
use crate::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};
use crate::render::ring_growth::{MeshSource, RingGrowth};
use crate::render::ring_growth_append::AppendGrowth;
use crate::render::speleothem_surface::SpeleothemSurfacePass;

/// Names of the Figure 9 presets, with what each shows.
pub const PRESETS: &[(&str, &str)] = &[
    (
        "fig9a",
        "stalactites from random radius and height steps (calcareous)",
    ),
    ("fig9b", "stalactites, normal CO2 (calcareous)"),
    ("fig9c", "stalactites, low CO2 (calcareous)"),
    ("fig9d", "stalactites, high CO2 (iron)"),
    ("fig9e", "stalagmites, dry drip interval, normal CO2 (iron)"),
    (
        "fig9f",
        "columns: stalactites meeting stalagmites (calcareous)",
    ),
    (
        "fig9g",
        "random stalactites and stalagmites, 24 speleothems (iron)",
    ),
    ("fig9h", "random stalactites and stalagmites (malachite)"),
];

/// The growth scene of a Figure 9 preset.
pub fn preset(name: &str) -> Result<GrowthScene> {
    let base = GrowthScene::default();
    let manual = |pil, drip, co2, mineral| GrowthScene {
        params: GrowthParams {
            pil,
            drip,
            co2,
            mineral,
            ..GrowthParams::default()
        },
        ..base.clone()
    };
    let random = |pil, mineral, count| GrowthScene {
        count,
        passes: 30,
        // A taller chamber, so that not every pair meets in a column.
        ceiling_y: 3.0,
        mode: StepMode::Random { jitter: 0.5 },
        params: GrowthParams {
            pil,
            mineral,
            wind_intensity: 0.3,
            wind_direction_degrees: 20.0,
            ..GrowthParams::default()
        },
        ..base.clone()
    };
    use DripInterval as D;
    Ok(match name {
        "fig9a" => random(Pil::Stalactites, Mineral::Calcareous, 9),
        "fig9b" => manual(
            Pil::Stalactites,
            D::Standard,
            Co2::Normal,
            Mineral::Calcareous,
        ),
        "fig9c" => manual(Pil::Stalactites, D::Standard, Co2::Low, Mineral::Calcareous),
        "fig9d" => manual(Pil::Stalactites, D::Standard, Co2::High, Mineral::Iron),
        "fig9e" => manual(Pil::Dripping, D::Dry, Co2::Normal, Mineral::Iron),
        "fig9f" => GrowthScene {
            passes: 24,
            ..manual(Pil::Dripping, D::Standard, Co2::High, Mineral::Calcareous)
        },
        "fig9g" => random(Pil::Dripping, Mineral::Iron, 12),
        "fig9h" => random(Pil::Dripping, Mineral::Malachite, 9),
        other => return Err(Error::unknown_preset(other, PRESETS)),
    })
}

/// The camera that frames the chamber from the front, slightly below mid-height.
pub fn default_camera(scene: &GrowthScene) -> Camera {
    let mid = 0.5 * (scene.floor_y + scene.ceiling_y);
    let height = scene.ceiling_y - scene.floor_y;
    Camera {
        eye: Vec3::new(0.0, mid + 0.05 * height, scene.extent + 1.35 * height),
        target: Vec3::new(0.0, mid - 0.02 * height, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 55.0,
        near: 0.05,
        far: 60.0,
    }
}

/// A warm lamp in front of the chamber, above and to the left of the camera.
pub fn lamp_lighting(scene: &GrowthScene) -> Lighting {
    let height = scene.ceiling_y - scene.floor_y;
    Lighting {
        sun_direction: Vec3::new(
            -0.9 * height,
            scene.floor_y + 0.8 * height,
            scene.extent + 0.9 * height,
        ),
        point: true,
        sun_color: Vec3::new(9.0, 7.2, 5.0) * (height / 2.4).powi(2),
        sky_color: Vec3::new(0.035, 0.035, 0.04),
        ground_color: Vec3::new(0.02, 0.017, 0.014),
        exposure: 1.1,
    }
}

/// Rock surfaces of the chamber: the floor rises and the ceiling hangs a little, so the
/// speleothem bases sink into them.
fn chamber(scene: &GrowthScene) -> (Mesh, Mesh) {
    // Wide enough that the planes' far edges sink into the lamp's falloff.
    let half = scene.extent * 12.0;
    let amp = 0.04 * (scene.ceiling_y - scene.floor_y);
    let seed = scene.seed;
    let relief =
        move |x: f32, z: f32| amp * fbm(seed ^ 0xCA7E, Vec3::new(x, 0.0, z) * 1.3, 4, 0.5).abs();
    let floor = Mesh::height_grid(half, scene.floor_y, 128, true, relief);
    let ceiling = Mesh::height_grid(half, scene.ceiling_y, 128, false, move |x, z| {
        -relief(x + 17.0, z)
    });
    (floor, ceiling)
}

/// Which GS/XFB growth runs: both give the same mesh (`tests/ring_growth.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum XfbGrowth {
    /// The paper's pass: the whole mesh re-streamed through the GS every pass.
    #[default]
    Restream,
    /// Only the growth front through the GS; new bands appended (O(one ring) a pass).
    Append,
}

/// A growth on either GS/XFB path, behind one interface.
pub enum Growth {
    Restream(RingGrowth),
    Append(AppendGrowth),
}

impl Growth {
    pub fn new(ctx: &Arc<Context>, plan: &GrowthPlan, kind: XfbGrowth) -> Result<Self> {
        Ok(match kind {
            XfbGrowth::Restream => Self::Restream(RingGrowth::new(ctx, plan, None)?),
            XfbGrowth::Append => Self::Append(AppendGrowth::new(ctx, plan)?),
        })
    }

    pub fn passes_done(&self) -> u32 {
        match self {
            Self::Restream(g) => g.passes_done(),
            Self::Append(g) => g.passes_done(),
        }
    }

    /// Records the next `passes` passes (clamped to the plan).
    pub fn record(&mut self, cmd: &crate::gpu::Commands<'_>, passes: u32) -> Result<()> {
        match self {
            Self::Restream(g) => g.record(cmd, passes),
            Self::Append(g) => g.record(cmd, passes),
        }
    }

    /// Continues with `plan` (see `AppendGrowth::set_plan`); false when it does not fit.
    pub fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool> {
        match self {
            Self::Restream(g) => g.set_plan(plan),
            Self::Append(g) => g.set_plan(plan),
        }
    }

    /// After the submissions: an error if any capture ran out of room.
    pub fn check_counts(&self) -> Result<()> {
        match self {
            Self::Restream(g) => g.check_counts().map(drop),
            Self::Append(g) => g.check_counts().map(drop),
        }
    }

    pub fn source(&self) -> MeshSource<'_> {
        match self {
            Self::Restream(g) => g.source(),
            Self::Append(g) => g.source(),
        }
    }

    /// The current mesh as the re-streaming pass holds it.
    pub fn read_back(&self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Vec<RingVertex>> {
        match self {
            Self::Restream(g) => g.read_back(ctx),
            Self::Append(g) => g.read_back(ctx, plan),
        }
    }
}

/// The speleothem scene's passes — the chamber's rock and the grown surface — shared
/// by `grow` and the interactive viewer.
pub struct GrowthRenderer {
    surface: SpeleothemSurfacePass,
    rock: LitMeshPass,
    floor: GpuMesh,
    ceiling: GpuMesh,
    lighting: Lighting,
}

const ROCK: ObjectPush = ObjectPush {
    model: Mat4::IDENTITY,
    albedo: Vec4::new(0.16, 0.13, 0.105, 1.0),
    material: Vec4::new(12.0, 0.05, 0.0, 0.0),
};
const CLEAR: [f32; 4] = [0.004, 0.0035, 0.003, 1.0];

impl GrowthRenderer {
    pub fn new(ctx: &Arc<Context>, scene: &GrowthScene, plan: &GrowthPlan) -> Result<Self> {
        let (floor, ceiling) = chamber(scene);
        Ok(Self {
            surface: SpeleothemSurfacePass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT, plan, scene.seed)?,
            rock: LitMeshPass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT)?,
            floor: GpuMesh::upload(ctx, "cave floor", &floor)?,
            ceiling: GpuMesh::upload(ctx, "cave ceiling", &ceiling)?,
            lighting: lamp_lighting(scene),
        })
    }

    /// The camera, and the plan's ring counts after `passes` passes (before the
    /// submission that draws them).
    pub fn set_frame(
        &mut self,
        camera: &Camera,
        aspect: f32,
        plan: &GrowthPlan,
        passes: u32,
    ) -> Result<()> {
        let frame = self.lighting.frame_uniforms(camera, aspect);
        self.rock.set_frame(&frame)?;
        self.surface.set_frame(&frame, plan, passes)
    }

    /// Clears `target` and draws the chamber and the mesh of `source` into it.
    pub fn draw(
        &self,
        cmd: &crate::gpu::Commands<'_>,
        target: &OffscreenTarget,
        source: MeshSource<'_>,
    ) -> Result<()> {
        target.begin(cmd, CLEAR);
        self.rock.draw(cmd, &self.floor, &ROCK)?;
        self.rock.draw(cmd, &self.ceiling, &ROCK)?;
        self.surface.draw(cmd, source)?;
        target.end(cmd);
        Ok(())
    }
}

/// What to produce besides the final frame, and how to grow.
#[derive(Clone, Debug, Default)]
pub struct GrowOutputs {
    pub growth: XfbGrowth,
    /// The camera (default: `default_camera`).
    pub camera: Option<Camera>,
    /// Also render a frame before the first pass and every `k` passes (for a GIF).
    pub frame_every: Option<u32>,
    /// Read the grown mesh back from the transform-feedback buffer.
    pub mesh: bool,
}

/// The result of a growth.
pub struct Grown {
    pub plan: GrowthPlan,
    pub frame: RenderedFrame,
    /// Frames of the growth (when requested), the last one equal to `frame`.
    pub frames: Vec<image::RgbaImage>,
    pub mesh: Option<Vec<RingVertex>>,
}

/// Plans, grows and renders `scene`. `progress(done, total)` is called after every
/// submitted batch of passes.
pub fn grow(
    ctx: &Arc<Context>,
    scene: &GrowthScene,
    size: Size,
    outputs: &GrowOutputs,
    progress: &mut dyn FnMut(u32, u32),
) -> Result<Grown> {
    let start = Instant::now();
    let plan = scene.plan()?;
    let camera = outputs
        .camera
        .clone()
        .unwrap_or_else(|| default_camera(scene));

    let target = OffscreenTarget::new(ctx, size.width, size.height)?;
    let mut growth = Growth::new(ctx, &plan, outputs.growth)?;
    let mut renderer = GrowthRenderer::new(ctx, scene, &plan)?;
    let mut timer = GpuTimer::new(ctx, "grow timer", 2)?;

    let step = outputs.frame_every.unwrap_or(plan.passes).max(1);
    let mut frames = Vec::new();
    let mut first = outputs.frame_every.is_some();
    let mut spans;
    loop {
        // The first batch with frames requested renders the base rings before any pass.
        let batch = if first { 0 } else { step };
        first = false;
        renderer.set_frame(&camera, size.aspect(), &plan, growth.passes_done() + batch)?;
        ctx.submit_and_wait("grow + shade", |cmd| {
            timer.reset(cmd);
            let span = timer.begin(cmd, "ring growth")?;
            growth.record(cmd, batch)?;
            timer.end(cmd, span);
            let span = timer.begin(cmd, "shading")?;
            renderer.draw(cmd, &target, growth.source())?;
            timer.end(cmd, span);
            target.copy_out(cmd);
            Ok(())
        })?;
        spans = timer.read()?;
        progress(growth.passes_done(), plan.passes);
        if outputs.frame_every.is_some() {
            frames.push(target.read_image()?);
        }
        if growth.passes_done() >= plan.passes {
            break;
        }
    }
    growth.check_counts()?;
    let image = target.read_image()?;
    let mesh = if outputs.mesh {
        Some(growth.read_back(ctx, &plan)?)
    } else {
        None
    };
    Ok(Grown {
        plan,
        frame: RenderedFrame {
            image,
            gpu_spans: spans,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
        },
        frames,
        mesh,
    })
}

/// The grown mesh as an exportable triangle soup: positions, the shading normals and
/// the mineral colours the surface shader uses (`mix(calcite, mc * ring / rc, i)`).
pub fn export_mesh(
    plan: &GrowthPlan,
    vertices: &[RingVertex],
) -> crate::export::mesh::TriangleSoup {
    const CALCITE: Vec3 = Vec3::splat(0.8);
    let info = crate::render::speleothem_surface::speleothem_info(plan, plan.passes);
    let mut soup = crate::export::mesh::TriangleSoup::default();
    for v in vertices {
        let sp = v.speleothem().min(plan.speleothems.len().saturating_sub(1));
        let (mineral, misc) = (info[2 * sp], info[2 * sp + 1]);
        let g = Vec3::new(0.0, misc.x, 0.0);
        let normal = (v.normal() - g * v.extra[2]).normalize_or(g);
        let t = if mineral.w > 0.0 {
            (v.extra[3] / mineral.w).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let color = CALCITE.lerp(mineral.truncate() * t, misc.y);
        soup.positions.push(v.position().to_array());
        soup.normals.push(normal.to_array());
        soup.colors.push(color.to_array());
    }
    soup
}

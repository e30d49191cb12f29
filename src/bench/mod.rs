//! `sediment bench`: frame timings people can trust and compare. Every series runs a
//! warm-up first (lavapipe compiles shaders on first use), then measured frames; each
//! frame's named passes are timed with GPU timestamps (bracketed by the full barriers
//! lavapipe needs, `gpu::timing`) and the frame's wall clock on the CPU. Every run also
//! measures a floor — an empty submission and a trivial full-screen pass at the same
//! size — so results from different machines compare as multiples of it.
//!
//! Scenes and variants:
//! - `grow`: the speleothem growth of a Fig. 9g-like scene (24 speleothems, 32 segments,
//!   130 passes, one pass and the shading per frame) on the paper's path, the GS/XFB
//!   pass re-streaming the whole mesh (`xfb-restream`), the same GS fed only the growth
//!   front with new bands appended (`xfb-append`), on the compute path that runs the
//!   same pass on every core (`compute-restream`), and generated on the CPU then
//!   uploaded (`cpu-upload`); vertices per second and the pass time at rings 8, 32 and
//!   128 show how each path scales as the mesh grows (O(mesh) against O(one ring)).
//! - `dunes`: Onoue & Nishita's comparison at the figure-17 scene — culling and LOD on
//!   and off, shadows none / dune / dune+ripple, dust — with the horizon-map
//!   precomputation on the GPU and the CPU and the sand simulations on one thread and
//!   all of them.
//! - `cave`: generation per octree depth 5..9 (octree, walls, split, smoothing) and the
//!   frame at each depth.

pub mod plot;
pub mod report;

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use crate::error::{Error, Result};
use crate::gpu::{COLOR_FORMAT, Context, DEPTH_FORMAT, GpuTimer, OffscreenTarget, Span};
use crate::model::sand::{Heightfield, SandParams, SandSim};
use crate::model::speleothem::plan::{GrowthParams, GrowthScene, GrowthUnits};
use crate::model::speleothem::table2::Pil;
use crate::model::speleothem::{RingVertex, grow_pass, initial_rings, vertex_counts};
use crate::render::ring_growth::{MeshSource, RingGrowth};
use crate::render::ring_growth_append::AppendGrowth;
use crate::render::ring_growth_compute::ComputeGrowth;
use crate::render::sky::SkyPass;
use crate::render::speleothem_surface::SpeleothemSurfacePass;
use crate::scene::camera::{Camera, Lighting};
use crate::scene::{Size, cave, dunes};
use report::{Meta, PaperRatio, PassResult, Report, SCHEMA, SeriesResult, Stats};

/// The scenes `sediment bench` knows.
pub const SCENES: &[&str] = &["grow", "dunes", "cave"];

/// Every variant per scene, for `--variants`.
pub const VARIANTS: &[(&str, &[&str])] = &[
    (
        "grow",
        &[
            "xfb-restream",
            "xfb-append",
            "compute-restream",
            "cpu-upload",
        ],
    ),
    (
        "dunes",
        &[
            "cull-off-lod-off",
            "cull-on-lod-off",
            "cull-on-lod-on",
            "dune-shadows",
            "dune-ripple-shadows",
            "all-with-dust",
        ],
    ),
    (
        "cave",
        &["depth-5", "depth-6", "depth-7", "depth-8", "depth-9"],
    ),
];

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchOptions {
    pub scenes: Vec<String>,
    /// Only these variants (all when empty).
    pub variants: Vec<String>,
    pub frames: u32,
    pub warmup: u32,
    pub size: Size,
}

impl BenchOptions {
    pub fn validate(&self) -> Result<()> {
        for s in &self.scenes {
            if !SCENES.contains(&s.as_str()) {
                return Err(Error::invalid(
                    "bench scene",
                    format!("\"{s}\" is not one of {}", SCENES.join(", ")),
                ));
            }
        }
        for v in &self.variants {
            if !VARIANTS.iter().any(|(_, vs)| vs.contains(&v.as_str())) {
                let all: Vec<&str> = VARIANTS
                    .iter()
                    .flat_map(|(_, vs)| vs.iter().copied())
                    .collect();
                return Err(Error::invalid(
                    "--variants",
                    format!("\"{v}\" is not one of {}", all.join(", ")),
                ));
            }
        }
        crate::error::ensure_in_range((1..=1000).contains(&self.frames), "--frames", "1..=1000")?;
        crate::error::ensure_in_range(self.warmup <= 100, "--warmup", "0..=100")
    }

    fn wants(&self, variant: &str) -> bool {
        self.variants.is_empty() || self.variants.iter().any(|v| v == variant)
    }
}

/// Runs the bench; `progress(what)` names each series as it starts.
pub fn run(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    progress: &mut dyn FnMut(&str),
) -> Result<Report> {
    opts.validate()?;
    let info = ctx.info();
    let mut report = Report {
        meta: Meta {
            schema: SCHEMA,
            device: info.name.clone(),
            driver: info.driver_info.clone(),
            vulkan: info.api_version.clone(),
            sediment_version: env!("CARGO_PKG_VERSION").to_owned(),
            git_commit: env!("SEDIMENT_GIT_COMMIT").to_owned(),
            width: opts.size.width,
            height: opts.size.height,
            frames: opts.frames,
            warmup: opts.warmup,
            threads: rayon::current_num_threads(),
        },
        floor: Vec::new(),
        series: Vec::new(),
        paper_ratios: Vec::new(),
    };
    progress("floor");
    report.floor = floor(ctx, opts)?;
    for scene in &opts.scenes {
        match scene.as_str() {
            "grow" => grow(ctx, opts, &mut report, progress)?,
            "dunes" => dunes_series(ctx, opts, &mut report, progress)?,
            "cave" => cave_series(ctx, opts, &mut report, progress)?,
            _ => {}
        }
    }
    Ok(report)
}

/// Runs `frame` `warmup` times unmeasured, then `frames` times, and summarises.
fn measure(
    scene: &str,
    variant: &str,
    opts: &BenchOptions,
    frame: &mut dyn FnMut() -> Result<Vec<Span>>,
) -> Result<SeriesResult> {
    for _ in 0..opts.warmup {
        frame()?;
    }
    let mut cpu = Vec::new();
    let mut spans = Vec::new();
    for _ in 0..opts.frames {
        let t = Instant::now();
        let s = frame()?;
        cpu.push(t.elapsed().as_secs_f64() * 1e3);
        spans.push(s);
    }
    Ok(summarise(scene, variant, &spans, &cpu))
}

fn summarise(scene: &str, variant: &str, spans: &[Vec<Span>], cpu: &[f64]) -> SeriesResult {
    let mut names: Vec<String> = Vec::new();
    for f in spans {
        for s in f {
            if !names.contains(&s.name) {
                names.push(s.name.clone());
            }
        }
    }
    let per_frame: Vec<f64> = spans
        .iter()
        .map(|f| f.iter().map(|s| s.milliseconds).sum())
        .collect();
    SeriesResult {
        scene: scene.to_owned(),
        variant: variant.to_owned(),
        passes: names
            .iter()
            .map(|n| PassResult {
                name: n.clone(),
                gpu_ms: Stats::of(
                    &spans
                        .iter()
                        .filter_map(|f| f.iter().find(|s| &s.name == n).map(|s| s.milliseconds))
                        .collect::<Vec<_>>(),
                ),
            })
            .collect(),
        frame_gpu_ms: Stats::of(&per_frame),
        frame_cpu_ms: Stats::of(cpu),
        per_frame_gpu_ms: per_frame,
        metrics: BTreeMap::new(),
    }
}

/// An empty submission, and a full-screen sky pass at the bench size.
fn floor(ctx: &Arc<Context>, opts: &BenchOptions) -> Result<Vec<SeriesResult>> {
    let mut timer = GpuTimer::new(ctx, "floor timer", 1)?;
    let empty = measure("floor", "empty-submit", opts, &mut || {
        ctx.submit_and_wait("empty", |cmd| {
            timer.reset(cmd);
            let span = timer.begin(cmd, "empty")?;
            timer.end(cmd, span);
            Ok(())
        })?;
        timer.read()
    })?;
    let target = OffscreenTarget::new(ctx, opts.size.width, opts.size.height)?;
    let sky = SkyPass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT)?;
    let camera = Camera {
        eye: Vec3::new(0.0, 1.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_degrees: 50.0,
        near: 0.1,
        far: 100.0,
    };
    let view_proj = camera.view_proj(opts.size.aspect());
    let full = measure("floor", "fullscreen", opts, &mut || {
        ctx.submit_and_wait("fullscreen", |cmd| {
            timer.reset(cmd);
            let span = timer.begin(cmd, "fullscreen")?;
            target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
            sky.draw(cmd, view_proj, camera.eye, Vec3::new(0.3, 0.5, 0.2), 1.0)?;
            target.end(cmd);
            timer.end(cmd, span);
            Ok(())
        })?;
        timer.read()
    })?;
    Ok(vec![empty, full])
}

/// The growth bench scene: 24 stalactites, 32 segments, that never stop within 130
/// passes (no radius change, a roof far above), so ring k exists at pass k.
pub fn growth_scene() -> GrowthScene {
    GrowthScene {
        count: 24,
        passes: 130,
        segments: 32,
        ceiling_y: 200.0,
        floor_y: 0.0,
        extent: 1.2,
        params: GrowthParams {
            pil: Pil::Stalactites,
            ..GrowthParams::default()
        },
        units: GrowthUnits {
            radius_unit: 1e-6,
            height_unit: 0.01,
            ..GrowthUnits::default()
        },
        ..GrowthScene::default()
    }
}

/// The rings at which the pass time is reported.
pub const RING_MARKS: [u32; 3] = [8, 32, 128];

fn grow(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    report: &mut Report,
    progress: &mut dyn FnMut(&str),
) -> Result<()> {
    let scene = growth_scene();
    let plan = scene.plan()?;
    let counts = vertex_counts(&plan);
    // Looking up at the stalactites from below.
    let camera = Camera {
        eye: Vec3::new(0.0, 196.5, 4.5),
        target: Vec3::new(0.0, 199.0, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 50.0,
        near: 0.05,
        far: 50.0,
    };
    let mut frame = GrowthFrame {
        uniforms: Lighting::default().frame_uniforms(&camera, opts.size.aspect()),
        target: OffscreenTarget::new(ctx, opts.size.width, opts.size.height)?,
        surface: SpeleothemSurfacePass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT, &plan, scene.seed)?,
        timer: GpuTimer::new(ctx, "grow bench timer", 2)?,
        plan: &plan,
        counts: &counts,
    };
    if opts.wants("xfb-restream") {
        let s = frame.series(
            ctx,
            "xfb-restream",
            || RingGrowth::new(ctx, &plan, None),
            progress,
        )?;
        report.series.push(s);
    }
    if opts.wants("xfb-append") {
        let s = frame.series(
            ctx,
            "xfb-append",
            || AppendGrowth::new(ctx, &plan),
            progress,
        )?;
        report.series.push(s);
    }
    if opts.wants("compute-restream") {
        let s = frame.series(
            ctx,
            "compute-restream",
            || ComputeGrowth::new(ctx, &plan),
            progress,
        )?;
        report.series.push(s);
    }
    if opts.wants("cpu-upload") {
        let s = frame.series(ctx, "cpu-upload", || CpuGrowth::new(ctx, &plan), progress)?;
        report.series.push(s);
    }
    Ok(())
}

/// One way to grow the bench scene a pass at a time: on the GPU inside the frame
/// (timed as the "ring growth" span) or on the CPU before it (timed by the clock).
trait GrowthPath {
    const ON_GPU: bool;
    /// The CPU's share of a pass, before the frame is recorded.
    fn advance_on_cpu(&mut self) -> Result<()> {
        Ok(())
    }
    /// The GPU's share of a pass, recorded into the frame.
    fn record_pass(&mut self, _cmd: &crate::gpu::Commands<'_>) -> Result<()> {
        Ok(())
    }
    fn source(&self) -> MeshSource<'_>;
    /// Vertices of the final mesh, as the path itself counted them.
    fn final_vertices(&self) -> Result<f64>;
    /// Vertices emitted over the whole growth, given the mesh's vertex count after each
    /// pass (a re-streaming path emits its whole output every pass).
    fn emitted_vertices(&self, counts: &[u64]) -> Result<f64> {
        Ok(counts.iter().sum::<u64>() as f64)
    }
}

impl GrowthPath for RingGrowth {
    const ON_GPU: bool = true;
    fn record_pass(&mut self, cmd: &crate::gpu::Commands<'_>) -> Result<()> {
        self.record(cmd, 1)
    }
    fn source(&self) -> MeshSource<'_> {
        RingGrowth::source(self)
    }
    fn final_vertices(&self) -> Result<f64> {
        // The stream queries (and an error on any overflow).
        let counts = self.check_counts()?;
        Ok(counts.last().map_or(0.0, |c| (c.written * 3) as f64))
    }
}

impl GrowthPath for AppendGrowth {
    const ON_GPU: bool = true;
    fn record_pass(&mut self, cmd: &crate::gpu::Commands<'_>) -> Result<()> {
        self.record(cmd, 1)
    }
    fn source(&self) -> MeshSource<'_> {
        AppendGrowth::source(self)
    }
    fn final_vertices(&self) -> Result<f64> {
        let counts = self.check_counts()?;
        let frozen: u64 = counts.iter().map(|(f, _)| f.written * 3).sum();
        Ok((frozen + counts.last().map_or(0, |(_, front)| front.written * 3)) as f64)
    }
    fn emitted_vertices(&self, _counts: &[u64]) -> Result<f64> {
        // Each pass emits the front's share only: what froze and the next front.
        let counts = self.check_counts()?;
        Ok(counts
            .iter()
            .map(|(f, front)| (f.written + front.written) * 3)
            .sum::<u64>() as f64)
    }
}

impl GrowthPath for ComputeGrowth {
    const ON_GPU: bool = true;
    fn record_pass(&mut self, cmd: &crate::gpu::Commands<'_>) -> Result<()> {
        self.record(cmd, 1)
    }
    fn source(&self) -> MeshSource<'_> {
        ComputeGrowth::source(self)
    }
    fn final_vertices(&self) -> Result<f64> {
        Ok(f64::from(self.gpu_vertex_count()?))
    }
}

impl GrowthPath for CpuGrowth {
    const ON_GPU: bool = false;
    fn advance_on_cpu(&mut self) -> Result<()> {
        self.advance()
    }
    fn source(&self) -> MeshSource<'_> {
        CpuGrowth::source(self)
    }
    fn final_vertices(&self) -> Result<f64> {
        Ok(self.mesh().len() as f64)
    }
}

/// What every growth series shares: the plan, the camera's uniforms, the target, the
/// surface pass and the timer.
struct GrowthFrame<'a> {
    uniforms: crate::render::lit_mesh::FrameUniforms,
    target: OffscreenTarget,
    surface: SpeleothemSurfacePass,
    timer: GpuTimer,
    plan: &'a crate::model::speleothem::GrowthPlan,
    /// Vertices after each pass.
    counts: &'a [u64],
}

impl GrowthFrame<'_> {
    /// A short warm-up run (shader compilation), then the whole plan one pass and its
    /// shading per frame; the pass times at rings 8, 32 and 128 and vertices/s.
    fn series<P: GrowthPath>(
        &mut self,
        ctx: &Arc<Context>,
        variant: &str,
        make: impl Fn() -> Result<P>,
        progress: &mut dyn FnMut(&str),
    ) -> Result<SeriesResult> {
        progress(&format!("grow {variant}"));
        let mut warm = make()?;
        for _ in 0..2 {
            warm.advance_on_cpu()?;
            ctx.submit_and_wait("grow warm-up", |cmd| warm.record_pass(cmd))?;
        }
        let mut growth = make()?;
        let passes = self.plan.passes;
        let (mut spans, mut cpu, mut pass_ms) = (Vec::new(), Vec::new(), Vec::new());
        for pass in 0..passes {
            if pass % 10 == 0 {
                progress(&format!("grow {variant} pass {pass}/{passes}"));
            }
            let t = Instant::now();
            growth.advance_on_cpu()?;
            let cpu_pass_ms = t.elapsed().as_secs_f64() * 1e3;
            self.surface
                .set_frame(&self.uniforms, self.plan, pass + 1)?;
            let (timer, target, surface) = (&mut self.timer, &self.target, &self.surface);
            ctx.submit_and_wait("grow frame", |cmd| {
                timer.reset(cmd);
                if P::ON_GPU {
                    let span = timer.begin(cmd, "ring growth")?;
                    growth.record_pass(cmd)?;
                    timer.end(cmd, span);
                }
                let span = timer.begin(cmd, "shading")?;
                target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
                surface.draw(cmd, growth.source())?;
                target.end(cmd);
                timer.end(cmd, span);
                Ok(())
            })?;
            cpu.push(t.elapsed().as_secs_f64() * 1e3);
            let frame_spans = self.timer.read()?;
            pass_ms.push(if P::ON_GPU {
                frame_spans
                    .iter()
                    .filter(|s| s.name == "ring growth")
                    .map(|s| s.milliseconds)
                    .sum()
            } else {
                cpu_pass_ms
            });
            spans.push(frame_spans);
        }
        let mut s = summarise("grow", variant, &spans, &cpu);
        for &k in &RING_MARKS {
            let lo = (k as usize).saturating_sub(2);
            let hi = (k as usize + 2).min(pass_ms.len().saturating_sub(1));
            let window = pass_ms.get(lo..=hi).unwrap_or(&[]);
            s.metrics
                .insert(format!("pass_ms_at_ring_{k}"), Stats::of(window).median);
        }
        // O(mesh) or O(one ring): how much dearer a pass is late in the growth.
        if let (Some(early), Some(late)) = (
            s.metrics.get("pass_ms_at_ring_8").copied(),
            s.metrics.get("pass_ms_at_ring_128").copied(),
        ) {
            s.metrics
                .insert("pass_ratio_ring_128_to_8".into(), late / early.max(1e-9));
        }
        let vertices = growth.emitted_vertices(self.counts)?;
        let total_ms: f64 = pass_ms.iter().sum();
        s.metrics.insert(
            "vertices_per_s".into(),
            vertices / (total_ms / 1e3).max(1e-9),
        );
        s.metrics
            .insert("final_vertices".into(), growth.final_vertices()?);
        Ok(s)
    }
}

/// The CPU growth path: each pass generated by `grow_pass` (the GS pass's CPU twin)
/// and uploaded whole into a host-visible vertex buffer the surface pass draws.
pub struct CpuGrowth {
    steps: Vec<glam::Vec4>,
    speleothems: usize,
    segments: u32,
    passes: u32,
    done: u32,
    mesh: Vec<RingVertex>,
    next: Vec<RingVertex>,
    buffer: crate::gpu::Buffer,
}

impl CpuGrowth {
    pub fn new(ctx: &Arc<Context>, plan: &crate::model::speleothem::GrowthPlan) -> Result<Self> {
        let max_vertices = vertex_counts(plan).into_iter().max().unwrap_or(1) as usize;
        let mut buffer = crate::gpu::Buffer::new(
            ctx,
            "cpu-grown mesh",
            crate::gpu::BufferDesc::upload(
                (max_vertices * size_of::<RingVertex>()) as u64,
                crate::gpu::vk::BufferUsageFlags::VERTEX_BUFFER,
            ),
        )?;
        let mesh = initial_rings(plan);
        buffer.write(0, &mesh)?;
        Ok(Self {
            steps: plan.gpu_steps(),
            speleothems: plan.speleothems.len(),
            segments: plan.segments,
            passes: plan.passes,
            done: 0,
            mesh,
            next: Vec::with_capacity(max_vertices),
            buffer,
        })
    }

    /// Generates the next pass and uploads it.
    pub fn advance(&mut self) -> Result<()> {
        if self.done >= self.passes {
            return Err(Error::invalid(
                "CPU growth",
                "every pass of the plan is done",
            ));
        }
        self.next.clear();
        grow_pass(
            &self.mesh,
            &self.steps,
            self.speleothems,
            self.segments,
            self.done,
            &mut self.next,
        );
        std::mem::swap(&mut self.mesh, &mut self.next);
        self.buffer.write(0, &self.mesh)?;
        self.done += 1;
        Ok(())
    }

    pub fn mesh(&self) -> &[RingVertex] {
        &self.mesh
    }

    /// The uploaded mesh as the GPU reads it.
    pub fn uploaded(&self) -> Result<Vec<RingVertex>> {
        let mut all: Vec<RingVertex> = self.buffer.read()?;
        all.truncate(self.mesh.len());
        Ok(all)
    }

    pub fn source(&self) -> MeshSource<'_> {
        MeshSource::Counted {
            buffer: &self.buffer,
            vertices: self.mesh.len() as u32,
        }
    }
}

fn dunes_series(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    report: &mut Report,
    progress: &mut dyn FnMut(&str),
) -> Result<()> {
    progress("dunes simulation");
    let base = dunes::preset("fig17")?;
    let terrain = dunes::simulate(&base, &mut |_, _| {})?;
    let variants: [(&str, bool, bool, dunes::Shadows, bool); 6] = [
        (
            "cull-off-lod-off",
            false,
            false,
            dunes::Shadows::None,
            false,
        ),
        ("cull-on-lod-off", true, false, dunes::Shadows::None, false),
        ("cull-on-lod-on", true, true, dunes::Shadows::None, false),
        ("dune-shadows", true, true, dunes::Shadows::Dune, false),
        (
            "dune-ripple-shadows",
            true,
            true,
            dunes::Shadows::DuneAndRipple,
            false,
        ),
        (
            "all-with-dust",
            true,
            true,
            dunes::Shadows::DuneAndRipple,
            true,
        ),
    ];
    let mut medians = BTreeMap::new();
    for (name, cull, lod, shadows, dust) in variants {
        if !opts.wants(name) {
            continue;
        }
        progress(&format!("dunes {name}"));
        let scene = dunes::DunesScene {
            cull,
            lod,
            shadows,
            dust: if dust {
                Some(crate::model::dust::DustParams::default())
            } else {
                None
            },
            ..base.clone()
        };
        let out = dunes::render_timed(ctx, &scene, &terrain, opts.size, opts.warmup + opts.frames)?;
        let skip = opts.warmup as usize;
        let gpu: Vec<f64> = out.timed_ms.iter().skip(skip).copied().collect();
        let cpu: Vec<f64> = out.timed_wall_ms.iter().skip(skip).copied().collect();
        let spans: Vec<Vec<Span>> = gpu
            .iter()
            .map(|&ms| {
                vec![Span {
                    name: "dunes".into(),
                    milliseconds: ms,
                }]
            })
            .collect();
        let mut s = summarise("dunes", name, &spans, &cpu);
        for p in &out.precompute {
            s.metrics.insert(
                format!("{}_gpu_ms", p.name.replace(' ', "_")),
                p.milliseconds,
            );
        }
        s.metrics
            .insert("triangles_drawn".into(), f64::from(out.visible_triangles));
        medians.insert(name, s.frame_gpu_ms.median);
        report.series.push(s);
    }
    // The horizon map on the CPU (the GPU's is among the precompute metrics above) and
    // the sand simulations on one thread and on all.
    if opts.wants("dune-ripple-shadows") {
        progress("dunes precompute and simulation");
        let t = Instant::now();
        let _ = crate::model::ripple_maps::horizon_map(
            &terrain.ripples,
            base.ripple_height_scale,
            base.ripple_size - 1,
        );
        let cpu_horizon = t.elapsed().as_secs_f64() * 1e3;
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::invalid("bench", format!("a one-thread pool: {e}")))?;
        let sim = |params: SandParams, size: usize, steps: u32| -> Result<f64> {
            let mut s = SandSim::new(Heightfield::random(size, size, 8.0, 1.0, 7), params)?;
            let t = Instant::now();
            s.run(steps, &mut |_| {});
            Ok((size * size) as f64 * f64::from(steps) / t.elapsed().as_secs_f64().max(1e-9))
        };
        let mut m = BTreeMap::new();
        m.insert("horizon_map_cpu_ms".to_owned(), cpu_horizon);
        m.insert(
            "ripple_sim_cell_steps_per_s_all_threads".to_owned(),
            sim(SandParams::paper_ripples(), 256, 200)?,
        );
        m.insert(
            "ripple_sim_cell_steps_per_s_1_thread".to_owned(),
            one.install(|| sim(SandParams::paper_ripples(), 256, 200))?,
        );
        m.insert(
            "dune_sim_cell_steps_per_s_all_threads".to_owned(),
            sim(SandParams::paper_dunes(), 64, 500)?,
        );
        m.insert(
            "dune_sim_cell_steps_per_s_1_thread".to_owned(),
            one.install(|| sim(SandParams::paper_dunes(), 64, 500))?,
        );
        if let Some(s) = report
            .series
            .iter_mut()
            .find(|s| s.scene == "dunes" && s.variant == "dune-ripple-shadows")
        {
            s.metrics.extend(m);
        }
    }
    let ratio = |a: &str, b: &str| match (medians.get(a), medians.get(b)) {
        (Some(x), Some(y)) if *y > 0.0 => Some(x / y),
        _ => None,
    };
    let mut push = |what: &str, paper: &str, paper_ratio: f64, ours: Option<f64>| {
        if let Some(ours) = ours {
            report.paper_ratios.push(PaperRatio {
                what: what.to_owned(),
                paper: paper.to_owned(),
                paper_ratio,
                ours,
            });
        }
    };
    push(
        "culling (no culling / culling, no LOD)",
        "15 s -> 9.7 s",
        15.0 / 9.7,
        ratio("cull-off-lod-off", "cull-on-lod-off"),
    );
    push(
        "LOD (no LOD / LOD, culling on)",
        "9.7 s -> 1.5 s",
        9.7 / 1.5,
        ratio("cull-on-lod-off", "cull-on-lod-on"),
    );
    push(
        "dune shadows (with / without)",
        "1.5 s -> 9.1 s",
        9.1 / 1.5,
        ratio("dune-shadows", "cull-on-lod-on"),
    );
    push(
        "ripple shadows (dune+ripple / dune)",
        "9.1 s -> 10.2 s",
        10.2 / 9.1,
        ratio("dune-ripple-shadows", "dune-shadows"),
    );
    if let Some(full) = medians.get("dune-ripple-shadows") {
        push(
            "full effect set at 720x480: paper time / ours",
            "10.2 s",
            1.0,
            Some(10_200.0 / full.max(1e-9)),
        );
    }
    Ok(())
}

fn cave_series(
    ctx: &Arc<Context>,
    opts: &BenchOptions,
    report: &mut Report,
    progress: &mut dyn FnMut(&str),
) -> Result<()> {
    for depth in 5..=9u32 {
        let name = format!("depth-{depth}");
        if !opts.wants(&name) {
            continue;
        }
        progress(&format!("cave {name}"));
        let mut scene = cave::CaveScene::default();
        scene.cave.depth = depth;
        let model = cave::build(&scene, &|_, _, _| {})?;
        let camera = cave::default_camera(&scene, &model);
        let cameras = vec![camera; (opts.warmup + opts.frames) as usize];
        let t = Instant::now();
        let out = cave::render(ctx, &scene, &model, opts.size, &cameras)?;
        let wall = t.elapsed().as_secs_f64() * 1e3 / cameras.len().max(1) as f64;
        let frames: Vec<&crate::render::RenderedFrame> =
            out.frames.iter().skip(opts.warmup as usize).collect();
        let spans: Vec<Vec<Span>> = frames.iter().map(|f| f.gpu_spans.clone()).collect();
        let cpu: Vec<f64> = frames.iter().map(|f| f.wall_ms).collect();
        let mut s = summarise("cave", &name, &spans, &cpu);
        let tm = &model.cave.timings;
        for (k, v) in [
            ("octree_ms", tm.build_ms),
            ("walls_ms", tm.extract_ms),
            ("split_ms", tm.split_ms),
            ("smooth_ms", tm.smooth_ms),
            ("generation_ms", tm.total_ms()),
            (
                "triangles_before_split",
                model.cave.triangles_before_split as f64,
            ),
            (
                "triangles_after_split",
                model.cave.triangles_after_split() as f64,
            ),
            ("mean_wall_ms_per_frame", wall),
        ] {
            s.metrics.insert(k.to_owned(), v);
        }
        report.series.push(s);
    }
    Ok(())
}

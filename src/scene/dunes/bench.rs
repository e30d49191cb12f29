//! How `sediment bench` times the desert: Onoue & Nishita's comparison at the
//! figure-17 scene — culling and LOD on and off (LOD per pixel and, as the paper
//! chooses it, per quad), shadows none / dune / dune+ripple,
//! dust — then the horizon-map precomputation on the CPU, the sand simulations on one
//! thread and on all, and the paper's ratios.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Instant;

use super::frame::{DunesFrame, Terrain, desert_light, simulate};
use super::{DunesScene, Shadows, default_camera, preset};
use crate::Size;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::frame::{BenchAdditions, BenchScene, PaperRatio, Scene, SeriesOutcome};
use crate::gpu::Context;
use crate::model::footprints::{Walk, fig18_walk};
use crate::model::sand::{Heightfield, SandParams, SandSim};

/// One timed set-up of the figure-17 scene.
struct Variant {
    name: &'static str,
    cull: bool,
    lod: bool,
    /// LOD chosen per quad (the paper's) rather than per pixel.
    lod_per_quad: bool,
    shadows: Shadows,
    dust: bool,
    /// Fig. 18's footprints in the detail field (issue 15's "every effect").
    footprints: bool,
    /// The desert to the horizon (`--endless`); off, the period repeated 3 x 3.
    endless: bool,
}

const fn variant(
    name: &'static str,
    cull: bool,
    lod: bool,
    shadows: Shadows,
    dust: bool,
) -> Variant {
    Variant {
        name,
        cull,
        lod,
        lod_per_quad: false,
        shadows,
        dust,
        footprints: false,
        endless: true,
    }
}

const VARIANTS: [Variant; 8] = [
    variant("cull-off-lod-off", false, false, Shadows::None, false),
    variant("cull-on-lod-off", true, false, Shadows::None, false),
    variant("cull-on-lod-on", true, true, Shadows::None, false),
    Variant {
        lod_per_quad: true,
        ..variant("cull-on-lod-quad", true, true, Shadows::None, false)
    },
    variant("dune-shadows", true, true, Shadows::Dune, false),
    // Every effect (issue 15's budgets): both shadows and the footprints, and dust.
    Variant {
        footprints: true,
        ..variant(
            "dune-ripple-shadows",
            true,
            true,
            Shadows::DuneAndRipple,
            false,
        )
    },
    Variant {
        footprints: true,
        ..variant("all-with-dust", true, true, Shadows::DuneAndRipple, true)
    },
    // Every effect but the desert beyond the period: what `--endless` costs.
    Variant {
        footprints: true,
        endless: false,
        ..variant(
            "dune-ripple-shadows-tiled",
            true,
            true,
            Shadows::DuneAndRipple,
            false,
        )
    },
];

const NAMES: &[&str] = &[
    VARIANTS[0].name,
    VARIANTS[1].name,
    VARIANTS[2].name,
    VARIANTS[3].name,
    VARIANTS[4].name,
    VARIANTS[5].name,
    VARIANTS[6].name,
    VARIANTS[7].name,
];

/// The figure-17 scene's variants over one simulated terrain.
#[derive(Default)]
pub struct DunesBench {
    /// The base scene and its terrain, simulated on the first variant.
    base: Option<(DunesScene, Terrain)>,
    /// The frame size the variants were built at (for the paper row's label).
    size: Option<Size>,
}

impl DunesBench {
    fn base(&mut self) -> Result<&(DunesScene, Terrain)> {
        if self.base.is_none() {
            let scene = preset("fig17")?;
            let terrain = simulate(&scene, &mut |_, _| {})?;
            self.base = Some((scene, terrain));
        }
        self.base
            .as_ref()
            .ok_or_else(|| Error::internal("dunes bench", "no base scene"))
    }
}

impl BenchScene for DunesBench {
    fn variants(&self) -> &'static [&'static str] {
        NAMES
    }

    fn build(
        &mut self,
        ctx: &Arc<Context>,
        variant: &str,
        size: Size,
    ) -> Result<(Box<dyn Scene>, Camera)> {
        self.size = Some(size);
        let v = VARIANTS
            .iter()
            .find(|v| v.name == variant)
            .ok_or_else(|| Error::internal("dunes bench", format!("variant {variant}")))?;
        let (base, terrain) = self.base()?;
        let scene = DunesScene {
            cull: v.cull,
            lod: v.lod,
            lod_choice: if v.lod_per_quad {
                super::LodChoice::Quad
            } else {
                super::LodChoice::Pixel
            },
            shadows: v.shadows,
            dust: v.dust,
            endless: v.endless,
            ..base.clone()
        };
        // Every variant from Fig. 17's camera (a walk would take the walker's).
        let camera = default_camera(&scene, terrain);
        let scene = DunesScene {
            footprints: Walk(v.footprints.then(|| fig18_walk(scene.field_size()))),
            ..scene
        };
        Ok((Box::new(DunesFrame::new(ctx, scene, terrain)?), camera))
    }

    /// The horizon map on the CPU (the GPU's is among the series' metrics) and the sand
    /// simulations on one thread and on all, beside the full-shadow series; the paper's
    /// ratios from the series' medians.
    fn finish(
        &mut self,
        ctx: &Arc<Context>,
        series: &[SeriesOutcome],
        frames: u32,
        progress: &mut dyn FnMut(&str),
    ) -> Result<BenchAdditions> {
        let mut added = BenchAdditions::default();
        let medians: BTreeMap<String, f64> = series
            .iter()
            .map(|s| (s.variant.clone(), s.median_gpu_ms))
            .collect();
        if medians.contains_key("dune-ripple-shadows") {
            progress("dunes precompute and simulation");
            let mut metrics = self.cpu_metrics()?;
            metrics.extend(self.sky_metrics(ctx)?);
            metrics.extend(self.horizon_metrics(ctx, frames)?);
            added.metrics.extend(
                metrics
                    .into_iter()
                    .map(|(k, v)| ("dune-ripple-shadows".to_owned(), k, v)),
            );
        }
        // Between variants, each as a multiple of its own floor (the floor frames drawn
        // between its frames): two series run a minute apart on a shared machine can
        // differ by more than the effect they compare.
        let relative: BTreeMap<String, f64> = series
            .iter()
            .filter_map(|s| s.times_floor.map(|x| (s.variant.clone(), x)))
            .collect();
        let ratio = |a: &str, b: &str| match (relative.get(a), relative.get(b)) {
            (Some(x), Some(y)) if *y > 0.0 => Some(x / y),
            _ => None,
        };
        let mut push = |what: &str, paper: &str, paper_ratio: f64, ours: Option<f64>| {
            if let Some(ours) = ours {
                added.paper_ratios.push(PaperRatio {
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
            "LOD per quad, the paper's choice (no LOD / LOD, culling on)",
            "9.7 s -> 1.5 s",
            9.7 / 1.5,
            ratio("cull-on-lod-off", "cull-on-lod-quad"),
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
            // The paper's 10.2 s was at 720x480 (Table 1); ours at the bench's size.
            let at = self.size.map_or("the bench size".to_owned(), |s| {
                format!("{}x{}", s.width, s.height)
            });
            push(
                &format!("full effect set at {at} (the paper: 720x480): paper time / ours"),
                "10.2 s",
                1.0,
                Some(10_200.0 / full.max(1e-9)),
            );
        }
        Ok(added)
    }
}

impl DunesBench {
    /// What moving the sun costs the sky: the sky-view table recomputed (both
    /// dispatches, the read-back and the irradiance) for 12 sun elevations after a
    /// warm-up, GPU and wall-clock medians; and the multiple-scattering table, made
    /// once per atmosphere on the CPU.
    fn sky_metrics(&mut self, ctx: &Arc<Context>) -> Result<BTreeMap<String, f64>> {
        let (base, terrain) = self.base()?;
        let air = base.atmosphere();
        let t = Instant::now();
        let multiple = air.multiple_scattering();
        let multiple_ms = t.elapsed().as_secs_f64() * 1e3;
        let pass = crate::render::atmosphere::SkyViewPass::new(ctx, Some(&multiple))?;
        let camera = default_camera(base, terrain);
        let (mut gpu, mut wall) = (Vec::new(), Vec::new());
        for k in 0..13 {
            let e = (-2.0 + 7.5 * k as f32).to_radians();
            let sun = glam::Vec3::new(0.0, e.sin(), e.cos());
            let t = Instant::now();
            let (_, span) = desert_light(ctx, &air, &pass, &camera, sun)?;
            if k > 0 {
                wall.push(t.elapsed().as_secs_f64() * 1e3);
                gpu.push(span.milliseconds);
            }
        }
        let median = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let mut m = BTreeMap::new();
        m.insert("sky_view_recompute_gpu_ms".to_owned(), median(&mut gpu));
        m.insert("sky_view_recompute_wall_ms".to_owned(), median(&mut wall));
        m.insert("multiple_scattering_table_cpu_ms".to_owned(), multiple_ms);
        Ok(m)
    }

    /// The horizon map on the GPU both ways (issue 19 item 1): the paper's brute walk
    /// and the linear-time sweep on the scene's ripple tile, and the sweep on a
    /// 1024 x 1024 tile along 8 and 16 directions; each the median over `frames` builds
    /// (the series' measured frames, clamped to 3..=10: more builds keep a burst of load
    /// on a shared machine from moving the median, and each 1024 x 1024 x 16 build with
    /// its read-back costs wall clock) of the pass's GPU timestamps. Every build is
    /// fresh (pipeline and first-touched memory), as a scene load pays it.
    fn horizon_metrics(
        &mut self,
        ctx: &Arc<Context>,
        frames: u32,
    ) -> Result<BTreeMap<String, f64>> {
        use crate::render::ripple_maps::{HorizonWalk, RippleMaps};
        let (base, terrain) = self.base()?;
        let (field, scale) = (&terrain.ripples, base.drawn_ripple_height_scale());
        let large = Heightfield::random(1024, 1024, 0.0, 1.0, 11);
        let builds = frames.clamp(3, 10);
        let time = |field: &Heightfield, walk: HorizonWalk| -> Result<f64> {
            let mut ms = Vec::new();
            for _ in 0..builds {
                let maps = RippleMaps::build(ctx, field, scale, scale, walk)?;
                ms.extend(
                    maps.spans
                        .iter()
                        .filter(|s| s.name == "horizon map")
                        .map(|s| s.milliseconds),
                );
            }
            Ok(crate::stats::Stats::of(&ms).median)
        };
        let steps = (field.width - 1) as u32;
        let brute = time(field, HorizonWalk::Brute { steps })?;
        let linear = time(field, HorizonWalk::Linear)?;
        let mut m = BTreeMap::new();
        m.insert("horizon_map_brute_gpu_ms".to_owned(), brute);
        m.insert("horizon_map_linear_gpu_ms".to_owned(), linear);
        m.insert(
            "horizon_map_linear_speedup".to_owned(),
            brute / linear.max(1e-9),
        );
        m.insert(
            "horizon_map_linear_1024_gpu_ms".to_owned(),
            time(&large, HorizonWalk::Linear)?,
        );
        // The size: 16 directions (the knight's moves between the 8).
        let mut ms = Vec::new();
        for _ in 0..builds {
            let (_, gpu_ms) = crate::render::ripple_maps::horizon_map_linear_gpu(
                ctx,
                &large,
                scale,
                16,
                Default::default(),
            )?;
            ms.push(gpu_ms);
        }
        m.insert(
            "horizon_map_linear_1024x16_gpu_ms".to_owned(),
            crate::stats::Stats::of(&ms).median,
        );
        Ok(m)
    }

    fn cpu_metrics(&mut self) -> Result<BTreeMap<String, f64>> {
        let (base, terrain) = self.base()?;
        let t = Instant::now();
        let _ = crate::model::ripple_maps::horizon_map(
            &terrain.ripples,
            base.ripple_height_scale,
            base.ripple_size - 1,
        );
        let cpu_horizon = t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        let _ = crate::model::ripple_maps::horizon_map_linear(
            &terrain.ripples,
            base.ripple_height_scale,
        );
        let cpu_horizon_linear = t.elapsed().as_secs_f64() * 1e3;
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| Error::internal("bench", format!("a one-thread pool: {e}")))?;
        // The median of five runs from the same start: one run of a small field is
        // short enough to fall inside one of a shared machine's slow stretches.
        let sim = |params: SandParams, size: usize, steps: u32| -> Result<f64> {
            let mut rates = Vec::new();
            for _ in 0..5 {
                let field = Heightfield::random(size, size, 8.0, 1.0, 7);
                let mut s = SandSim::new(field, params.clone())?;
                let t = Instant::now();
                s.run(steps, &mut |_| {});
                let cell_steps = (size * size) as f64 * f64::from(steps);
                rates.push(cell_steps / t.elapsed().as_secs_f64().max(1e-9));
            }
            Ok(crate::stats::Stats::of(&rates).median)
        };
        let mut m = BTreeMap::new();
        m.insert("horizon_map_cpu_ms".to_owned(), cpu_horizon);
        m.insert("horizon_map_linear_cpu_ms".to_owned(), cpu_horizon_linear);
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
        // The wind law (sequential): picks per second over the preset's 300 first
        // iterations, the median of three runs.
        let mut rates = Vec::new();
        for _ in 0..3 {
            let mut dunes = crate::model::dune_wind::WindDunes::new(
                base.dune_size,
                base.supply_slabs(),
                base.wind_dune_params(),
                7,
            )?;
            let t = Instant::now();
            dunes.run(300, &mut |_| {});
            let picks = (base.dune_size * base.dune_size) as f64 * 300.0;
            rates.push(picks / t.elapsed().as_secs_f64().max(1e-9));
        }
        m.insert(
            "wind_dune_sim_picks_per_s".to_owned(),
            crate::stats::Stats::of(&rates).median,
        );
        Ok(m)
    }
}

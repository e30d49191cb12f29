//! `--json FILE|-` of grow, dunes, cave, layers and rock: what a run made, as one JSON
//! object for scripts (the book's "Reports" chapter documents every key). Every key
//! with a unit names it (`_m`, `_ms`); `made` is the scene's own
//! ([`crate::frame::SceneDef::made`]), the rest is the same for every scene.

use std::path::PathBuf;

use serde_json::{Value, json};

use crate::export::asset::Asset;
use crate::frame::headless::Rendered;

/// The version of the report's layout: it changes when a key is removed or changes
/// meaning (adding keys keeps it).
pub const SCHEMA: &str = "sediment-scene-report/1";

/// What the run was asked for, beside what [`Rendered`] says it made.
pub struct Run<'a> {
    /// The subcommand ("grow").
    pub scene: &'a str,
    /// The preset, if one was given (or named by the scene file).
    pub preset: Option<&'a str>,
    /// The picture's size, pixels.
    pub size: crate::Size,
    /// Every file the run writes, sidecars included, with the option that writes it.
    pub files: &'a [(PathBuf, String)],
}

/// The report of `run`, whose render gave `rendered`.
pub fn report(run: &Run<'_>, rendered: &Rendered) -> Value {
    let picture = rendered.picture.as_ref().map(|shot| {
        json!({
            "gpu_ms": shot.gpu_spans.iter().map(|s| s.milliseconds).sum::<f64>(),
            "gpu_passes": shot
                .gpu_spans
                .iter()
                .map(|s| json!({ "name": s.name, "ms": s.milliseconds }))
                .collect::<Vec<_>>(),
            "wall_ms": shot.wall_ms,
        })
    });
    let timed = (!rendered.timed_ms.is_empty()).then(|| {
        let s = crate::stats::Stats::of(&rendered.timed_ms);
        json!({
            "frames": s.samples,
            "gpu_median_ms": s.median,
            "gpu_min_ms": s.min,
            "gpu_p95_ms": s.p95,
        })
    });
    json!({
        "schema": SCHEMA,
        "sediment": {
            "version": env!("CARGO_PKG_VERSION"),
            "commit": env!("SEDIMENT_GIT_COMMIT"),
        },
        "scene": run.scene,
        "preset": run.preset,
        "size_px": [run.size.width, run.size.height],
        "made": rendered.made.clone().unwrap_or_else(|| json!({})),
        "mesh": rendered.asset.as_ref().map(mesh),
        "files": run
            .files
            .iter()
            .map(|(path, option)| json!({ "path": path, "option": option }))
            .collect::<Vec<_>>(),
        "timings_ms": {
            "model": rendered.model_ms,
            "wall": rendered.wall_ms,
        },
        "picture": picture,
        "timing_frames": timed,
    })
}

/// The exported asset's parts, counts and bounds, in metres as written.
fn mesh(asset: &Asset) -> Value {
    let bounds = |(lo, hi): (glam::Vec3, glam::Vec3)| {
        let short = |v: glam::Vec3| v.to_array().map(crate::text::json_f32);
        json!({ "min": short(lo), "max": short(hi) })
    };
    let counts = asset.counts();
    json!({
        "parts": asset
            .parts
            .iter()
            .map(|p| json!({
                "name": p.name,
                "material": p.material.name,
                "vertices": p.mesh.positions.len(),
                "triangles": p.mesh.indices.len() / 3,
                "lod_triangles": p.mesh.lods.iter().map(|l| l.len() / 3).collect::<Vec<_>>(),
                "bounds_m": bounds(p.mesh.bounds()),
            }))
            .collect::<Vec<_>>(),
        "vertices": counts.vertices,
        "triangles": counts.triangles,
        "bounds_m": bounds(asset.bounds()),
    })
}

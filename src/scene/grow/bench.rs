//! How `sediment bench` times the speleothem growth: a Fig. 9g-like scene (24
//! speleothems, 32 segments, 130 passes, one pass and the shading per frame) on each
//! growth path; the pass time at rings 8, 32 and 128 shows how each path scales as the
//! mesh grows (O(mesh) against O(one ring)).

use std::sync::Arc;

use glam::Vec3;

use super::frame::GrowthFrame;
use crate::Size;
use crate::camera::{Camera, Jitter};
use crate::error::{Error, Result};
use crate::frame::{BenchAdditions, BenchScene, Scene, SeriesOutcome};
use crate::gpu::Context;
use crate::model::speleothem::plan::{GrowthParams, GrowthScene, GrowthUnits};
use crate::model::speleothem::table2::Pil;
use crate::render::growth::GrowthPath;
use crate::render::lighting::Lighting;
use crate::stats::interquartile_mean;

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

/// The variants: one per growth path.
const VARIANTS: &[&str] = &[
    "xfb-restream",
    "xfb-append",
    "compute-restream",
    "cpu-upload",
];

/// The growth paths of the bench scene, without a chamber, under the default light.
pub struct GrowBench;

impl BenchScene for GrowBench {
    fn variants(&self) -> &'static [&'static str] {
        VARIANTS
    }

    fn build(
        &mut self,
        ctx: &Arc<Context>,
        variant: &str,
        _size: Size,
    ) -> Result<(Box<dyn Scene>, Camera)> {
        let path: GrowthPath = variant
            .parse()
            .map_err(|_| Error::internal("grow bench", format!("variant {variant}")))?;
        // Looking up at the stalactites from below.
        let camera = Camera {
            eye: Vec3::new(0.0, 196.5, 4.5),
            target: Vec3::new(0.0, 199.0, 0.0),
            up: Vec3::Y,
            fov_y_degrees: 50.0,
            near: 0.05,
            far: 50.0,
            jitter: Jitter::NONE,
        };
        let frame = GrowthFrame::bare(ctx, growth_scene(), path, Lighting::default())?;
        Ok((Box::new(frame), camera))
    }

    /// For the append-only path, its pass at ring 8 against ring 128 measured in the
    /// same seconds (`pass_ratio_ring_128_to_8_interleaved`; see `interleaved_ratio`).
    fn finish(
        &mut self,
        ctx: &Arc<Context>,
        series: &[SeriesOutcome],
        _frames: u32,
        progress: &mut dyn FnMut(&str),
    ) -> Result<BenchAdditions> {
        let path = GrowthPath::XfbAppend;
        if !series.iter().any(|s| s.variant == path.name()) {
            return Ok(BenchAdditions::default());
        }
        progress("grow: append-only passes at rings 8 and 128, interleaved");
        let ratio = interleaved_ratio(ctx, path)?;
        Ok(BenchAdditions {
            metrics: vec![(
                path.name().to_owned(),
                "pass_ratio_ring_128_to_8_interleaved".to_owned(),
                ratio,
            )],
            paper_ratios: Vec::new(),
        })
    }
}

/// Passes either side of a ring in `interleaved_ratio`.
const HALF_WINDOW: u32 = 7;

/// The pass at ring 128 over the pass at ring 8, the two grown side by side: one
/// growth stands at ring 8 - 7 and another at ring 128 - 7, and their next 15 passes
/// alternate, one of each in turn; the ratio of their interquartile means. In the
/// series (one pass a frame, 130 frames) the two rings are seconds apart, and on
/// lavapipe a pass of one ring takes one of two levels, pass by pass and in stretches,
/// so the series' ratio wanders even where the work does not change; passes grown side
/// by side share the levels, and an interquartile mean averages over them where a
/// median of passes split near half and half takes one level or the other. Only for a
/// path whose pass is O(one ring): a re-streaming path would take seconds to reach ring
/// 121.
fn interleaved_ratio(ctx: &Arc<Context>, path: GrowthPath) -> Result<f64> {
    let (early_ring, late_ring) = (8, 128);
    // Every pass of the bench scene adds the same ring to each speleothem, so ring k
    // of a longer plan is ring k of the series.
    let scene = GrowthScene {
        passes: late_ring + HALF_WINDOW + 1,
        ..growth_scene()
    };
    let light = Lighting::default();
    let mut early = GrowthFrame::bare(ctx, scene.clone(), path, light.clone())?;
    let mut late = GrowthFrame::bare(ctx, scene, path, light)?;
    early.advance(ctx, early_ring - HALF_WINDOW, &mut |_, _| {})?;
    late.advance(ctx, late_ring - HALF_WINDOW, &mut |_, _| {})?;
    let (mut at_early, mut at_late) = (Vec::new(), Vec::new());
    for _ in 0..2 * HALF_WINDOW + 1 {
        at_early.push(early.advance(ctx, 1, &mut |_, _| {})?);
        at_late.push(late.advance(ctx, 1, &mut |_, _| {})?);
    }
    Ok(interquartile_mean(&at_late) / interquartile_mean(&at_early).max(1e-9))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_growth_path_is_a_variant() {
        assert_eq!(
            VARIANTS.to_vec(),
            GrowthPath::ALL.map(GrowthPath::name).to_vec()
        );
    }
}

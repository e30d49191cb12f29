//! How `sediment bench` times the speleothem growth: a Fig. 9g-like scene (24
//! speleothems, 32 segments, 130 passes, one pass and the shading per frame) on each
//! growth path; the pass time at rings 8, 32 and 128 shows how each path scales as the
//! mesh grows (O(mesh) against O(one ring)).

use std::sync::Arc;

use glam::Vec3;

use super::frame::GrowthFrame;
use crate::error::{Error, Result};
use crate::frame::{BenchScene, Scene};
use crate::gpu::Context;
use crate::model::speleothem::plan::{GrowthParams, GrowthScene, GrowthUnits};
use crate::model::speleothem::table2::Pil;
use crate::render::growth::GrowthPath;
use crate::scene::Size;
use crate::scene::camera::{Camera, Jitter, Lighting};

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

//! A scene defined outside sediment: a user's own 16-bit heightmap PNG drawn with the
//! desert's shading — bump-mapped ripples, dune and ripple shadows, the sky — through
//! the same machinery as sediment's own scenes. Registering it gives it a command line
//! with every parameter (`--help`), headless pictures and animations, scene files,
//! the viewer and bench rows:
//!
//! ```text
//! cargo run --release --example custom_scene -- --size 160x120 -o x.png
//! cargo run --release --example custom_scene -- --heightmap my-terrain.png --cell 2 -o t.png
//! cargo run --release --example custom_scene -- bench --frames 5
//! ```
//!
//! Without `--heightmap` it draws a heightmap of its own (a few round hills), so it
//! runs as it is.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

use sediment::camera::{Camera, Jitter};
use sediment::frame::{BenchScene, GalleryShot, Progress, Scene, SceneDef};
use sediment::glam::Vec3;
use sediment::gpu::Context;
use sediment::model::sand::{Heightfield, SandParams, SandSim};
use sediment::params::{Point3, check, no_more_checks};
use sediment::scene::dunes::{DunesFrame, DunesScene, Terrain};
use sediment::{Error, Result, Size};

sediment::params! {
    /// A heightmap drawn as a desert: the file, its scale and the light.
    pub struct HeightmapScene {
        /// A square 16-bit greyscale PNG of heights, 8..=512 samples a side; none: a
        /// few round hills of this example's own.
        [top, "Terrain"] heightmap: Option<PathBuf> = None, "FILE.png", "", check::any();
        /// Metres between neighbouring samples.
        [top, "Terrain"] cell: f32 = 4.0, "M", "m", check::above(0.0);
        /// Metres sample value 65535 stands for above sample 0.
        [top, "Terrain"] height: f32 = 12.0, "M", "m", check::above(0.0);
        /// Sun elevation above the horizon.
        [top, "Light"] sun_elevation: f32 = 20.0, "DEG", "degrees", check::within(-2.0..=90.0);
        /// Sun azimuth, from +x toward +z.
        [top, "Light"] sun_azimuth: f32 = 200.0, "DEG", "degrees", check::any();
        /// Camera position x,y,z in metres; default: over one corner of the terrain.
        [camera, "Camera"] eye: Option<Point3> = None, "X,Y,Z", "m", check::any();
        /// The point the camera looks at.
        [camera, "Camera"] target: Option<Point3> = None, "X,Y,Z", "m", check::any();
    }
    validate = no_more_checks;
}

impl HeightmapScene {
    /// The desert's parameters the shading reads: the sun, the scale, no dust.
    fn desert(&self, samples: usize) -> DunesScene {
        DunesScene {
            dune_size: samples,
            cell: self.cell,
            sun_elevation: self.sun_elevation,
            sun_azimuth: self.sun_azimuth,
            ripple_size: 64,
            ..DunesScene::default()
        }
    }
}

/// The heights in metres, a square side long: the file's, or round hills.
fn heights(params: &HeightmapScene) -> Result<(usize, Vec<f32>)> {
    let Some(path) = &params.heightmap else {
        let n = 64;
        let hill = |x: f32, z: f32, cx: f32, cz: f32, r: f32| {
            let d2 = ((x - cx).powi(2) + (z - cz).powi(2)) / (r * r);
            (-d2).exp()
        };
        let h = (0..n * n)
            .map(|i| {
                let (x, z) = ((i % n) as f32 / n as f32, (i / n) as f32 / n as f32);
                params.height
                    * (0.6 * hill(x, z, 0.3, 0.4, 0.18) + hill(x, z, 0.65, 0.6, 0.22)).min(1.0)
            })
            .collect();
        return Ok((n, h));
    };
    let image = image::open(path)
        .map_err(|e| Error::invalid("heightmap", format!("{}: {e}", path.display())))?
        .into_luma16();
    let (w, h) = image.dimensions();
    if w != h || !(8..=512).contains(&w) {
        return Err(Error::invalid(
            "heightmap",
            format!("must be square, 8..=512 samples a side, not {w}x{h}"),
        ));
    }
    let scale = params.height / 65535.0;
    Ok((
        w as usize,
        image.pixels().map(|p| f32::from(p.0[0]) * scale).collect(),
    ))
}

/// The heightmap drawn as a desert, registered as a scene.
struct HeightmapDef;

impl SceneDef for HeightmapDef {
    type Params = HeightmapScene;
    type Model = (DunesScene, Terrain);

    fn name(&self) -> &'static str {
        "heightmap"
    }

    fn about(&self) -> &'static str {
        "Draw a 16-bit heightmap PNG as a desert: sediment's dune shading, ripples, \
         shadows and sky over terrain of your own."
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        &[("hills", "the example's own round hills under a low sun")]
    }

    fn preset(&self, name: &str) -> Result<HeightmapScene> {
        match name {
            "hills" => Ok(HeightmapScene {
                sun_elevation: 10.0,
                ..HeightmapScene::default()
            }),
            other => Err(Error::unknown_preset(other, self.presets())),
        }
    }

    /// Nothing here is random but the ripples', which keep their own seed.
    fn set_seed(&self, _params: &mut HeightmapScene, _seed: u64) {}

    fn inputs(&self, params: &HeightmapScene) -> Vec<PathBuf> {
        params.heightmap.iter().cloned().collect()
    }

    fn model(
        &self,
        params: &HeightmapScene,
        progress: Progress<'_>,
    ) -> Result<(DunesScene, Terrain)> {
        let (n, dune_heights) = heights(params)?;
        let desert = params.desert(n);
        // A small ripple tile for the bump mapping, from the paper's ripple law.
        let mut ripples = SandSim::new(
            Heightfield::random(desert.ripple_size, desert.ripple_size, 0.0, 1.0, 7),
            SandParams::paper_ripples(),
        )?;
        ripples.run(300, &mut |d| progress("ripples", d, 300));
        let scale = (SandParams::paper_dunes().vertical_scale as f32 * desert.cell) as f64;
        let dune_field = Heightfield {
            width: n,
            height: n,
            data: dune_heights.iter().map(|&h| f64::from(h) / scale).collect(),
        };
        Ok((
            desert,
            Terrain {
                dune_heights,
                ripples: ripples.field().clone(),
                dune_field,
                // A heightmap's ground has no floor of rock under it.
                bedrock_m: None,
            },
        ))
    }

    fn camera(&self, params: &HeightmapScene, model: &(DunesScene, Terrain)) -> Camera {
        let side = model.0.field_size();
        Camera {
            eye: Vec3::new(-0.1 * side, 1.6 * params.height + 0.12 * side, -0.1 * side),
            target: Vec3::new(0.55 * side, 0.2 * params.height, 0.55 * side),
            up: Vec3::Y,
            fov_y_degrees: 50.0,
            near: 0.5,
            far: 6.0 * side,
            jitter: Jitter::NONE,
        }
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        _params: &HeightmapScene,
        model: &Arc<(DunesScene, Terrain)>,
        _realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        Ok(Box::new(DunesFrame::new(ctx, model.0.clone(), &model.1)?))
    }

    fn gallery(&self) -> Vec<GalleryShot> {
        vec![GalleryShot {
            name: "heightmap-hills",
            preset: "hills",
            set: &[],
            animated: false,
            files: &[],
            description: "a heightmap of round hills drawn as a desert",
        }]
    }

    fn bench(&self) -> Option<Box<dyn BenchScene>> {
        Some(Box::new(HillsBench))
    }
}

/// The bench's one series: the hills at the default sun.
struct HillsBench;

impl BenchScene for HillsBench {
    fn variants(&self) -> &'static [&'static str] {
        &["hills"]
    }

    fn build(
        &mut self,
        ctx: &Arc<Context>,
        _variant: &str,
        _size: Size,
    ) -> Result<(Box<dyn Scene>, Camera)> {
        let params = HeightmapScene::default();
        let model = Arc::new(HeightmapDef.model(&params, &|_, _, _| {})?);
        let camera = HeightmapDef.camera(&params, &model);
        Ok((HeightmapDef.frame(ctx, &params, &model, true)?, camera))
    }
}

fn main() -> ExitCode {
    sediment::cli::scene_main("custom_scene", &HeightmapDef)
}

//! `sediment grow`: Tortelli & Walter's speleothem growth on the GS/XFB pipeline.

use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::export::mesh::{check_mesh_path, write_mesh};
use sediment::render::growth::GrowthPath;
use sediment::scene::grow;
use sediment::scene::params::SceneFileArgs;

use crate::{Cli, fail_on_validation_errors, open_context, progress, scene_or_print};

#[derive(clap::Args, Debug)]
pub struct GrowArgs {
    #[command(flatten)]
    pub scene: grow::Params,
    #[command(flatten)]
    pub file: SceneFileArgs,
    /// The growth path: `restream` (the paper's GS/XFB pass, the whole mesh through the
    /// geometry shader every pass), `append` (only the growth front through the same
    /// shader; new bands appended by resuming the transform-feedback counter, O(one
    /// ring) per pass), `compute` (the same pass as a compute shader) or `cpu` (the CPU
    /// reference, uploaded). All give the same mesh.
    #[arg(
        long,
        value_name = "restream|append|compute|cpu",
        default_value = "restream"
    )]
    growth: GrowthPath,
    /// The final frame as PNG (default grow.png when no other output is asked for).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The growth in fast motion as an animated GIF (default: not written).
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// One GIF frame every K passes, 1..=512 (default 1).
    #[arg(long, value_name = "K", default_value_t = 1)]
    gif_every: u32,
    /// The grown mesh read back from the GPU: .glb (glTF 2.0 binary: stalactites,
    /// stalagmites and columns as named parts with materials and the mineral colours)
    /// or .obj (with its .mtl and sRGB vertex colours). Metres, y up, the chamber's floor
    /// centre at the origin (default: not written).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// Metres per scene unit in the exported mesh, (0, 1000] (default 1: the chamber is
    /// 2.4 m high and a ring starts 9 cm wide, a cave chamber's size).
    #[arg(long, value_name = "M", default_value_t = 1.0)]
    unit_scale: f32,
    /// Every ring of every speleothem as CSV: speleothem, kind, ring, year (with
    /// --climate; else the pass), height along the growth and radius in metres
    /// (default: not written).
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// The first stalagmite cut open (a wedge removed), its rings as growth layers in
    /// bands of 10 rings (with --climate, 1000 years at 100 years a pass), rendered
    /// at --size as `sediment layers --render` draws Franke's layers (default: not written).
    #[arg(long, value_name = "FILE.png")]
    cut_away: Option<PathBuf>,
}

pub fn run(cli: &Cli, a: &GrowArgs) -> anyhow::Result<()> {
    // Everything the user gave is checked before any GPU work or file is touched.
    let Some(resolved) = scene_or_print(cli, &a.scene, &a.file)? else {
        return Ok(());
    };
    let scene = &resolved.scene;
    let camera = resolved.camera.over(grow::default_camera(&scene.growth))?;
    if !(1..=512).contains(&a.gif_every) {
        bail!(sediment::Error::invalid(
            "--gif-every",
            "must be in 1..=512"
        ));
    }
    let output = super::picture(
        &a.output,
        &[&a.gif, &a.mesh, &a.csv, &a.cut_away],
        "grow.png",
    );
    if let Some(o) = &output {
        check_extension(o, "-o", &["png"])?;
    }
    if let Some(g) = &a.gif {
        check_extension(g, "--gif", &["gif"])?;
    }
    if let Some(mesh) = &a.mesh {
        check_mesh_path(mesh, "--mesh")?;
    }
    if let Some(csv) = &a.csv {
        check_extension(csv, "--csv", &["csv"])?;
        // Not the climate record or the scene file it was read from.
        let climate = a.scene.growth.climate.as_deref().map(std::path::Path::new);
        let inputs: Vec<&std::path::Path> = [climate, a.file.scene.as_deref()]
            .into_iter()
            .flatten()
            .collect();
        sediment::export::check_not_input(csv, "--csv", &inputs)?;
    }
    if let Some(cut) = &a.cut_away {
        check_extension(cut, "--cut-away", &["png"])?;
        let plan = scene.growth.plan()?;
        if !plan
            .speleothems
            .iter()
            .any(|s| s.kind == sediment::model::speleothem::Kind::Stalagmite)
        {
            bail!(sediment::Error::invalid(
                "--cut-away",
                "needs a stalagmite: grow with --pil 2 or --climate"
            ));
        }
    }
    if !(a.unit_scale > 0.0 && a.unit_scale <= 1000.0) {
        bail!(sediment::Error::invalid(
            "--unit-scale",
            "must be in (0, 1000] metres per scene unit"
        ));
    }
    let ctx = open_context(cli)?;
    let outputs = grow::GrowOutputs {
        look: scene.look.clone(),
        camera: Some(camera),
        path: a.growth,
        frame_every: a.gif.as_ref().map(|_| a.gif_every),
        mesh: a.mesh.is_some(),
    };
    // The GIF is encoded frame by frame as the growth goes (one frame in memory),
    // into a temporary file renamed into place when the growth succeeded.
    let mut gif = a
        .gif
        .as_ref()
        .map(|path| sediment::export::gif::GifStream::create(path, 80))
        .transpose()?;
    let grown = grow::grow_streaming(
        &ctx,
        &scene.growth,
        cli.size,
        &outputs,
        &mut |done, total| progress(done as usize, total as usize, "passes"),
        &mut |frame| gif.as_mut().map_or(Ok(()), |g| g.push(frame)),
    )?;
    crate::output::done();
    fail_on_validation_errors(&ctx)?;
    if let Some(path) = &output {
        sediment::export::png::write_png(path, &grown.image)?;
        crate::output::wrote(path);
    }
    if let (Some(path), Some(gif)) = (&a.gif, gif) {
        let frames = gif.finish()?;
        crate::output::wrote_line(format!("wrote {} ({frames} frames)", path.display()));
    }
    if let (Some(path), Some(mesh)) = (&a.mesh, &grown.mesh) {
        let title = format!("grow {}", a.scene.preset.as_deref().unwrap_or("scene"));
        let asset = grow::export_asset(
            &grown.plan,
            mesh,
            &title,
            a.unit_scale,
            scene.growth.floor_y,
        );
        crate::output::wrote_line(write_mesh(path, &asset)?.line());
    }
    if let Some(path) = &a.csv {
        grow::write_rings_csv(path, &grown.plan)?;
        crate::output::wrote_line(format!(
            "wrote {} (every ring: date, height, radius)",
            path.display()
        ));
    }
    if let Some(path) = &a.cut_away {
        let image = grow::cut_away_render(&ctx, &grown.plan, cli.size)?;
        fail_on_validation_errors(&ctx)?;
        sediment::export::png::write_png(path, &image)?;
        crate::output::wrote_line(format!(
            "wrote {} (the first stalagmite's rings as growth layers)",
            path.display()
        ));
    }
    if let Some((first, years)) = grown.plan.dates {
        log::info!(
            "climate: {} to {}, {years} years a pass",
            sediment::model::speleothem::climate::calendar_year(first),
            sediment::model::speleothem::climate::calendar_year(
                first + f64::from(grown.plan.passes) * years
            )
        );
    }
    let stopped = grown
        .plan
        .speleothems
        .iter()
        .filter(|s| s.stop.is_some())
        .count();
    log::info!(
        "{} speleothems, {} passes ({} stopped growing); GPU {}; wall {:.1} ms",
        grown.plan.speleothems.len(),
        grown.plan.passes,
        stopped,
        sediment::frame::spans_line(&grown.gpu_spans),
        grown.wall_ms
    );
    Ok(())
}

//! `sediment dunes`: Onoue & Nishita's desert of dunes and wind ripples.

use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::scene::dunes;
use sediment::scene::params::SceneFileArgs;

use crate::{Cli, fail_on_validation_errors, open_context, progress, scene_or_print};

#[derive(clap::Args, Debug)]
pub struct DunesArgs {
    #[command(flatten)]
    pub scene: dunes::Params,
    #[command(flatten)]
    pub file: SceneFileArgs,
    /// The frame as PNG (default dunes.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// An animated GIF: with --dust the dust blowing over the dunes (two time steps a
    /// frame), else the ripples and dunes forming over time (each frame renders the
    /// simulation part of the way through) (default: not written).
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=120 (default 12).
    #[arg(long, value_name = "N", default_value_t = 12)]
    gif_frames: u32,
    /// The dune field's heights: .png (16-bit greyscale, the metres at 0 and 65535 and
    /// the cell size in its tEXt chunks) or .exr (float metres); the range also goes
    /// to FILE.json, and the ripple tile beside it as FILE-ripples.png/.exr (+ .json)
    /// (default: not written).
    #[arg(long, value_name = "FILE.png|FILE.exr")]
    heightmap: Option<PathBuf>,
    /// The dune field as .glb (one period, tiling seamlessly, with UVs, the ripples as
    /// an embedded normal map and the sand's grain as a base colour map) or .obj (with
    /// its .mtl and the normal map beside it). Metres, y up, the field's centre at the
    /// origin and its lowest sand at y = 0 (default: not written).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// Render the frame this many more times, 0..=1000, and print the median, minimum
    /// and 95th percentile of their GPU times (the first frame, which includes
    /// lavapipe's shader compilation, is not counted). `sediment bench` is the full
    /// instrument; this is the quick look.
    #[arg(long, value_name = "N", default_value_t = 0)]
    timing_frames: u32,
}

pub fn run(cli: &Cli, a: &DunesArgs) -> anyhow::Result<()> {
    let Some(resolved) = scene_or_print(cli, &a.scene, &a.file)? else {
        return Ok(());
    };
    let scene = &resolved.scene;
    if a.timing_frames > 1000 {
        bail!(sediment::Error::invalid(
            "--timing-frames",
            "must be 0..=1000"
        ));
    }
    if let Some(g) = &a.gif {
        check_extension(g, "--gif", &["gif"])?;
        if !(2..=120).contains(&a.gif_frames) {
            bail!(sediment::Error::invalid(
                "--gif-frames",
                "must be in 2..=120"
            ));
        }
    }
    if let Some(o) = &a.output {
        check_extension(o, "-o", &["png"])?;
    }
    if let Some(h) = &a.heightmap {
        check_extension(
            h,
            "--heightmap",
            sediment::export::heightmap::HEIGHTMAP_FORMATS,
        )?;
    }
    if let Some(m) = &a.mesh {
        sediment::export::mesh::check_mesh_path(m, "--mesh")?;
    }
    let ctx = open_context(cli)?;
    let sim_start = std::time::Instant::now();
    let terrain = dunes::simulate(scene, &mut |d, t| {
        progress(d as usize, t as usize, "simulation steps")
    })?;
    let sim_s = sim_start.elapsed().as_secs_f64();
    crate::output::done();
    let cell_steps = (scene.ripple_size * scene.ripple_size) as f64 * f64::from(scene.ripple_steps)
        + (scene.dune_size * scene.dune_size) as f64 * f64::from(scene.dune_steps);
    log::info!(
        "simulated {:.1} M cell-steps in {sim_s:.2} s ({:.0} M cell-steps/s on {} threads)",
        cell_steps / 1e6,
        cell_steps / 1e6 / sim_s.max(1e-9),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    // One camera for every frame: the final terrain's.
    let camera = resolved
        .camera
        .over(dunes::default_camera(scene, &terrain))?;
    let out = dunes::render(
        &ctx,
        scene,
        &terrain,
        cli.size,
        Some(&camera),
        a.timing_frames,
    )?;
    fail_on_validation_errors(&ctx)?;
    let output = super::picture(&a.output, &[&a.gif, &a.heightmap, &a.mesh], "dunes.png");
    if let Some(output) = &output {
        sediment::export::png::write_png(output, &out.image)?;
        crate::output::wrote(output);
    }
    if let Some(path) = &a.gif {
        // Each frame goes to the encoder as it is rendered: one frame in memory.
        let mut gif = sediment::export::gif::GifStream::create(path, 150)?;
        let frames = a.gif_frames as usize;
        if scene.dust.is_some() {
            // The dust blowing over the final terrain, two time steps a frame.
            let times: Vec<u32> = (0..a.gif_frames).map(|i| 2 * i).collect();
            dunes::render_times(
                &ctx,
                scene,
                &terrain,
                cli.size,
                &camera,
                &times,
                &mut |i, image| {
                    progress(i + 1, frames, "animation frames");
                    gif.push(&image)
                },
            )?;
        } else {
            // The simulation again in chunks, one frame rendered after each (the same
            // seed gives the same final terrain).
            dunes::simulate_frames(
                scene,
                a.gif_frames,
                &mut |d, t| progress(d as usize, t as usize, "animation (simulation and frames)"),
                &mut |_, snapshot| {
                    let image =
                        dunes::render(&ctx, scene, snapshot, cli.size, Some(&camera), 0)?.image;
                    gif.push(&image)
                },
            )?;
        }
        crate::output::done();
        fail_on_validation_errors(&ctx)?;
        let written = gif.finish()?;
        crate::output::wrote_line(format!("wrote {} ({written} frames)", path.display()));
    }
    if let Some(path) = &a.heightmap {
        use sediment::export::heightmap::write_heightmap;
        let ripples = ripple_tile_path(path);
        for (target, map, what) in [
            (
                path.clone(),
                dunes::export::dune_heightmap(scene, &terrain),
                "dune field",
            ),
            (
                ripples,
                dunes::export::ripple_heightmap(scene, &terrain),
                "ripple tile",
            ),
        ] {
            let (range, files) = write_heightmap(&target, &map)?;
            let files: Vec<_> = files.iter().map(|f| f.display().to_string()).collect();
            crate::output::wrote_line(format!(
                "wrote {} ({what}; {})",
                files.join(" and "),
                range.line()
            ));
        }
    }
    if let Some(path) = &a.mesh {
        let title = format!("dunes {}", a.scene.preset.as_deref().unwrap_or("scene"));
        let asset = dunes::export::export(scene, &terrain, &out.mesh, &title);
        crate::output::wrote_line(sediment::export::mesh::write_mesh(path, &asset)?.line());
    }
    let spans = sediment::frame::spans_line;
    log::info!(
        "{}/{} dune triangles drawn; GPU frame: {}; precompute: {}; wall {:.1} ms",
        out.visible_triangles,
        out.total_triangles,
        spans(&out.gpu_spans),
        spans(&out.precompute),
        out.wall_ms
    );
    if !out.timed_ms.is_empty() {
        let ms = sediment::stats::Stats::of(&out.timed_ms);
        log::info!(
            "GPU frame over {} timing frames: median {:.2} ms, min {:.2} ms, p95 {:.2} ms",
            ms.samples,
            ms.median,
            ms.min,
            ms.p95
        );
    }
    Ok(())
}

/// Where the ripple tile of `--heightmap FILE.ext` goes: FILE-ripples.ext.
fn ripple_tile_path(path: &std::path::Path) -> PathBuf {
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

//! `sediment cave`: Cui, Chow & Zhang's procedural caves with speleothems.

use std::io::Write as _;
use std::path::PathBuf;

use std::sync::Arc;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::scene::cave;
use sediment::scene::params::SceneFileArgs;

use crate::{Cli, fail_on_validation_errors, open_context, progress, scene_or_print};

#[derive(clap::Args, Debug)]
pub struct CaveArgs {
    #[command(flatten)]
    pub scene: cave::Params,
    #[command(flatten)]
    pub file: SceneFileArgs,
    /// Print the paper's Table 1 counterpart (triangles before/after the crack-free
    /// split and generation time per phase, octree depths 5..9) and exit.
    #[arg(long)]
    table: bool,
    /// The frame as PNG (default cave.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The cave and its speleothems as .glb (glTF 2.0 binary: the walls, stalactites,
    /// stalagmites and columns as named parts with materials) or .obj (with its .mtl).
    /// Metres, y up, the origin at the centre of the cave's floor (default: not written).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// A fly-through along the passage as an animated GIF (default: not written).
    #[arg(long, value_name = "FILE.gif")]
    flythrough: Option<PathBuf>,
    /// Fly-through frames, 2..=240 (default 24).
    #[arg(long, value_name = "N", default_value_t = 24)]
    flythrough_frames: u32,
}

pub fn run(cli: &Cli, a: &CaveArgs) -> anyhow::Result<()> {
    let Some(resolved) = scene_or_print(cli, &a.scene, &a.file)? else {
        return Ok(());
    };
    let scene = &resolved.scene;
    if a.table {
        let rows = cave::table(&scene.cave, &mut |d| {
            progress(d as usize - 5, 5, "octree depths")
        })?;
        crate::output::done();
        say!(
            "| depth | triangles before split | after | increase | paper before | paper after | paper increase | octree ms | walls ms | split ms | smooth ms | total ms |"
        );
        say!("|---|---|---|---|---|---|---|---|---|---|---|---|");
        for (row, (_, pb, pa)) in rows.iter().zip(cave::PAPER_TABLE_1) {
            let t = &row.timings;
            say!(
                "| {} | {} | {} | {:.1} % | {pb} | {pa} | {:.1} % | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} |",
                row.depth,
                row.before,
                row.after,
                100.0 * (row.after - row.before) as f64 / row.before as f64,
                100.0 * (pa - pb) as f64 / pb as f64,
                t.build_ms,
                t.extract_ms,
                t.split_ms,
                t.smooth_ms,
                t.total_ms()
            );
        }
        return Ok(());
    }
    if let Some(o) = &a.output {
        check_extension(o, "-o", &["png"])?;
    }
    if let Some(m) = &a.mesh {
        sediment::export::mesh::check_mesh_path(m, "--mesh")?;
    }
    if let Some(g) = &a.flythrough {
        check_extension(g, "--flythrough", &["gif"])?;
        if !(2..=240).contains(&a.flythrough_frames) {
            bail!(sediment::Error::invalid(
                "--flythrough-frames",
                "must be in 2..=240"
            ));
        }
    }
    let ctx = open_context(cli)?;
    let model = Arc::new(cave::build(scene, &|phase, done, total| {
        progress(done as usize, total as usize, phase);
    })?);
    crate::output::done();
    let c = &model.cave;
    log::info!(
        "octree depth {}: {} nodes; {} -> {} triangles after the crack-free split (+{:.1} %), {} voxels carved for manifoldness; {} speleothem sites ({} columns); generated in {:.0} ms (octree {:.0}, walls {:.0}, split {:.0}, smoothing {:.0})",
        scene.cave.depth,
        c.tree.node_count(),
        c.triangles_before_split,
        c.triangles_after_split(),
        100.0 * (c.triangles_after_split() - c.triangles_before_split) as f64
            / c.triangles_before_split.max(1) as f64,
        c.carved_voxels,
        model.sites.len(),
        model.sites.iter().filter(|s| s.column).count(),
        c.timings.total_ms(),
        c.timings.build_ms,
        c.timings.extract_ms,
        c.timings.split_ms,
        c.timings.smooth_ms
    );
    let camera = resolved.camera.over(cave::default_camera(scene, &model))?;
    let mut cameras = vec![camera];
    if a.flythrough.is_some() {
        cameras.extend(cave::flythrough(scene, &model, a.flythrough_frames));
    }
    // The fly-through's frames go to the GIF as they are made (one in memory); the
    // still (camera 0) is kept.
    let mut gif = a
        .flythrough
        .as_ref()
        .map(|path| sediment::export::gif::GifStream::create(path, 120))
        .transpose()?;
    let rendered = cave::render_streaming(
        &ctx,
        scene,
        &model,
        cli.size,
        &cameras,
        &mut |i, image| match (&mut gif, i) {
            (_, 0) => Ok(true),
            (Some(g), _) => g.push(image).map(|()| false),
            (None, _) => Ok(false),
        },
    )?;
    fail_on_validation_errors(&ctx)?;
    let output = super::picture(&a.output, &[&a.mesh, &a.flythrough], "cave.png");
    let (image, frame) = &rendered.frames[0];
    if let Some(output) = &output {
        sediment::export::png::write_png(output, image)?;
        crate::output::wrote(output);
    }
    if let (Some(path), Some(gif)) = (&a.flythrough, gif) {
        let frames = gif.finish()?;
        crate::output::wrote_line(format!("wrote {} ({frames} frames)", path.display()));
    }
    if let Some(path) = &a.mesh {
        let title = format!("cave {}", a.scene.preset.as_deref().unwrap_or("scene"));
        let asset = cave::export(scene, &model, rendered.grown.as_ref(), &title);
        crate::output::wrote_line(sediment::export::mesh::write_mesh(path, &asset)?.line());
    }
    log::info!(
        "GPU frame: {}; wall {:.1} ms",
        sediment::frame::spans_line(&frame.spans),
        frame.wall_ms
    );
    Ok(())
}

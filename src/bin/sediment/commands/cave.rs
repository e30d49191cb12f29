//! `sediment cave`: Cui, Chow & Zhang's procedural caves with speleothems.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::scene::cave;

use crate::{CameraOverride, Cli, fail_on_validation_errors, open_context, progress};

#[derive(clap::Args, Debug)]
/// The scene options, shared with `sediment view`.
pub struct CaveSceneArgs {
    /// A reproduction of one of the paper's figures: fig5a/fig5b (wireframe/solid
    /// before smoothing), fig5c/fig5d (after), fig8 (a passage with stalactites and
    /// stalagmites, the default).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// Maximum octree depth, 5..=9 (the cube has 2^depth voxels a side; default 7).
    #[arg(long, value_name = "N")]
    pub depth: Option<u32>,
    /// Side of the cave's cube in metres, 1..=10000 (default 24).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cave_size: Option<f32>,
    /// Laplacian weight lambda of eq. (1), 0..=1 (paper 0.5).
    #[arg(long, value_name = "L", allow_negative_numbers = true)]
    pub lambda: Option<f32>,
    /// Smoothing iterations k, 0..=100 (default 4).
    #[arg(long, value_name = "K")]
    pub iterations: Option<u32>,
    /// Wall noise frequency in features per cube side, 1..=64 (default 6).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub noise_scale: Option<f32>,
    /// fBm octaves, 1..=8 (default 4).
    #[arg(long, value_name = "N")]
    pub octaves: Option<u32>,
    /// Wall roughness (noise amplitude), 0..=0.2 of the side (default 0.05).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub roughness: Option<f32>,
    /// Carving threshold, -0.1..=0.1 of the side: higher carves a wider cave (default 0).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub threshold: Option<f32>,
    /// Passage half-height, 0.04..=0.3 of the side (default 0.16).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub half_height: Option<f32>,
    /// Passage half-width, 0.04..=0.3 of the side (default 0.13).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub half_width: Option<f32>,
    /// How far the passage winds sideways, 0..=0.2 of the side (default 0.1).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub meander: Option<f32>,
    /// Speleothems: short (Short et al.'s profile, as the paper), grown (the same
    /// sites grown on the geometry-shader / transform-feedback pipeline), or none.
    #[arg(long, value_name = "short|grown|none")]
    pub speleothems: Option<String>,
    /// Stalactite sites to try, 0..=200 (default 40; sites without room are skipped).
    #[arg(long, value_name = "N")]
    pub speleothem_count: Option<u32>,
    /// Metres per unit of the paper's speleothem radius r (r is 5..50 units), (0, 1]
    /// (default 0.03).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub unit: Option<f32>,
    /// Stalagmite growth relative to its stalactite, 0.1..=10 (paper 1.5).
    #[arg(long, value_name = "R", allow_negative_numbers = true)]
    pub growth_ratio: Option<f32>,
    /// Growth passes with --speleothems grown, 1..=512 (default 30).
    #[arg(long, value_name = "N")]
    pub grown_passes: Option<u32>,
    /// Draw the wall as wireframe (the paper's Fig. 5a/c).
    #[arg(long)]
    pub wireframe: bool,
    /// Show the blocky wall before smoothing (the paper's Fig. 5a/b).
    #[arg(long)]
    pub no_smooth: bool,
    /// Fog density per metre, 0..=1 (default 0.04).
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub fog: Option<f32>,
    /// Camera position x,y,z in metres (the cave spans 0..cave-size on each axis; the
    /// passage runs along x with its floor at y = cave-size / 4).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub eye: Option<String>,
    /// Point the camera looks at, x,y,z in metres.
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub target: Option<String>,
}

#[derive(clap::Args, Debug)]
pub struct CaveArgs {
    #[command(flatten)]
    pub scene: CaveSceneArgs,
    /// Print the paper's Table 1 counterpart (triangles before/after the crack-free
    /// split and generation time per phase, octree depths 5..9) and exit.
    #[arg(long)]
    table: bool,
    /// The frame as PNG (default cave.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The cave and its speleothems as .glb (glTF 2.0 binary) or .obj (with normals).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// A fly-through along the passage as an animated GIF.
    #[arg(long, value_name = "FILE.gif")]
    flythrough: Option<PathBuf>,
    /// Fly-through frames, 2..=240 (default 24).
    #[arg(long, value_name = "N", default_value_t = 24)]
    flythrough_frames: u32,
}

pub fn cave_scene(cli: &Cli, a: &CaveSceneArgs) -> anyhow::Result<cave::CaveScene> {
    let mut s = match &a.preset {
        Some(name) => cave::preset(name)?,
        None => cave::CaveScene::default(),
    };
    s.cave.volume.seed = cli.seed;
    set!(s.cave.depth, a.depth);
    set!(s.cave.size_m, a.cave_size);
    set!(s.cave.lambda, a.lambda);
    set!(s.cave.iterations, a.iterations);
    let v = &mut s.cave.volume;
    set!(v.noise_scale, a.noise_scale);
    set!(v.octaves, a.octaves);
    set!(v.roughness, a.roughness);
    set!(v.threshold, a.threshold);
    set!(v.half_height, a.half_height);
    set!(v.half_width, a.half_width);
    set!(v.meander, a.meander);
    if let Some(m) = &a.speleothems {
        s.speleothems = m.parse()?;
    }
    set!(s.speleothem_count, a.speleothem_count);
    set!(s.unit_m, a.unit);
    set!(s.growth_ratio, a.growth_ratio);
    set!(s.grown_passes, a.grown_passes);
    set!(s.fog, a.fog);
    s.wireframe |= a.wireframe;
    s.smooth &= !a.no_smooth;
    s.validate()?;
    Ok(s)
}

pub fn run(cli: &Cli, a: &CaveArgs) -> anyhow::Result<()> {
    let mut scene = cave_scene(cli, &a.scene)?;
    if a.table {
        let rows = cave::table(&scene.cave, &mut |d| {
            progress(d as usize - 5, 5, "octree depths")
        })?;
        eprintln!();
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
    let camera_override = CameraOverride::parse(&a.scene.eye, &a.scene.target)?;
    if let Some(o) = &a.output {
        check_extension(o, "-o", &["png"])?;
    }
    if let Some(m) = &a.mesh {
        check_extension(m, "--mesh", &["glb", "obj"])?;
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
    let model = cave::build(&scene, &|phase, done, total| {
        progress(done as usize, total as usize, phase);
    })?;
    progress(1, 1, "done");
    eprintln!();
    let c = &model.cave;
    say!(
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
    let camera = camera_override.over(cave::default_camera(&scene, &model))?;
    scene.camera = Some(camera.clone());
    let mut cameras = vec![camera];
    if a.flythrough.is_some() {
        cameras.extend(cave::flythrough(&scene, &model, a.flythrough_frames));
    }
    let rendered = cave::render(&ctx, &scene, &model, cli.size, &cameras)?;
    fail_on_validation_errors(&ctx)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("cave.png"));
    let frame = &rendered.frames[0];
    sediment::export::png::write_png(&output, &frame.image)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.flythrough {
        let frames: Vec<_> = rendered.frames[1..]
            .iter()
            .map(|f| f.image.clone())
            .collect();
        sediment::export::gif::write_gif(path, &frames, 120)?;
        say!("wrote {} ({} frames)", path.display(), frames.len());
    }
    if let Some(path) = &a.mesh {
        let soup = cave::export(&scene, &model, rendered.grown.as_ref());
        sediment::export::mesh::write_mesh(path, &soup)?;
        say!("wrote {}", path.display());
    }
    let spans = frame
        .gpu_spans
        .iter()
        .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
        .collect::<Vec<_>>()
        .join(", ");
    say!("GPU frame: {spans}; wall {:.1} ms", frame.wall_ms);
    Ok(())
}

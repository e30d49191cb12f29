//! `sediment dunes`: Onoue & Nishita's desert of dunes and wind ripples.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::scene::dunes;

use crate::{
    CameraOverride, Cli, degrees_or_off, fail_on_validation_errors, on_off, open_context, progress,
};

#[derive(clap::Args, Debug)]
/// The scene options, shared with `sediment view`.
pub struct DunesSceneArgs {
    /// A reproduction of one of the paper's figures: fig12 (no ripples), fig13
    /// (ripples), fig14/fig15 (low sun without/with dune shadows), fig16/fig17 (dune
    /// shadows without/with ripple shadows), fig18 (with sand dust; no footprints).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// Ripple tile side in texels: a power of two in 16..=1024 (paper: 256).
    #[arg(long, value_name = "N")]
    pub ripple_size: Option<usize>,
    /// Ripple simulation steps, 0..=100000.
    #[arg(long, value_name = "N")]
    pub ripple_steps: Option<u32>,
    /// Dune grid side in vertices, 8..=512 (paper: 64).
    #[arg(long, value_name = "N")]
    pub dune_size: Option<usize>,
    /// Dune simulation steps, 0..=100000.
    #[arg(long, value_name = "N")]
    pub dune_steps: Option<u32>,
    /// Ripple saltation length L0 in texels (paper 7.3).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    pub ripple_l0: Option<f64>,
    /// Ripple saltation amount q (paper 0.6).
    #[arg(long, value_name = "Q", allow_negative_numbers = true)]
    pub ripple_q: Option<f64>,
    /// Ripple hop growth with height b (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub ripple_b: Option<f64>,
    /// Creep diffusion D for both simulations, 0..=1 (default 0.2).
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub diffusion: Option<f64>,
    /// Angle of repose for dune avalanching in degrees, or "off" (default 33).
    #[arg(long, value_name = "DEG|off")]
    pub repose: Option<String>,
    /// World metres per dune cell, > 0 (default 4).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub cell: Option<f32>,
    /// World metres covered by one ripple tile, > 0 (default 16: 64 ripple texels per
    /// 4 m dune cell, as in the paper).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub ripple_tile: Option<f32>,
    /// Ripple bump strength, 0..=4 (default 0.65; 1 uses the simulated slopes as they
    /// are).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub ripple_strength: Option<f32>,
    /// Ripple orientation relative to the dune field's wind (+x), degrees.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub wind_direction: Option<f32>,
    /// Sun elevation above the horizon, 0.5..=89.5 degrees.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub sun_elevation: Option<f32>,
    /// Sun azimuth, degrees from +x toward +z.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    pub sun_azimuth: Option<f32>,
    /// Level of detail over the ripple normal chain: on, or off (level 0 everywhere).
    #[arg(long, value_name = "on|off")]
    pub lod: Option<String>,
    /// Back-face and frustum culling of dune quads: on or off.
    #[arg(long, value_name = "on|off")]
    pub cull: Option<String>,
    /// Shadows: none, dune, or dune+ripple.
    #[arg(long, value_name = "none|dune|dune+ripple")]
    pub shadows: Option<String>,
    /// How dune shadows are found: map (the paper's ray march once per light into a
    /// shadow map, the default) or pixel (the same march in every pixel, slower; for
    /// comparison).
    #[arg(long, value_name = "map|pixel")]
    pub dune_shadows: Option<String>,
    /// Sand dust blobs drifting with the wind (paper eq. 7).
    #[arg(long)]
    pub dust: bool,
    /// Time step at which the dust is shown, 0..=100000 (default 40).
    #[arg(long, value_name = "N")]
    pub dust_step: Option<u32>,
    /// Camera position x,y,z in metres (the field spans 0..(dune-size - 1) x cell).
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub eye: Option<String>,
    /// Point the camera looks at, x,y,z in metres.
    #[arg(long, value_name = "X,Y,Z", allow_negative_numbers = true)]
    pub target: Option<String>,
    /// Dune saltation length L0 in cells (paper 7.0).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    pub dune_l0: Option<f64>,
    /// Dune saltation base amount q0 (paper 1.5).
    #[arg(long, value_name = "Q", allow_negative_numbers = true)]
    pub dune_q0: Option<f64>,
    /// Dune hop shortening with slope b (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub dune_b: Option<f64>,
    /// Dune lift increase with slope b' (paper 2.0).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub dune_b_prime: Option<f64>,
    /// Dune wind speed-up: extra hop length in cells per unit of sand height above the
    /// field's mean, >= 0 (default 2; 0 for the paper's law alone).
    #[arg(long, value_name = "CELLS", allow_negative_numbers = true)]
    pub dune_speedup: Option<f64>,
    /// Lee shadow zone behind dune crests in degrees, 0..90 exclusive, or "off" for the
    /// paper's law alone (default 15): sand there is not eroded and catches the grains
    /// flying into it, which makes the steep slip face.
    #[arg(long, value_name = "DEG|off")]
    pub shadow_zone: Option<String>,
}

#[derive(clap::Args, Debug)]
pub struct DunesArgs {
    #[command(flatten)]
    pub scene: DunesSceneArgs,
    /// The frame as PNG (default dunes.png).
    #[arg(short = 'o', long = "output", value_name = "FILE.png")]
    output: Option<PathBuf>,
    /// The ripples and dunes forming over time as an animated GIF (each frame
    /// renders the simulation part of the way through).
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=120 (default 12).
    #[arg(long, value_name = "N", default_value_t = 12)]
    gif_frames: u32,
    /// The dune field as a 16-bit greyscale PNG; the ripple tile goes beside it as
    /// FILE-ripples.png.
    #[arg(long, value_name = "FILE.png")]
    heightmap: Option<PathBuf>,
    /// The dune mesh as .glb or .obj.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
    /// Render the frame this many more times, 0..=1000, and print the median, minimum
    /// and 95th percentile of their GPU times (the first frame, which includes
    /// lavapipe's shader compilation, is not counted). `sediment bench` is the full
    /// instrument; this is the quick look.
    #[arg(long, value_name = "N", default_value_t = 0)]
    timing_frames: u32,
}

pub fn dunes_scene(cli: &Cli, a: &DunesSceneArgs) -> anyhow::Result<dunes::DunesScene> {
    let mut s = match &a.preset {
        Some(name) => dunes::preset(name)?,
        None => dunes::DunesScene::default(),
    };
    s.seed = cli.seed;
    set!(s.ripple_size, a.ripple_size);
    set!(s.ripple_steps, a.ripple_steps);
    set!(s.dune_size, a.dune_size);
    set!(s.dune_steps, a.dune_steps);
    if let sediment::model::sand::Saltation::Ripple { l0, q, b } = &mut s.ripple.saltation {
        set!(*l0, a.ripple_l0);
        set!(*q, a.ripple_q);
        set!(*b, a.ripple_b);
    }
    if let sediment::model::sand::Saltation::Dune {
        l0,
        q0,
        b,
        b_prime,
        speedup,
        shadow_degrees,
    } = &mut s.dune.saltation
    {
        set!(*l0, a.dune_l0);
        set!(*q0, a.dune_q0);
        set!(*b, a.dune_b);
        set!(*b_prime, a.dune_b_prime);
        set!(*speedup, a.dune_speedup);
        if let Some(z) = &a.shadow_zone {
            *shadow_degrees = degrees_or_off("--shadow-zone", z)?;
        }
    }
    if let Some(d) = a.diffusion {
        s.ripple.diffusion = d;
        s.dune.diffusion = d;
    }
    if let Some(r) = &a.repose {
        s.dune.repose_degrees = degrees_or_off("--repose", r)?;
    }
    set!(s.cell, a.cell);
    set!(s.ripple_tile, a.ripple_tile);
    set!(s.ripple_strength, a.ripple_strength);
    set!(s.wind_degrees, a.wind_direction);
    set!(s.sun_elevation_degrees, a.sun_elevation);
    set!(s.sun_azimuth_degrees, a.sun_azimuth);
    if let Some(v) = &a.lod {
        s.lod = on_off("--lod", v)?;
    }
    if let Some(v) = &a.cull {
        s.cull = on_off("--cull", v)?;
    }
    if let Some(v) = &a.shadows {
        s.shadows = v.parse()?;
    }
    if let Some(m) = &a.dune_shadows {
        s.dune_shadows_per_pixel = match m.trim().to_ascii_lowercase().as_str() {
            "map" => false,
            "pixel" => true,
            other => bail!(sediment::Error::invalid(
                "--dune-shadows",
                format!("\"{other}\" is not map or pixel")
            )),
        };
    }
    if a.dust && s.dust.is_none() {
        s.dust = Some(sediment::model::dust::DustParams::default());
    }
    set!(s.dust_step, a.dust_step);
    s.validate()?;
    Ok(s)
}

pub fn run(cli: &Cli, a: &DunesArgs) -> anyhow::Result<()> {
    let mut scene = dunes_scene(cli, &a.scene)?;
    let camera_override = CameraOverride::parse(&a.scene.eye, &a.scene.target)?;
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
    for (path, what) in [(&a.heightmap, "--heightmap"), (&a.output, "-o")] {
        if let Some(p) = path {
            check_extension(p, what, &["png"])?;
        }
    }
    if let Some(m) = &a.mesh {
        check_extension(m, "--mesh", &["glb", "obj"])?;
    }
    let ctx = open_context(cli)?;
    let sim_start = std::time::Instant::now();
    let terrain = dunes::simulate(&scene, &mut |d, t| {
        progress(d as usize, t as usize, "simulation steps")
    })?;
    let sim_s = sim_start.elapsed().as_secs_f64();
    eprintln!();
    let cell_steps = (scene.ripple_size * scene.ripple_size) as f64 * f64::from(scene.ripple_steps)
        + (scene.dune_size * scene.dune_size) as f64 * f64::from(scene.dune_steps);
    say!(
        "simulated {:.1} M cell-steps in {sim_s:.2} s ({:.0} M cell-steps/s on {} threads)",
        cell_steps / 1e6,
        cell_steps / 1e6 / sim_s.max(1e-9),
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    if camera_override.is_some() {
        scene.camera = Some(camera_override.over(dunes::default_camera(&scene, &terrain))?);
    }
    let out = dunes::render_timed(&ctx, &scene, &terrain, cli.size, a.timing_frames)?;
    let mut gif_frames = Vec::new();
    if a.gif.is_some() {
        // The simulation again in chunks, one frame after each (the same seed gives
        // the same final terrain).
        let snapshots = dunes::simulate_frames(&scene, a.gif_frames, &mut |d, t| {
            progress(d as usize, t as usize, "animation steps")
        })?;
        eprintln!();
        // One camera for every frame: the final frame's.
        let camera = scene
            .camera
            .clone()
            .unwrap_or_else(|| dunes::default_camera(&scene, &terrain));
        for (i, terrain) in snapshots.iter().enumerate() {
            progress(i, snapshots.len(), "animation frames");
            // Dust drifts on between frames.
            let frame_scene = dunes::DunesScene {
                dust_step: scene.dust_step + 4 * i as u32,
                camera: Some(camera.clone()),
                ..scene.clone()
            };
            gif_frames.push(
                dunes::render(&ctx, &frame_scene, terrain, cli.size)?
                    .frame
                    .image,
            );
        }
        eprintln!();
    }
    fail_on_validation_errors(&ctx)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("dunes.png"));
    sediment::export::png::write_png(&output, &out.frame.image)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.gif {
        sediment::export::gif::write_gif(path, &gif_frames, 150)?;
        say!("wrote {} ({} frames)", path.display(), gif_frames.len());
    }
    if let Some(path) = &a.heightmap {
        sediment::export::png::write_heightmap16(path, &terrain.dune_field)?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let ripples = path.with_file_name(format!("{stem}-ripples.png"));
        sediment::export::png::write_heightmap16(&ripples, &terrain.ripples)?;
        say!("wrote {} and {}", path.display(), ripples.display());
    }
    if let Some(path) = &a.mesh {
        let soup = sediment::export::mesh::TriangleSoup::from_indexed(&out.mesh, [0.72, 0.5, 0.3]);
        sediment::export::mesh::write_mesh(path, &soup)?;
        say!("wrote {}", path.display());
    }
    let spans = |s: &[sediment::gpu::Span]| {
        s.iter()
            .map(|s| format!("{} {:.2} ms", s.name, s.milliseconds))
            .collect::<Vec<_>>()
            .join(", ")
    };
    say!(
        "{}/{} dune triangles drawn; GPU frame: {}; precompute: {}; wall {:.1} ms",
        out.visible_triangles,
        out.total_triangles,
        spans(&out.frame.gpu_spans),
        spans(&out.precompute),
        out.frame.wall_ms
    );
    if !out.timed_ms.is_empty() {
        let ms = sediment::bench::report::Stats::of(&out.timed_ms);
        say!(
            "GPU frame over {} timing frames: median {:.2} ms, min {:.2} ms, p95 {:.2} ms",
            ms.samples,
            ms.median,
            ms.min,
            ms.p95
        );
    }
    Ok(())
}

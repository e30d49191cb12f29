//! `sediment layers`: Franke's layered stalagmite, in his units or in real ones.

use std::path::PathBuf;

use anyhow::bail;
use sediment::Size;
use sediment::export::check_extension;
use sediment::scene::layers;
use sediment::scene::params::SceneFileArgs;

use crate::{Cli, fail_on_validation_errors, open_context, parse_size, scene_or_print};

#[derive(clap::Args, Debug)]
pub struct LayersArgs {
    #[command(flatten)]
    pub scene: layers::Params,
    #[command(flatten)]
    pub file: SceneFileArgs,
    /// The cross-section as .svg or .png (default section.svg, unless another output
    /// is asked for: then none).
    #[arg(short = 'o', long = "output", value_name = "FILE.svg|FILE.png")]
    output: Option<PathBuf>,
    /// Size of the cross-section picture (and its GIF) in pixels, each side
    /// 1..=16384 (default: --size when given, else 600x800, a portrait page).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    section_size: Option<Size>,
    /// Emphasise every K-th layer, 0 for none (default 10).
    #[arg(long, value_name = "K", default_value_t = 10)]
    emphasis: usize,
    /// Colour the layers: none, age or supply.
    #[arg(long, value_name = "none|age|supply", default_value = "none")]
    color: String,
    /// Every layer's points as CSV (layer, time, point, x, y) (default: not written).
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// The stalagmite growing layer by layer as an animated GIF of the section
    /// (default: not written).
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=200 (default 40).
    #[arg(long, value_name = "N", default_value_t = 40)]
    gif_frames: u32,
    /// A 3D cut-away (a wedge removed, the cut faces banded by layer) rendered on the
    /// GPU at --size, as PNG (default: not written).
    #[arg(long, value_name = "FILE.png")]
    render: Option<PathBuf>,
    /// The cut-away as .glb or .obj (+ .mtl): outer surface, light and dark growth
    /// bands and floor as named parts with materials. Metres, y up, the floor's centre
    /// at the origin (real units are millimetres; one of Franke's units is read as
    /// 0.05695 m, his r = 1 as Kaufmann's 2 R0 / sqrt(pi) at R0 = 50.47 mm) (default: not written).
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
}

pub fn run(cli: &Cli, a: &LayersArgs) -> anyhow::Result<()> {
    use sediment::export::section::{self, SectionStyle};
    let Some(resolved) = scene_or_print(cli, &a.scene, &a.file)? else {
        return Ok(());
    };
    let setup = &resolved.scene;
    // The section by default only: asked for other outputs, nothing unasked is written
    // (`--mesh` used to write section.svg too).
    let output = super::picture(
        &a.output,
        &[&a.csv, &a.gif, &a.render, &a.mesh],
        "section.svg",
    );
    if let Some(output) = &output {
        check_extension(output, "-o", &["svg", "png"])?;
    }
    // --size is the size of every picture this command makes unless --section-size
    // sets the section's own.
    let section_size = a
        .section_size
        .or(cli.size_given.then_some(cli.size))
        .unwrap_or(Size::new(600, 800));
    for (path, what, ext) in [
        (&a.csv, "--csv", "csv"),
        (&a.gif, "--gif", "gif"),
        (&a.render, "--render", "png"),
    ] {
        if let Some(p) = path {
            check_extension(p, what, &[ext])?;
        }
    }
    if let Some(m) = &a.mesh {
        sediment::export::mesh::check_mesh_path(m, "--mesh")?;
    }
    // No output may overwrite an input of the run.
    let mut inputs: Vec<&std::path::Path> = Vec::new();
    if let Some(sediment::scene::layers::BaseSpec::File(f)) = &a.scene.base {
        inputs.push(f);
    }
    if let Some(sediment::scene::layers::SupplySpec::Timeline(f)) = &a.scene.supply {
        inputs.push(f);
    }
    if let Some(f) = &a.file.scene {
        inputs.push(f);
    }
    for (path, what) in [
        (output.as_ref(), "-o"),
        (a.csv.as_ref(), "--csv"),
        (a.gif.as_ref(), "--gif"),
        (a.render.as_ref(), "--render"),
        (a.mesh.as_ref(), "--mesh"),
    ] {
        if let Some(p) = path {
            sediment::export::check_not_input(p, what, &inputs)?;
        }
    }
    if !(2..=200).contains(&a.gif_frames) {
        bail!(sediment::Error::invalid(
            "--gif-frames",
            "must be in 2..=200"
        ));
    }
    let colouring: section::Colouring = a.color.parse()?;
    let start = std::time::Instant::now();
    let (stalagmite, unit) = setup.grow()?;
    let layers_grown = stalagmite.layers.len() - 1;
    let apex = stalagmite.surface().first().map_or(0.0, |p| p[1]);
    let u = unit.as_deref().unwrap_or("units");
    log::info!(
        "grew {layers_grown} layers in {:.0} ms; apex height {apex:.3} {u}; {} support points",
        start.elapsed().as_secs_f64() * 1e3,
        setup.franke.pz
    );
    if let Some(p) = &setup.physical {
        let first = &p.timeline[0];
        let c = sediment::model::layers::physical::Conditions {
            temperature_c: first.temperature_c,
            drip_interval_s: first.drip_interval_s,
            excess_ca: first.excess_ca,
            film_m: p.film_mm * 1e-3,
        };
        log::info!(
            "growth law at the start (T {} C, drip {} s, excess Ca {} mol/m^3, film {} mm): W0 = {:.4e} m/s = {:.4} mm/yr, R0 = {:.2} mm",
            first.temperature_c,
            first.drip_interval_s,
            first.excess_ca,
            p.film_mm,
            c.growth_rate(),
            c.growth_mm_per_year(),
            c.equilibrium_radius() * 1e3
        );
    }
    if let Some(o) = &stalagmite.overhang {
        log::warn!(
            "the surface would overhang at layer {} (time {}) near x = {:.3}, y = {:.3} {u}: \
             the supply widened the top past the flank below, where ceiling-formation rules take \
             over (Franke); growth stopped there",
            o.layer + 1,
            o.time,
            o.at[0],
            o.at[1]
        );
    }
    let style = SectionStyle {
        emphasis: a.emphasis,
        colouring,
        unit: unit.clone(),
        upto: None,
    };
    let (w, h) = (section_size.width, section_size.height);
    let mut render = None;
    if a.render.is_some() || a.mesh.is_some() {
        let band = (layers_grown / 24).max(1);
        let cut = layers::cut_away(&stalagmite, band);
        if a.render.is_some() {
            let ctx = open_context(cli)?;
            let camera = resolved.camera.over(layers::default_camera(&cut))?;
            let frame = layers::render(&ctx, &cut, cli.size, Some(&camera))?;
            fail_on_validation_errors(&ctx)?;
            render = Some(frame);
        }
        if let Some(path) = &a.mesh {
            let title = format!("layers {}", a.scene.preset.as_deref().unwrap_or("scene"));
            let asset = layers::export(&cut, &title, layers::metres_per_unit(unit.as_deref()));
            crate::output::wrote_line(sediment::export::mesh::write_mesh(path, &asset)?.line());
        }
    }
    if let Some(output) = &output {
        section::write(output, &stalagmite, &style, w, h)?;
        crate::output::wrote(output);
    }
    if let Some(path) = &a.csv {
        section::write_csv(path, &stalagmite, unit.as_deref())?;
        crate::output::wrote(path);
    }
    if let Some(path) = &a.gif {
        // Drawn and encoded one frame at a time (a 4096x4096 section of 40 frames held
        // 2.6 GB when collected first).
        let n = a.gif_frames as usize;
        let mut gif = sediment::export::gif::GifStream::create(path, 100)?;
        for f in 1..=n {
            let upto = 1 + (stalagmite.layers.len() - 1) * f / n;
            let frame = section::png(
                &stalagmite,
                &SectionStyle {
                    upto: Some(upto),
                    ..style.clone()
                },
                w,
                h,
            );
            gif.push(&frame)?;
        }
        let frames = gif.finish()?;
        crate::output::wrote_line(format!("wrote {} ({frames} frames)", path.display()));
    }
    if let (Some(path), Some(frame)) = (&a.render, render) {
        sediment::export::png::write_png(path, &frame.image)?;
        crate::output::wrote(path);
    }
    Ok(())
}

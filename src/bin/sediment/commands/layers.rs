//! `sediment layers`: Franke's layered stalagmite, in his units or in real ones.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::bail;
use sediment::export::check_extension;
use sediment::scene::Size;

use crate::{Cli, fail_on_validation_errors, open_context, parse_size};

#[derive(clap::Args, Debug)]
/// The scene options, shared with `sediment view`.
pub struct LayersSceneArgs {
    /// A demo case: candlestick (constant supply), drying (steps 1, 0.6, 0.3: a cone),
    /// wetting (rising supply: overhang), uneven (uneven base), timeline (12 000 years
    /// in mm).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,
    /// Layer thickness per time unit at the apex, > 0 (default 0.02; Franke units).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub dic: Option<f64>,
    /// Support points of the profile, 8..=2000 (default 160).
    #[arg(long, value_name = "N")]
    pub pz: Option<usize>,
    /// Layers, 1..=20000 (default 300).
    #[arg(long, value_name = "N")]
    pub rep: Option<usize>,
    /// Decay length r of the deposit, > 0 (default 1; the stationary radius is
    /// 0.886 r for the Gaussian, r / 2 linear, r exponential).
    #[arg(long = "r", value_name = "F", allow_negative_numbers = true)]
    pub r: Option<f64>,
    /// Decay law: gaussian (Franke's exp(-(s/r)^2)), linear (Dreybrodt's), exponential.
    #[arg(long, value_name = "gaussian|linear|exponential")]
    pub decay: Option<String>,
    /// Water supply over time, a factor on the stationary radius: constant,
    /// linear:A..B (from A to B), steps:A,B,... (equal runs), each 0.05..=20; or
    /// timeline:FILE.csv (real units: rows of years, temperature C, drip interval s,
    /// excess Ca mol/m^3).
    #[arg(long, value_name = "SPEC")]
    pub supply: Option<String>,
    /// An uneven base: a CSV of x,y support points from the axis (x = 0) outwards,
    /// heights falling steadily (a rising base would pond water).
    #[arg(long, value_name = "FILE.csv")]
    pub base: Option<PathBuf>,
    /// Radius of the flat base in stationary radii, 2..=20 (default 4.5).
    #[arg(long, value_name = "F", allow_negative_numbers = true)]
    pub extent: Option<f64>,
    /// Real units at constant cave conditions (the options below), in mm and years.
    #[arg(long)]
    pub physical: bool,
    /// Cave temperature, 0..=40 C (default 10).
    #[arg(long, value_name = "C", allow_negative_numbers = true)]
    pub temperature: Option<f64>,
    /// Drip interval, 0.1..=1000000 s (default 100).
    #[arg(long, value_name = "S", allow_negative_numbers = true)]
    pub drip_interval: Option<f64>,
    /// Excess calcium c_in - c_eq, 0..=10 mol/m^3 (default 1).
    #[arg(long, value_name = "MOL_M3", allow_negative_numbers = true)]
    pub excess_ca: Option<f64>,
    /// Water-film thickness: 0.1, 0.075 or 0.05 mm (default 0.1).
    #[arg(long, value_name = "MM", allow_negative_numbers = true)]
    pub film: Option<f64>,
    /// Years of growth with --physical, > 0 (default 10000).
    #[arg(long, value_name = "YEARS", allow_negative_numbers = true)]
    pub years: Option<f64>,
    /// Years per layer in real units, > 0 (default 40).
    #[arg(long, value_name = "YEARS", allow_negative_numbers = true)]
    pub years_per_layer: Option<f64>,
}

#[derive(clap::Args, Debug)]
pub struct LayersArgs {
    #[command(flatten)]
    pub scene: LayersSceneArgs,
    /// The cross-section as .svg or .png (default section.svg).
    #[arg(short = 'o', long = "output", value_name = "FILE.svg|FILE.png")]
    output: Option<PathBuf>,
    /// Size of the cross-section picture in pixels (default 600x800).
    #[arg(long, value_name = "WxH", default_value = "600x800", value_parser = parse_size)]
    section_size: Size,
    /// Emphasise every K-th layer, 0 for none (default 10).
    #[arg(long, value_name = "K", default_value_t = 10)]
    emphasis: usize,
    /// Colour the layers: none, age or supply.
    #[arg(long, value_name = "none|age|supply", default_value = "none")]
    color: String,
    /// Every layer's points as CSV (layer, time, point, x, y).
    #[arg(long, value_name = "FILE.csv")]
    csv: Option<PathBuf>,
    /// The stalagmite growing layer by layer as an animated GIF of the section.
    #[arg(long, value_name = "FILE.gif")]
    gif: Option<PathBuf>,
    /// GIF frames, 2..=200 (default 40).
    #[arg(long, value_name = "N", default_value_t = 40)]
    gif_frames: u32,
    /// A 3D cut-away (a wedge removed, the cut faces banded by layer) rendered on the
    /// GPU at --size, as PNG.
    #[arg(long, value_name = "FILE.png")]
    render: Option<PathBuf>,
    /// The cut-away as .glb or .obj.
    #[arg(long, value_name = "FILE.glb|FILE.obj")]
    mesh: Option<PathBuf>,
}

pub fn layers_setup(a: &LayersSceneArgs) -> anyhow::Result<sediment::scene::layers::LayersSetup> {
    use sediment::model::layers::{Base, physical};
    use sediment::scene::layers::{self, PhysicalSetup};
    let mut s = match &a.preset {
        Some(name) => layers::preset(name)?,
        None => layers::LayersSetup::default(),
    };
    set!(s.franke.dic, a.dic);
    set!(s.franke.pz, a.pz);
    set!(s.franke.rep, a.rep);
    set!(s.franke.r, a.r);
    set!(s.extent, a.extent);
    if let Some(d) = &a.decay {
        s.franke.decay = d.parse()?;
    }
    let film_m = a.film.unwrap_or(0.1) * 1e-3;
    let years_per_layer = a.years_per_layer.unwrap_or(40.0);
    if let Some(spec) = &a.supply {
        if let Some(file) = spec.strip_prefix("timeline:") {
            let text = std::fs::read_to_string(file).map_err(|source| sediment::Error::Read {
                path: file.into(),
                source,
            })?;
            s.physical = Some(PhysicalSetup {
                timeline: physical::parse_timeline(&text, film_m)?,
                film_m,
                years_per_layer,
            });
        } else {
            s.franke.supply = spec.parse()?;
        }
    }
    if a.physical {
        let c = physical::Conditions {
            temperature_c: a.temperature.unwrap_or(10.0),
            drip_interval_s: a.drip_interval.unwrap_or(100.0),
            excess_ca: a.excess_ca.unwrap_or(1.0),
            film_m,
        };
        c.validate()?;
        let years = a.years.unwrap_or(10_000.0);
        if !(years.is_finite() && years > 0.0) {
            bail!(sediment::Error::invalid("--years", "must be > 0"));
        }
        let row = |year| physical::TimelineRow {
            year,
            temperature_c: c.temperature_c,
            drip_interval_s: c.drip_interval_s,
            excess_ca: c.excess_ca,
        };
        s.physical = Some(PhysicalSetup {
            timeline: vec![row(0.0), row(years)],
            film_m,
            years_per_layer,
        });
    } else if let Some(p) = &mut s.physical {
        // A preset or a timeline: the film and step options still apply.
        p.film_m = film_m;
        p.years_per_layer = years_per_layer;
    }
    if let Some(path) = &a.base {
        let text = std::fs::read_to_string(path).map_err(|source| sediment::Error::Read {
            path: path.clone(),
            source,
        })?;
        let mut points = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let v: Option<Vec<f64>> = line.split(',').map(|c| c.trim().parse().ok()).collect();
            match v.as_deref() {
                Some([x, y]) => points.push([*x, *y]),
                _ if n == 0 => {} // a header
                _ => bail!(sediment::Error::invalid(
                    "--base",
                    format!("{} line {}: \"{line}\" is not x,y", path.display(), n + 1)
                )),
            }
        }
        s.base = Some(Base::from_points(points)?);
    }
    Ok(s)
}

pub fn run(cli: &Cli, a: &LayersArgs) -> anyhow::Result<()> {
    use sediment::export::section::{self, SectionStyle};
    use sediment::scene::layers as scene_layers;
    let setup = layers_setup(&a.scene)?;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| PathBuf::from("section.svg"));
    check_extension(&output, "-o", &["svg", "png"])?;
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
        check_extension(m, "--mesh", &["glb", "obj"])?;
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
    say!(
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
            film_m: p.film_m,
        };
        say!(
            "growth law at the start (T {} C, drip {} s, excess Ca {} mol/m^3, film {} mm): W0 = {:.4e} m/s = {:.4} mm/yr, R0 = {:.2} mm",
            first.temperature_c,
            first.drip_interval_s,
            first.excess_ca,
            p.film_m * 1e3,
            c.growth_rate(),
            c.growth_mm_per_year(),
            c.equilibrium_radius() * 1e3
        );
    }
    if let Some(o) = &stalagmite.overhang {
        say!(
            "note: the surface would overhang at layer {} (time {}) near x = {:.3}, y = {:.3} {u}: \
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
    let (w, h) = (a.section_size.width, a.section_size.height);
    let mut render = None;
    if a.render.is_some() || a.mesh.is_some() {
        let band = (layers_grown / 24).max(1);
        let cut = scene_layers::cut_away(&stalagmite, band);
        if a.render.is_some() {
            let ctx = open_context(cli)?;
            let frame = scene_layers::render(&ctx, &cut, cli.size)?;
            fail_on_validation_errors(&ctx)?;
            render = Some(frame);
        }
        if let Some(path) = &a.mesh {
            sediment::export::mesh::write_mesh(path, &scene_layers::export(&cut))?;
            say!("wrote {}", path.display());
        }
    }
    section::write(&output, &stalagmite, &style, w, h)?;
    say!("wrote {}", output.display());
    if let Some(path) = &a.csv {
        section::write_csv(path, &stalagmite)?;
        say!("wrote {}", path.display());
    }
    if let Some(path) = &a.gif {
        let n = a.gif_frames as usize;
        let frames: Vec<_> = (1..=n)
            .map(|f| {
                let upto = 1 + (stalagmite.layers.len() - 1) * f / n;
                section::png(
                    &stalagmite,
                    &SectionStyle {
                        upto: Some(upto),
                        ..style.clone()
                    },
                    w,
                    h,
                )
            })
            .collect();
        sediment::export::gif::write_gif(path, &frames, 100)?;
        say!("wrote {} ({} frames)", path.display(), frames.len());
    }
    if let (Some(path), Some(frame)) = (&a.render, render) {
        sediment::export::png::write_png(path, &frame.image)?;
        say!("wrote {}", path.display());
    }
    Ok(())
}

//! The layered stalagmite in 3D: Franke's profile revolved about the growth axis with
//! a wedge cut away, so the cut faces show the growth layers as bands — what a sliced
//! real stalagmite shows. Drawn with the lit-mesh pass; exportable as a mesh.

use std::sync::Arc;
use std::time::Instant;

use glam::{Mat4, Vec3, Vec4};

use super::camera::{Camera, Lighting};
use super::size::Size;
use crate::error::Result;
use crate::export::mesh::TriangleSoup;
use crate::gpu::{COLOR_FORMAT, Context, DEPTH_FORMAT, GpuTimer, OffscreenTarget};
use crate::model::layers::{Stalagmite, arc_lengths};
use crate::model::mesh::Mesh;
use crate::render::RenderedFrame;
use crate::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};

/// The removed wedge, radians (a quarter).
pub const WEDGE: f32 = std::f32::consts::FRAC_PI_2;
/// Segments around the full circle.
const SEGMENTS: u32 = 96;

const CALCITE: Vec3 = Vec3::new(0.78, 0.72, 0.62);
const BAND_LIGHT: Vec3 = Vec3::new(0.86, 0.8, 0.68);
const BAND_DARK: Vec3 = Vec3::new(0.55, 0.42, 0.3);
const FLOOR: Vec3 = Vec3::new(0.3, 0.28, 0.26);

/// The meshes of the cut-away: outer surface, light and dark bands of the cut faces,
/// and the floor disk.
pub struct CutAway {
    pub surface: Mesh,
    pub light: Mesh,
    pub dark: Mesh,
    pub floor: Mesh,
    /// Height and radius of the whole stalagmite (for the camera).
    pub height: f32,
    pub radius: f32,
    pub base_y: f32,
}

/// Builds the cut-away: bands of `band` layers alternate light and dark.
pub fn cut_away(s: &Stalagmite, band: usize) -> CutAway {
    let to3 = |p: [f64; 2], a: f32| {
        let (x, y) = (p[0] as f32, p[1] as f32);
        Vec3::new(x * a.cos(), y, x * a.sin())
    };
    let top = s.surface();
    let (mut base_y, mut top_y) = (f32::MAX, f32::MIN);
    for p in s.layers.iter().flatten() {
        base_y = base_y.min(p[1] as f32);
        top_y = top_y.max(p[1] as f32);
    }
    // The stalagmite's radius: as far out as the surface stands clear of the floor.
    let clear = base_y + 0.05 * (top_y - base_y);
    let radius = top
        .iter()
        .filter(|p| p[1] as f32 > clear)
        .map(|p| p[0] as f32)
        .fold(0.0f32, f32::max)
        .max(1e-3 * (top_y - base_y));
    // Outer surface over the kept angles [0, 2 pi - WEDGE].
    let kept = std::f32::consts::TAU - WEDGE;
    let steps = ((SEGMENTS as f32) * kept / std::f32::consts::TAU).ceil() as u32;
    let mut surface = Mesh::default();
    for i in 0..=steps {
        let a = kept * i as f32 / steps as f32;
        for p in top {
            surface.positions.push(to3(*p, a));
        }
    }
    let n = top.len() as u32;
    for i in 0..steps {
        for j in 0..n - 1 {
            let (a, b) = (i * n + j, (i + 1) * n + j);
            // Outward: the profile runs outwards and down, the angle turns from +x to +z.
            surface.indices.extend([a, a + 1, b + 1, a, b + 1, b]);
        }
    }
    // Outward and up: the profile faces up on the cap and out on the flank.
    fix_winding(&mut surface, |p, _| {
        Vec3::new(p.x, 0.0, p.z).normalize_or_zero() + Vec3::Y
    });
    // Cut faces: the ribbons between consecutive layers, on both planes of the cut,
    // each facing into the removed wedge.
    let mut light = Mesh::default();
    let mut dark = Mesh::default();
    let band = band.max(1);
    for (k, w) in s.layers.windows(2).enumerate() {
        let target = if (k / band) % 2 == 0 {
            &mut light
        } else {
            &mut dark
        };
        for (angle, facing) in [
            (0.0f32, Vec3::NEG_Z),
            (kept, Vec3::new(-kept.sin(), 0.0, kept.cos())),
        ] {
            let start = target.indices.len();
            ribbon(&w[0], &w[1], |p| to3(p, angle), target);
            let mut part = Mesh {
                positions: std::mem::take(&mut target.positions),
                normals: Vec::new(),
                indices: target.indices.split_off(start),
            };
            fix_winding(&mut part, |_, _| facing);
            target.positions = part.positions;
            target.indices.extend(part.indices);
        }
    }
    // The floor: a disk at the base, four times the stalagmite's radius.
    let mut floor = Mesh::default();
    floor.positions.push(Vec3::new(0.0, base_y, 0.0));
    for i in 0..SEGMENTS {
        let a = std::f32::consts::TAU * i as f32 / SEGMENTS as f32;
        floor.positions.push(Vec3::new(
            4.0 * radius * a.cos(),
            base_y - 1e-3 * radius,
            4.0 * radius * a.sin(),
        ));
    }
    for i in 0..SEGMENTS {
        floor.indices.extend([0, 1 + (i + 1) % SEGMENTS, 1 + i]);
    }
    fix_winding(&mut floor, |_, _| Vec3::Y);
    for m in [&mut surface, &mut light, &mut dark, &mut floor] {
        m.recompute_normals();
    }
    CutAway {
        surface,
        light,
        dark,
        floor,
        height: top_y - base_y,
        radius,
        base_y,
    }
}

/// Triangulates the strip between two profiles (both from the axis outwards), walking
/// both by arc length so neither side gets long slivers.
fn ribbon(a: &[[f64; 2]], b: &[[f64; 2]], place: impl Fn([f64; 2]) -> Vec3, out: &mut Mesh) {
    let (sa, sb) = (arc_lengths(a), arc_lengths(b));
    let (la, lb) = (
        sa.last().copied().unwrap_or(0.0).max(1e-12),
        sb.last().copied().unwrap_or(0.0).max(1e-12),
    );
    let base = out.positions.len() as u32;
    out.positions.extend(a.iter().map(|&p| place(p)));
    out.positions.extend(b.iter().map(|&p| place(p)));
    let nb = a.len() as u32;
    let (mut i, mut j) = (0usize, 0usize);
    while i + 1 < a.len() || j + 1 < b.len() {
        let advance_a = j + 1 >= b.len() || (i + 1 < a.len() && sa[i + 1] / la <= sb[j + 1] / lb);
        if advance_a {
            out.indices
                .extend([base + i as u32, base + i as u32 + 1, base + nb + j as u32]);
            i += 1;
        } else {
            out.indices.extend([
                base + i as u32,
                base + nb + j as u32 + 1,
                base + nb + j as u32,
            ]);
            j += 1;
        }
    }
}

/// Flips triangles whose normal points away from `facing(centroid, normal)`, and drops
/// degenerate ones (where two layers touch).
fn fix_winding(m: &mut Mesh, facing: impl Fn(Vec3, Vec3) -> Vec3) {
    let mut kept = Vec::with_capacity(m.indices.len());
    for t in m.indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        if n.length_squared() <= 1e-20 {
            continue;
        }
        let c = (p[0] + p[1] + p[2]) / 3.0;
        if n.dot(facing(c, n)) >= 0.0 {
            kept.extend_from_slice(t);
        } else {
            kept.extend([t[0], t[2], t[1]]);
        }
    }
    m.indices = kept;
}

/// The camera looking into the cut from the open wedge, slightly from above.
pub fn default_camera(c: &CutAway) -> Camera {
    let size = c.height.max(2.5 * c.radius);
    let centre = Vec3::new(0.0, c.base_y + 0.5 * c.height, 0.0);
    // The wedge opens toward +x, -z.
    let dir = Vec3::new(1.0, 0.45, -1.2).normalize();
    Camera {
        eye: centre + dir * size * 2.2,
        target: centre,
        up: Vec3::Y,
        fov_y_degrees: 35.0,
        near: size * 0.01,
        far: size * 10.0,
    }
}

/// The cut-away's pass and meshes, shared by `render` and the interactive viewer.
pub struct CutAwayRenderer {
    pass: LitMeshPass,
    parts: Vec<(GpuMesh, Vec3, f32)>,
}

impl CutAwayRenderer {
    pub fn new(ctx: &Arc<Context>, c: &CutAway) -> Result<Self> {
        let parts = [
            (&c.surface, CALCITE, 0.15),
            (&c.light, BAND_LIGHT, 0.05),
            (&c.dark, BAND_DARK, 0.05),
            (&c.floor, FLOOR, 0.02),
        ]
        .into_iter()
        .filter(|(m, _, _)| !m.indices.is_empty())
        .map(|(m, color, spec)| Ok((GpuMesh::upload(ctx, "stalagmite part", m)?, color, spec)))
        .collect::<Result<_>>()?;
        Ok(Self {
            pass: LitMeshPass::new(ctx, COLOR_FORMAT, DEPTH_FORMAT)?,
            parts,
        })
    }

    /// The camera of the next frame.
    pub fn set_frame(&mut self, camera: &Camera, aspect: f32) -> Result<()> {
        let lighting = Lighting {
            sun_direction: Vec3::new(0.6, 0.8, -0.5),
            ..Lighting::default()
        };
        self.pass
            .set_frame(&lighting.frame_uniforms(camera, aspect))
    }

    /// Records the frame into `target` (span "cut-away").
    pub fn record(
        &self,
        cmd: &crate::gpu::Commands<'_>,
        target: &OffscreenTarget,
        timer: &mut GpuTimer,
    ) -> Result<()> {
        let span = timer.begin(cmd, "cut-away")?;
        target.begin(cmd, [0.02, 0.02, 0.025, 1.0]);
        for (mesh, color, spec) in &self.parts {
            self.pass.draw(
                cmd,
                mesh,
                &ObjectPush {
                    model: Mat4::IDENTITY,
                    albedo: color.extend(1.0),
                    material: Vec4::new(20.0, *spec, 0.0, 0.0),
                },
            )?;
        }
        target.end(cmd);
        timer.end(cmd, span);
        Ok(())
    }
}

/// Renders the cut-away.
pub fn render(ctx: &Arc<Context>, c: &CutAway, size: Size) -> Result<RenderedFrame> {
    let start = Instant::now();
    let target = OffscreenTarget::new(ctx, size.width, size.height)?;
    let mut renderer = CutAwayRenderer::new(ctx, c)?;
    renderer.set_frame(&default_camera(c), size.aspect())?;
    let mut timer = GpuTimer::new(ctx, "layers timer", 1)?;
    ctx.submit_and_wait("stalagmite cut-away", |cmd| {
        timer.reset(cmd);
        renderer.record(cmd, &target, &mut timer)?;
        target.copy_out(cmd);
        Ok(())
    })?;
    Ok(RenderedFrame {
        image: target.read_image()?,
        gpu_spans: timer.read()?,
        wall_ms: start.elapsed().as_secs_f64() * 1e3,
    })
}

/// The cut-away as one coloured mesh for export.
pub fn export(c: &CutAway) -> TriangleSoup {
    let mut soup = TriangleSoup::from_indexed(&c.surface, CALCITE.to_array());
    soup.append(TriangleSoup::from_indexed(&c.light, BAND_LIGHT.to_array()));
    soup.append(TriangleSoup::from_indexed(&c.dark, BAND_DARK.to_array()));
    soup.append(TriangleSoup::from_indexed(&c.floor, FLOOR.to_array()));
    soup
}

/// Real units for Franke's model (the Dreybrodt/Kaufmann growth law).
#[derive(Clone, Debug, PartialEq)]
pub struct PhysicalSetup {
    pub timeline: Vec<crate::model::layers::physical::TimelineRow>,
    /// Water-film thickness, m.
    pub film_m: f64,
    pub years_per_layer: f64,
}

/// Everything that decides a layered stalagmite.
#[derive(Clone, Debug, PartialEq)]
pub struct LayersSetup {
    pub franke: crate::model::layers::FrankeParams,
    /// A user base, or `None` for a flat floor out to `extent`.
    pub base: Option<crate::model::layers::Base>,
    /// Radius of the flat floor, in multiples of the stationary radius (2..=20).
    pub extent: f64,
    /// Real units instead of Franke's (dic, r, supply then come from the timeline).
    pub physical: Option<PhysicalSetup>,
}

impl Default for LayersSetup {
    fn default() -> Self {
        Self {
            franke: crate::model::layers::FrankeParams::default(),
            base: None,
            extent: 4.5,
            physical: None,
        }
    }
}

/// The demo cases.
pub const PRESETS: &[(&str, &str)] = &[
    ("candlestick", "constant supply: a candlestick stalagmite"),
    (
        "drying",
        "supply falling in steps 1, 0.6, 0.3: a conical top",
    ),
    (
        "wetting",
        "supply rising from 0.5 to 1.6: the top widens until it overhangs",
    ),
    (
        "uneven",
        "constant supply on an uneven base: the same stationary top",
    ),
    (
        "timeline",
        "a 12 000-year climate timeline in millimetres (growth law of Kaufmann 2003)",
    ),
];

/// A built-in climate: a wet, warm optimum drying out in steps (a stalagmite that
/// narrows upwards; wetting phases would overhang).
pub fn example_timeline() -> Vec<crate::model::layers::physical::TimelineRow> {
    use crate::model::layers::physical::TimelineRow;
    let row = |year, temperature_c, drip_interval_s, excess_ca| TimelineRow {
        year,
        temperature_c,
        drip_interval_s,
        excess_ca,
    };
    vec![
        row(0.0, 9.0, 50.0, 1.0),
        row(3000.0, 11.0, 60.0, 1.2),
        row(6000.0, 10.0, 120.0, 1.0),
        row(9000.0, 8.0, 250.0, 0.9),
        row(12000.0, 8.0, 250.0, 0.9),
    ]
}

pub fn preset(name: &str) -> Result<LayersSetup> {
    use crate::model::layers::{Base, Supply};
    let d = LayersSetup::default();
    Ok(match name {
        "candlestick" => d,
        "drying" => LayersSetup {
            franke: crate::model::layers::FrankeParams {
                supply: Supply::Steps(vec![1.0, 0.6, 0.3]),
                rep: 450,
                ..d.franke
            },
            ..d
        },
        "wetting" => LayersSetup {
            franke: crate::model::layers::FrankeParams {
                supply: Supply::Steps(vec![0.6, 0.6, 0.6, 1.4]),
                rep: 400,
                ..d.franke
            },
            ..d
        },
        "uneven" => LayersSetup {
            base: Some(Base::from_points(
                (0..=40)
                    .map(|i| {
                        let x = 4.0 * f64::from(i) / 40.0;
                        [
                            x,
                            0.6 * (1.0 - x / 4.0).powi(2) + 0.2 * (-(x * x) / 3.0).exp(),
                        ]
                    })
                    .collect(),
            )?),
            ..d
        },
        "timeline" => LayersSetup {
            physical: Some(PhysicalSetup {
                timeline: example_timeline(),
                film_m: 1e-4,
                years_per_layer: 40.0,
            }),
            ..d
        },
        other => return Err(crate::error::Error::unknown_preset(other, PRESETS)),
    })
}

impl LayersSetup {
    /// The deposits, and the unit of the coordinates ("mm") in real units.
    pub fn schedule(&self) -> Result<(Vec<crate::model::layers::LayerStep>, Option<String>)> {
        self.franke.validate()?;
        crate::error::ensure_in_range((2.0..=20.0).contains(&self.extent), "--extent", "2..=20")?;
        match &self.physical {
            Some(p) => Ok((
                crate::model::layers::physical::schedule(&p.timeline, p.film_m, p.years_per_layer)?,
                Some("mm".to_owned()),
            )),
            None => Ok((self.franke.schedule(), None)),
        }
    }

    /// Grows the stalagmite.
    pub fn grow(&self) -> Result<(Stalagmite, Option<String>)> {
        let (steps, unit) = self.schedule()?;
        let decay = self.franke.decay;
        let widest = steps.iter().map(|s| s.r).fold(0.0f64, f64::max);
        let pz = self.franke.pz;
        let base = match &self.base {
            Some(b) => b.resampled(pz),
            None => {
                crate::model::layers::Base::flat(self.extent * decay.stationary_radius(widest), pz)
                    .points
            }
        };
        Ok((crate::model::layers::grow(&base, &steps, decay)?, unit))
    }
}

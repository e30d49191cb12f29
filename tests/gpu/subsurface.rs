//! Light through the calcite (`--subsurface`, `shaders-glsl/speleothem/surface.glsl`):
//! a column of fig9f seen side-on to the lamp, its dark half glowing with the light
//! that crossed it, against the transmission law computed here from the column's
//! own geometry.

use glam::{Vec2, Vec3, Vec4};

use crate::common;
use sediment::Size;
use sediment::camera::{Camera, Jitter};
use sediment::frame::{FrameRunner, Scene, Time};
use sediment::model::speleothem::grow_reference;
use sediment::render::growth::GrowthPath;
use sediment::render::tone_map::ToneMap;
use sediment::scene::grow::{self, GrowthFrame, Look, SpeleothemScene};

/// Calcite's mean free path in `surface.glsl`, in scene units.
const FREE_PATH: f32 = 0.015;
/// fig9f is calcareous: the colour is Table 1's white throughout.
const ALBEDO: f32 = 0.8;
const EXPOSURE: f32 = 8.0;
const SIZE: u32 = 240;

/// A vertical cylinder: the axis's (x, z) and the radius.
#[derive(Clone, Copy, Debug)]
struct Column {
    axis: Vec2,
    radius: f32,
}

impl Column {
    /// The distance along the ray `o + s d` (s > 0) to where it enters the cylinder.
    fn hit(&self, o: Vec3, d: Vec3) -> Option<f32> {
        let p = Vec2::new(o.x, o.z) - self.axis;
        let q = Vec2::new(d.x, d.z);
        let a = q.dot(q);
        let b = 2.0 * p.dot(q);
        let c = p.dot(p) - self.radius * self.radius;
        let disc = b * b - 4.0 * a * c;
        if a < 1e-9 || disc < 0.0 {
            return None;
        }
        let s = (-b - disc.sqrt()) / (2.0 * a);
        (s > 0.0).then_some(s)
    }

    /// The length of the path inside the cylinder from its surface point `p` along
    /// `l` (the other root of the ray's quadratic), 0 where `l` leaves at once.
    fn chord(&self, p: Vec3, l: Vec3) -> f32 {
        let r = Vec2::new(p.x, p.z) - self.axis;
        let q = Vec2::new(l.x, l.z);
        (-2.0 * r.dot(q) / q.dot(q).max(1e-12)).max(0.0)
    }
}

/// The column of `speleothem` in the reference mesh, measured over the rings within
/// 5 cm of height `y`: (its axis and mean radius, the radii's spread).
fn column_at(
    mesh: &[sediment::model::speleothem::RingVertex],
    speleothem: usize,
    y: f32,
) -> Option<(Column, f32)> {
    let ring: Vec<Vec3> = mesh
        .iter()
        .filter(|v| v.speleothem() == speleothem && (v.position().y - y).abs() < 0.05)
        .map(|v| v.position())
        .collect();
    if ring.len() < 16 {
        return None;
    }
    let axis = ring.iter().map(|p| Vec2::new(p.x, p.z)).sum::<Vec2>() / ring.len() as f32;
    let radii: Vec<f32> = ring
        .iter()
        .map(|p| (Vec2::new(p.x, p.z) - axis).length())
        .collect();
    let mean = radii.iter().sum::<f32>() / radii.len() as f32;
    let spread = radii.iter().map(|r| (r - mean).abs()).fold(0.0, f32::max);
    Some((Column { axis, radius: mean }, spread))
}

fn render(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    scene: &SpeleothemScene,
    camera: &Camera,
    subsurface: bool,
) -> image::RgbaImage {
    let model = SpeleothemScene {
        look: Look {
            subsurface,
            ..scene.look.clone()
        },
        ..scene.clone()
    };
    let mut frame = GrowthFrame::with_look(ctx, model, GrowthPath::XfbRestream).expect("frame");
    let mut runner = FrameRunner::new(ctx, Size::new(SIZE, SIZE)).expect("runner");
    let end = Time::At(u32::MAX);
    frame.advance_to(ctx, end, &|_, _, _| {}).expect("grow");
    runner.render(&mut frame, camera, end).expect("render").0
}

// The lamp beside the camera's line of sight: the terminator runs down the middle of
// the column as the camera sees it, and on its dark half each pixel shows the light
// that entered on the far side, at cosine -n.l, and crossed the chord toward the lamp:
// albedo x radiance x (-n.l) x exp(-chord / free path). Linear tone mapping, no film,
// no shadows: with light through the calcite or without, the frames differ by that
// alone. Measured: the profile across the dark half within 8 % of its peak on
// average, its sum within 10 %, the lit half unchanged.
#[test]
fn light_through_a_column_follows_the_transmission_law() {
    common::with_gpu(|ctx| {
        let params = grow::preset("fig9f").expect("preset");
        let mut scene = params.speleothems().expect("scene");
        scene.look = Look {
            tonemap: ToneMap::Linear,
            exposure: EXPOSURE,
            environment: 0.0,
            shadows: false,
            ..scene.look.clone()
        };
        let plan = scene.growth.plan().expect("plan");
        let mesh = grow_reference(&plan, plan.passes);
        let lighting = grow::lamp_lighting(&scene.growth, &scene.look);
        let lamp = lighting.sun_direction;
        let height = 0.3 * scene.growth.ceiling_y + 0.7 * scene.growth.floor_y;
        let speleothems = mesh.iter().map(|v| v.speleothem() + 1).max().unwrap_or(0);
        let columns: Vec<Column> = (0..speleothems)
            .filter_map(|s| column_at(&mesh, s, height))
            .map(|(c, _)| c)
            .collect();
        // A column whose camera, 0.35 units off to the side of the lamp's direction,
        // sees it past every other column.
        let (column, spread, eye) = (0..speleothems)
            .filter_map(|s| column_at(&mesh, s, height))
            .find_map(|(c, spread)| {
                let centre = Vec3::new(c.axis.x, height, c.axis.y);
                let d = Vec2::new(lamp.x - centre.x, lamp.z - centre.z).normalize();
                let eye = centre + 0.35 * Vec3::new(-d.y, 0.0, d.x);
                let dir = (centre - eye).normalize();
                let clear = columns.iter().all(|o| {
                    (o.axis - c.axis).length() < 1e-4
                        || o.hit(eye, dir).is_none_or(|s| s > (centre - eye).length())
                });
                clear.then_some((c, spread, eye))
            })
            .expect("a column in clear view");
        assert!(
            spread < 0.03 * column.radius,
            "the column is no cylinder: radii spread {spread} of {}",
            column.radius
        );
        let camera = Camera {
            eye,
            target: Vec3::new(column.axis.x, height, column.axis.y),
            up: Vec3::Y,
            fov_y_degrees: 30.0,
            near: 0.01,
            far: 20.0,
            jitter: Jitter::NONE,
        };
        let on = render(ctx, &scene, &camera, true);
        let off = render(ctx, &scene, &camera, false);
        common::assert_no_validation_errors(ctx);

        let inverse = camera.view_proj(1.0).inverse();
        let unproject = |x: f32, y: f32, z: f32| {
            let p = inverse * Vec4::new(x, y, z, 1.0);
            p.truncate() / p.w
        };
        let (mut predicted_sum, mut measured_sum, mut error_sum, mut peak) =
            (0.0, 0.0, 0.0, 0.0f32);
        let mut band = Vec::new();
        let mut lit_changed = 0;
        for j in SIZE / 3..2 * SIZE / 3 {
            for i in 0..SIZE {
                let x = (i as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
                let y = (j as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
                let near = unproject(x, y, 0.0);
                let dir = (unproject(x, y, 1.0) - near).normalize();
                let Some(s) = column.hit(near, dir) else {
                    continue;
                };
                let p = near + s * dir;
                let n = Vec3::new(p.x - column.axis.x, 0.0, p.z - column.axis.y).normalize();
                // Away from the silhouette, where a pixel mixes column and background.
                if n.dot(-dir) < 0.35 {
                    continue;
                }
                let to_lamp = lamp - p;
                let l = to_lamp.normalize();
                let measured = (0..3)
                    .map(|k| {
                        common::picture::linear(on.get_pixel(i, j)[k]) as f32
                            - common::picture::linear(off.get_pixel(i, j)[k]) as f32
                    })
                    .sum::<f32>()
                    / 3.0
                    / EXPOSURE;
                let entering = -n.dot(l);
                if entering < 0.02 {
                    if entering < -0.02 && measured.abs() > 1.0 / 255.0 {
                        lit_changed += 1;
                    }
                    continue;
                }
                let radiance = lighting.sun_color.x / to_lamp.length_squared();
                let predicted =
                    ALBEDO * radiance * entering * (-column.chord(p, l) / FREE_PATH).exp();
                band.push((predicted, measured));
                peak = peak.max(predicted);
            }
        }
        for &(predicted, measured) in &band {
            predicted_sum += predicted;
            measured_sum += measured;
            error_sum += (predicted - measured).abs();
        }
        let mean_error = error_sum / band.len().max(1) as f32 / peak.max(1e-9);
        let ratio = measured_sum / predicted_sum.max(1e-9);
        eprintln!(
            "column radius {:.4} at {:?}: {} dark-side pixels, peak {peak:.4}, mean |error| \
             {:.1} % of the peak, measured / predicted sum {ratio:.3}, lit pixels changed \
             {lit_changed}",
            column.radius,
            column.axis,
            band.len(),
            100.0 * mean_error
        );
        assert!(band.len() > 500, "only {} dark-side pixels", band.len());
        assert!(
            mean_error <= 0.08,
            "mean |error| {:.3} of the peak",
            mean_error
        );
        assert!(
            (0.9..=1.1).contains(&ratio),
            "measured / predicted {ratio:.3}"
        );
        assert_eq!(lit_changed, 0, "lit pixels changed by the transmission");
    });
}

// The viewer's `y` turns the light through the calcite off and on: after it the frame
// draws what a frame built with `--subsurface off` draws (fig9e's needles seen from
// behind, against the lamp, where the two differ: checked here too).
#[test]
fn the_subsurface_key_draws_what_the_option_does() {
    use sediment::input::Key;
    common::with_gpu(|ctx| {
        let scene = grow::preset("fig9e")
            .expect("preset")
            .speleothems()
            .expect("scene");
        let camera = Camera {
            eye: Vec3::new(1.6, 1.0, -2.8),
            target: Vec3::new(-0.6, 1.2, 1.2),
            ..grow::default_camera(&scene.growth)
        };
        let [on, off, keyed] = common::growth::switch_pictures(
            ctx,
            &scene,
            (&camera, Size::new(240, 160)),
            Key::Char('y'),
            |look, on| look.subsurface = on,
        );
        let (_, same) = common::difference(&keyed, &off);
        let (_, apart) = common::difference(&on, &off);
        eprintln!(
            "after y against --subsurface off: max {}; on against off: mean {:.3}, max {}",
            same.max, apart.mean, apart.max
        );
        assert_eq!(same.max, 0, "the key draws another frame than the option");
        assert!(
            apart.max >= 64,
            "the light through the needles shows by {}",
            apart.max
        );
    });
}

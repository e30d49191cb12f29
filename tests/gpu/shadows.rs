//! The lamp's soft shadows (`render::shadow_map`, percentage-closer soft shadows)
//! against the analytic share of a spherical lamp a sphere leaves visible, and in the
//! growth chamber: the floor by the columns darker with shadows than without.

use glam::{Mat4, Vec3};

use crate::common;
use sediment::camera::{Camera, Jitter};
use sediment::gpu::OffscreenTarget;
use sediment::model::mesh::Mesh;
use sediment::render::lighting::Lighting;
use sediment::render::lit_mesh::{GpuMesh, LitMeshPass, ObjectPush};
use sediment::render::shadow_map::{DEFAULT_SIZE, ShadowMap, Spot};
use sediment::render::tone_map::ToneMap;

const LAMP: Vec3 = Vec3::new(0.9, 2.0, 0.2);
const LAMP_RADIUS: f32 = 0.3;
const BALL: Vec3 = Vec3::new(0.0, 0.5, 0.0);
const BALL_RADIUS: f32 = 0.25;
const SIZE: u32 = 240;

/// Area of the intersection of two discs of radii `a` and `b` whose centres are `d`
/// apart.
fn overlap(a: f64, b: f64, d: f64) -> f64 {
    use std::f64::consts::PI;
    if d >= a + b {
        return 0.0;
    }
    if d <= (a - b).abs() {
        return PI * a.min(b).powi(2);
    }
    let ca = ((d * d + a * a - b * b) / (2.0 * d * a)).clamp(-1.0, 1.0);
    let cb = ((d * d + b * b - a * a) / (2.0 * d * b)).clamp(-1.0, 1.0);
    let k = ((-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b)).max(0.0);
    a * a * ca.acos() + b * b * cb.acos() - 0.5 * k.sqrt()
}

/// The share of the lamp's disc seen from floor point `p` past the ball: the two
/// as discs of angular radii asin(R / distance), their overlap taken away.
fn visible_share(p: Vec3) -> f64 {
    let to_lamp = (LAMP - p).as_dvec3();
    let to_ball = (BALL - p).as_dvec3();
    let a = (f64::from(LAMP_RADIUS) / to_lamp.length()).asin();
    let b = (f64::from(BALL_RADIUS) / to_ball.length()).asin();
    let d = to_lamp.angle_between(to_ball);
    1.0 - overlap(a, b, d) / (std::f64::consts::PI * a * a)
}

/// How the map is drawn.
#[derive(Clone, Copy, PartialEq)]
enum MapDrawing {
    /// Floor and ball into the cleared map.
    Whole,
    /// The floor kept as a static caster, the ball drawn over a copy of it: first
    /// somewhere else, then where it is, so the copy must have dropped the first.
    OverStatic,
}

/// The floor seen from above, lit by the lamp alone (no ambient, no highlight,
/// linear tone mapping), with the ball's shadow or without.
fn render(ctx: &std::sync::Arc<sediment::gpu::Context>, on: bool) -> (image::RgbaImage, Mat4) {
    render_with(ctx, on, MapDrawing::Whole)
}

fn render_with(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    on: bool,
    drawing: MapDrawing,
) -> (image::RgbaImage, Mat4) {
    let mut shadow = match drawing {
        MapDrawing::Whole => ShadowMap::new(ctx, DEFAULT_SIZE),
        MapDrawing::OverStatic => ShadowMap::keeping_static(ctx, DEFAULT_SIZE),
    }
    .expect("shadow map");
    shadow
        .set_spot(
            &Spot {
                position: LAMP,
                radius: LAMP_RADIUS,
                centre: Vec3::new(-0.3, 0.3, 0.0),
                reach: 1.8,
            },
            on,
        )
        .expect("aim");
    let target = OffscreenTarget::new(ctx, SIZE, SIZE).expect("target");
    let mut pass =
        LitMeshPass::shadowed(ctx, target.format(), ToneMap::Linear, &shadow).expect("pass");
    let floor = GpuMesh::upload(
        ctx,
        "floor",
        &Mesh::height_grid(3.0, 0.0, 24, true, |_, _| 0.0),
    )
    .expect("floor");
    let ball = GpuMesh::upload(ctx, "ball", &Mesh::sphere(BALL, BALL_RADIUS, 48)).expect("ball");
    let camera = Camera {
        eye: Vec3::new(-0.3, 3.0, 0.0),
        target: Vec3::new(-0.3, 0.0, 0.0),
        up: Vec3::NEG_Z,
        fov_y_degrees: 40.0,
        near: 0.1,
        far: 10.0,
        jitter: Jitter::NONE,
    };
    let lighting = Lighting {
        sun_direction: LAMP,
        point: true,
        sun_color: Vec3::splat(2.0),
        sky_color: Vec3::ZERO,
        ground_color: Vec3::ZERO,
        exposure: 1.0,
        tonemap: ToneMap::Linear,
    };
    let frame = lighting.frame_uniforms(&camera, 1.0);
    pass.set_frame(&frame).expect("frame");
    let matte = ObjectPush {
        model: Mat4::IDENTITY,
        albedo: glam::Vec4::ONE,
        material: glam::Vec4::new(1.0, 0.0, 0.0, 0.0),
    };
    if drawing == MapDrawing::OverStatic {
        let elsewhere = Mat4::from_translation(Vec3::new(-0.6, 0.0, 0.4));
        for model in [elsewhere, Mat4::IDENTITY] {
            ctx.submit_and_wait("shadow map over static casters", |cmd| {
                shadow.record_over_static(
                    cmd,
                    |shadow, cmd| shadow.draw_mesh(cmd, &floor, Mat4::IDENTITY),
                    |shadow, cmd| shadow.draw_mesh(cmd, &ball, model),
                )
            })
            .expect("map");
        }
    }
    ctx.submit_and_wait("shadow test", |cmd| {
        if shadow.on() && drawing == MapDrawing::Whole {
            shadow.record(cmd, |cmd| {
                shadow.draw_mesh(cmd, &floor, Mat4::IDENTITY)?;
                shadow.draw_mesh(cmd, &ball, Mat4::IDENTITY)
            })?;
        }
        target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
        pass.draw(cmd, &floor, &matte)?;
        pass.draw(cmd, &ball, &matte)?;
        target.end(cmd);
        target.copy_out(cmd)
    })
    .expect("submit");
    (target.read_image().expect("read"), frame.view_proj)
}

/// Where the pixel's ray meets the floor, unless the ball is in the way.
fn floor_point(view_proj: Mat4, x: u32, y: u32) -> Option<Vec3> {
    let inverse = view_proj.inverse();
    let ndc_x = (x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
    let ndc_y = (y as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0;
    let near = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
    let far = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
    let dir = (far - near).normalize();
    let oc = near - BALL;
    let b = oc.dot(dir);
    // A margin of a pixel's width round the ball's outline, where samples mix.
    let r = BALL_RADIUS * 1.03;
    if b * b - (oc.length_squared() - r * r) >= 0.0 {
        return None;
    }
    let t = -near.y / dir.y;
    (t > 0.0).then(|| near + dir * t)
}

/// The shadowed floor over the unshadowed one gives the share of the lamp the shader
/// found visible; it matches the analytic share: lit where the whole lamp shows,
/// dark in the umbra, and within 0.06 on average across the penumbra.
#[test]
fn soft_shadows_match_the_share_of_a_spherical_lamp_left_visible() {
    let gpu = common::gpu();
    let (lit, view_proj) = render(&gpu, false);
    let (shadowed, _) = render(&gpu, true);
    let (mut full, mut umbra, mut penumbra) = (Vec::new(), Vec::new(), Vec::new());
    for y in 0..SIZE {
        for x in 0..SIZE {
            let Some(p) = floor_point(view_proj, x, y) else {
                continue;
            };
            let off = common::picture::linear(lit.get_pixel(x, y)[0]);
            if off < 0.05 {
                continue;
            }
            let seen = common::picture::linear(shadowed.get_pixel(x, y)[0]) / off;
            let share = visible_share(p);
            if share >= 0.999 {
                full.push(seen);
            } else if share <= 0.001 {
                umbra.push(seen);
            } else {
                penumbra.push((seen - share).abs());
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let (full_mean, umbra_mean, penumbra_error) = (mean(&full), mean(&umbra), mean(&penumbra));
    let dark_in_full = full.iter().filter(|&&s| s < 0.95).count() as f64 / full.len() as f64;
    eprintln!(
        "fully lit {} px (mean {full_mean:.4}, {:.3} % below 0.95), umbra {} px (mean \
         {umbra_mean:.4}), penumbra {} px (mean error {penumbra_error:.4})",
        full.len(),
        dark_in_full * 100.0,
        umbra.len(),
        penumbra.len()
    );
    assert!(full.len() > 10_000 && umbra.len() > 500 && penumbra.len() > 2_000);
    // Measured on lavapipe: 1.0000 with 0.03 % below 0.95; 0.005; 0.039 (the
    // average blocker depth of Fernando's PCSS gives 0.052, the receiver itself
    // compared with every tap, 0.14: both fail).
    assert!(
        full_mean > 0.995 && dark_in_full < 0.005,
        "acne or light leaks"
    );
    assert!(umbra_mean < 0.02, "the umbra leaks light");
    assert!(penumbra_error < 0.06, "penumbra off the analytic share");
}

/// A map whose static casters (the floor) are kept and copied, the moving ones (the
/// ball, moved since the last map) drawn over the copy, shades exactly as one drawn
/// whole.
#[test]
fn a_map_drawn_over_its_kept_static_casters_equals_one_drawn_whole() {
    let gpu = common::gpu();
    let (whole, _) = render_with(&gpu, true, MapDrawing::Whole);
    let (over, _) = render_with(&gpu, true, MapDrawing::OverStatic);
    let (lit, _) = render(&gpu, false);
    assert!(whole != lit, "the ball casts no shadow");
    let differing = whole
        .pixels()
        .zip(over.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(differing, 0, "pixels differ between the two maps' shading");
}

/// fig9f's columns with the lamp's shadows against without (the issue's own
/// measure: the floor by the columns was bit-identical to a floor without them):
/// shadows only take light away, and a share of the floor goes darker by more than
/// 8/255 with them (5.6 % on lavapipe; 0 without).
#[test]
fn the_columns_of_fig9f_shadow_the_floor_and_nothing_brightens() {
    use sediment::frame::{FrameRunner, Scene, Time};
    use sediment::render::growth::GrowthPath;
    use sediment::scene::grow::{self, GrowthFrame};
    let gpu = common::gpu();
    let size = sediment::Size::new(240, 160);
    let picture = |shadows: bool| {
        let mut params = grow::preset("fig9f").expect("preset");
        params.shadows = shadows;
        let model = params.speleothems().expect("scene");
        let camera = grow::default_camera(&model.growth);
        let mut frame =
            GrowthFrame::with_look(&gpu, model, GrowthPath::XfbRestream).expect("frame");
        let mut runner = FrameRunner::new(&gpu, size).expect("runner");
        let end = Time::At(u32::MAX);
        frame.advance_to(&gpu, end, &|_, _, _| {}).expect("grow");
        runner.render(&mut frame, &camera, end).expect("render").0
    };
    let (on, off) = (picture(true), picture(false));
    let mut brighter = 0;
    let (mut floor, mut darker) = (0, 0);
    for (x, y, p) in on.enumerate_pixels() {
        let q = off.get_pixel(x, y);
        let drop = (0..3)
            .map(|c| i32::from(q[c]) - i32::from(p[c]))
            .max()
            .unwrap_or(0);
        let rise = (0..3)
            .map(|c| i32::from(p[c]) - i32::from(q[c]))
            .max()
            .unwrap_or(0);
        brighter += usize::from(rise > 2);
        // The floor: the frame's lower 45 %.
        if y >= size.height * 55 / 100 {
            floor += 1;
            darker += usize::from(drop > 8);
        }
    }
    let share = darker as f64 / floor as f64;
    eprintln!(
        "floor darker by > 8/255: {:.2} %; brighter pixels {brighter}",
        share * 100.0
    );
    assert_eq!(brighter, 0, "a shadow brightened a pixel");
    assert!(share > 0.04, "the columns cast no shadow on the floor");
}

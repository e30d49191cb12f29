//! Comparing a grown mesh with the CPU reference (`model::speleothem::grow_reference`),
//! one rule for every test that grows speleothems on the GPU.

use sediment::model::speleothem::RingVertex;

/// The triangles of a mesh in a canonical order: by speleothem, ring, segment and ID
/// of each vertex, then by position (rounded) between coincident keys — for paths that
/// emit the reference's triangles in another order (append-only).
pub fn sorted_triangles(mesh: &[RingVertex]) -> Vec<RingVertex> {
    let key = |v: &RingVertex| {
        let p = v.position() * 1e3;
        (
            [
                v.speleothem() as i64,
                i64::from(v.ring()),
                i64::from(v.segment()),
            ],
            v.id() as i64,
            [p.x.round() as i64, p.y.round() as i64, p.z.round() as i64],
        )
    };
    let mut triangles: Vec<&[RingVertex]> = mesh.chunks_exact(3).collect();
    triangles.sort_by_key(|t| [key(&t[0]), key(&t[1]), key(&t[2])]);
    triangles.concat()
}

/// `gpu[i]` equals `cpu[i]` for every i: positions within 1e-4 of `scale` (the
/// scene's height: 2.4 units for the default chamber), IDs and integer attributes
/// exact, normals within 1e-4, thickening and ring index within 1e-4 of the scale.
pub fn assert_matches(name: &str, gpu: &[RingVertex], cpu: &[RingVertex], scale: f32) {
    assert_eq!(gpu.len(), cpu.len(), "{name}: vertex count");
    let differs = |g: &RingVertex, c: &RingVertex| {
        let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol;
        (0..3).any(|k| !close(g.pos_id[k], c.pos_id[k], 1e-4 * scale))
            || g.pos_id[3] != c.pos_id[3]
            || g.normal_sp[3] != c.normal_sp[3]
            || g.extra[0] != c.extra[0]
            || g.extra[3] != c.extra[3]
            || (0..3).any(|k| !close(g.normal_sp[k], c.normal_sp[k], 1e-4))
            || (1..3).any(|k| !close(g.extra[k], c.extra[k], 1e-4 * scale.max(c.extra[k].abs())))
    };
    let wrong: Vec<usize> = (0..gpu.len())
        .filter(|&i| differs(&gpu[i], &cpu[i]))
        .collect();
    assert!(
        wrong.is_empty(),
        "{name}: out of {} vertices, {} differed; first at {}: GPU {:?} CPU {:?}",
        gpu.len(),
        wrong.len(),
        wrong[0],
        gpu[wrong[0]],
        cpu[wrong[0]]
    );
}

/// Pictures of `scene` grown to its end on the paper's GS/XFB path, from `camera` at
/// `size`, with a switch of its look (`set(look, on)`) on, off, and on then turned by
/// the viewer's `key`: `[on, off, keyed]`, for tests that hold a key to its option.
pub fn switch_pictures(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    scene: &sediment::scene::grow::SpeleothemScene,
    (camera, size): (&sediment::camera::Camera, sediment::Size),
    key: sediment::input::Key,
    set: impl Fn(&mut sediment::scene::grow::Look, bool),
) -> [image::RgbaImage; 3] {
    use sediment::frame::{FrameRunner, Interactive, Scene, Time};
    use sediment::render::growth::GrowthPath;
    use sediment::scene::grow::{GrowthFrame, SpeleothemScene};
    let frame_with = |on: bool| {
        let mut model: SpeleothemScene = scene.clone();
        set(&mut model.look, on);
        GrowthFrame::with_look(ctx, model, GrowthPath::XfbRestream).expect("frame")
    };
    let draw = |mut frame: GrowthFrame| {
        let mut runner = FrameRunner::new(ctx, size).expect("runner");
        let end = Time::At(u32::MAX);
        frame.advance_to(ctx, end, &|_, _, _| {}).expect("grow");
        runner.render(&mut frame, camera, end).expect("render").0
    };
    let mut keyed = frame_with(true);
    assert!(keyed.key(ctx, key).expect("key"), "{key:?} not handled");
    [draw(frame_with(true)), draw(frame_with(false)), draw(keyed)]
}

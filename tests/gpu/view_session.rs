//! The viewer's growth session without a window: steering mid-growth, including a
//! change that adds speleothems (the first switch to PIL 2) and so regrows the passes
//! so far, ends in exactly the mesh the CPU reference grows from the same changes.

use crate::common;

use sediment::Size;
use sediment::frame::{FrameRunner, Interactive, Time};
use sediment::input::Key;
use sediment::model::speleothem::grow_reference;
use sediment::model::speleothem::plan::{GrowthParams, GrowthScene};
use sediment::model::speleothem::table2::Pil;
use sediment::render::growth::GrowthPath;
use sediment::scene::grow::{GrowthFrame, default_camera};

/// Runs `frames` viewer ticks of the session (one pass each).
fn frames(
    ctx: &std::sync::Arc<sediment::gpu::Context>,
    session: &mut GrowthFrame,
    scene: &GrowthScene,
    n: u32,
) {
    let mut runner = FrameRunner::new(ctx, Size::new(64, 48)).expect("runner");
    let camera = default_camera(scene);
    for _ in 0..n {
        runner
            .frame(session, &camera, Time::Tick, false)
            .expect("frame");
        session.counts().expect("counts");
    }
}

#[test]
fn steering_ends_in_the_reference_mesh_of_the_same_changes() {
    common::with_gpu(|ctx| {
        for kind in [GrowthPath::XfbAppend, GrowthPath::XfbRestream] {
            let scene = GrowthScene {
                count: 2,
                passes: 16,
                segments: 12,
                params: GrowthParams::default(),
                ..GrowthScene::default()
            };
            let mut session = GrowthFrame::new(ctx, scene.clone(), kind).expect("session");
            frames(ctx, &mut session, &scene, 5);
            assert_eq!(session.plan().speleothems.len(), 2, "stalactites only");
            // PIL 1 -> 2 at pass 5: stalagmites appear (regrow), then CO2 at pass 9
            // (plan rewritten in place).
            assert!(session.key(ctx, Key::Char('p')).expect("key"));
            assert_eq!(session.params().pil, Pil::Dripping);
            assert_eq!(session.plan().speleothems.len(), 4, "stalagmites added");
            assert_eq!(session.passes_done(), 5, "regrown to where it was");
            frames(ctx, &mut session, &scene, 4);
            assert!(session.key(ctx, Key::Char('c')).expect("key"));
            frames(ctx, &mut session, &scene, 10);
            assert_eq!(session.passes_done(), 16);

            let mut expected = scene.clone();
            expected.changes = session_changes();
            let plan = expected.plan().expect("plan");
            assert_eq!(
                &plan,
                session.plan(),
                "{kind:?}: the plan of the same changes"
            );
            let mesh = session.read_back(ctx).expect("read back");
            let reference = grow_reference(&plan, plan.passes);
            assert_eq!(mesh.len(), reference.len(), "{kind:?}: vertex count");
            let key = |v: &sediment::model::speleothem::RingVertex| {
                let p = v.position() * 1e4;
                [p.x.round() as i64, p.y.round() as i64, p.z.round() as i64]
            };
            let mut a: Vec<_> = mesh.iter().map(key).collect();
            let mut b: Vec<_> = reference.iter().map(key).collect();
            a.sort_unstable();
            b.sort_unstable();
            let differing = a.iter().zip(&b).filter(|(x, y)| x != y).count();
            assert!(
                differing <= a.len() / 1000,
                "{kind:?}: {differing} of {} vertex positions differ",
                a.len()
            );
        }
    });
}

/// The changes the keys above made: PIL 2 at pass 5, CO2 normal -> high at pass 9.
fn session_changes() -> Vec<sediment::model::speleothem::plan::ParamChange> {
    use sediment::model::speleothem::plan::ParamChange;
    use sediment::model::speleothem::table2::Co2;
    vec![
        ParamChange {
            pass: 5,
            pil: Some(Pil::Dripping),
            ..ParamChange::default()
        },
        ParamChange {
            pass: 9,
            co2: Some(Co2::High),
            ..ParamChange::default()
        },
    ]
}

mod common;
use sediment::frame::{FrameRunner, Time};
use sediment::scene::Size;
use sediment::scene::dunes;

#[test]
fn scratch_timing() {
    let configs: Vec<Vec<(String, String)>> = std::env::var("CONFIGS")
        .unwrap_or_default()
        .split(';')
        .map(|c| {
            c.split_whitespace()
                .filter_map(|kv| kv.split_once('='))
                .map(|(k, v)| (k.to_owned(), v.to_owned()))
                .collect()
        })
        .collect();
    let preset = std::env::var("PRESET").unwrap_or("fig17".into());
    let scene = dunes::preset(&preset).expect("preset");
    let terrain = dunes::simulate(&scene, &mut |_, _| {}).expect("simulate");
    let ctx = common::gpu_options(sediment::gpu::ContextOptions {
        temporal: true,
        validate: false,
        ..Default::default()
    });
    let camera = dunes::default_camera(&scene, &terrain);
    let mut frame = dunes::frame::DunesFrame::new(&ctx, scene.clone(), &terrain).expect("f");
    let mut runner = FrameRunner::new(&ctx, Size::new(720, 480)).expect("r");
    let mut times: Vec<Vec<f64>> = vec![Vec::new(); configs.len()];
    for round in 0..60 {
        for (k, c) in configs.iter().enumerate() {
            for (key, v) in c {
                // SAFETY: single-threaded scratch test.
                unsafe { std::env::set_var(key, v) };
            }
            let f = runner
                .frame(&mut frame, &camera, Time::At(0), false)
                .expect("frame");
            for (key, _) in c {
                unsafe { std::env::remove_var(key) };
            }
            if round >= 5 {
                times[k].push(f.gpu_ms());
            }
        }
    }
    for (k, t) in times.iter_mut().enumerate() {
        t.sort_by(f64::total_cmp);
        eprintln!(
            "TIMING config {:?}: median {:.2} ms p25 {:.2} p75 {:.2}",
            configs[k],
            t[t.len() / 2],
            t[t.len() / 4],
            t[3 * t.len() / 4]
        );
    }
}

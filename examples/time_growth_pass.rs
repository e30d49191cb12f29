//! Time one ring-growth pass on each of sediment's four growth paths (the paper's
//! GS/XFB re-streaming pass, its append-only variant, the compute-shader twin and the
//! CPU reference uploaded), with GPU timestamps, after the passes before it.
//!
//! ```sh
//! cargo run --release --example time_growth_pass -- [PRESET] [PASS]   # fig9g, 30
//! ```
//! `sediment bench grow` is the full instrument (warm-up, medians, the floor).

use sediment::gpu::{Context, ContextOptions};
use sediment::render::growth::GrowthPath;
use sediment::scene::grow::{self, GrowthFrame};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let preset = args.next().unwrap_or_else(|| "fig9g".to_owned());
    let pass: u32 = args.next().map_or(Ok(30), |s| s.parse())?;

    let ctx = Context::new(&ContextOptions::default().with_env())?;
    println!("device: {}", ctx.info().name);
    for path in GrowthPath::ALL {
        let mut scene = grow::preset(&preset)?.growth_scene()?;
        scene.passes = scene.passes.max(pass);
        let mut frame = GrowthFrame::new(&ctx, scene, path)?;
        // The passes before (the first also compiles the shaders on lavapipe).
        frame.advance(&ctx, pass - 1, &mut |_, _| {})?;
        let ms = frame.advance(&ctx, 1, &mut |_, _| {})?;
        // Vertices after each pass: this pass's output.
        let vertices = sediment::model::speleothem::vertex_counts(frame.plan())
            .get(pass as usize - 1)
            .copied()
            .unwrap_or(0);
        println!(
            "{:<18} pass {pass}: {ms:8.3} ms ({:.3} M vertices after it)",
            path.name(),
            vertices as f64 / 1e6
        );
    }
    Ok(())
}

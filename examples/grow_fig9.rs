//! Grow Figure 9f's columns on the paper's geometry-shader / transform-feedback pass and
//! write the frame as PNG and the grown mesh as glTF (stalactites, stalagmites and
//! columns as named parts, in metres).
//!
//! ```sh
//! cargo run --release --example grow_fig9 -- [PRESET] [OUT_DIR]   # default fig9f, .
//! ```

use std::path::PathBuf;

use sediment::Size;
use sediment::frame::{FrameRunner, Scene, Time};
use sediment::gpu::{Context, ContextOptions};
use sediment::render::growth::GrowthPath;
use sediment::scene::grow;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let preset = args.next().unwrap_or_else(|| "fig9f".to_owned());
    let out = args
        .next()
        .map_or_else(|| PathBuf::from("."), PathBuf::from);

    // Lavapipe where there is no GPU; `SEDIMENT_DEVICE` picks another device by name.
    let ctx = Context::new(&ContextOptions::default().with_env())?;
    let params = grow::preset(&preset)?;
    let scene = params.speleothems()?;
    let camera = grow::default_camera(&scene.growth);
    let floor_y = scene.growth.floor_y;
    // The paper's pass: the whole mesh re-streamed through the geometry shader.
    let mut frame = grow::GrowthFrame::with_look(&ctx, scene, GrowthPath::XfbRestream)?;
    let end = Time::At(u32::MAX);
    frame.advance_to(&ctx, end, &|_, done, total| {
        eprint!("\rpass {done}/{total}")
    })?;
    eprintln!();
    let mut runner = FrameRunner::new(&ctx, Size::new(720, 480))?;
    let (image, _) = runner.render(&mut frame, &camera, end)?;

    let png = out.join(format!("{preset}.png"));
    sediment::export::png::write_png(&png, &image)?;
    println!("wrote {}", png.display());

    // One scene unit is one metre; the floor at y = floor_y becomes y = 0.
    let mesh = frame.read_back(&ctx)?;
    let mut asset = grow::export_asset(frame.plan(), &mesh, &preset, 1.0, floor_y);
    let glb = out.join(format!("{preset}.glb"));
    println!(
        "{}",
        // Ordered for the vertex cache, no coarser levels of detail.
        sediment::export::mesh::write_mesh(&glb, &mut asset, 0)?.line()
    );
    Ok(())
}

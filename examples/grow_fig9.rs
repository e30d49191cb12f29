//! Grow Figure 9f's columns on the paper's geometry-shader / transform-feedback pass and
//! write the frame as PNG and the grown mesh as glTF (stalactites, stalagmites and
//! columns as named parts, in metres).
//!
//! ```sh
//! cargo run --release --example grow_fig9 -- [PRESET] [OUT_DIR]   # default fig9f, .
//! ```

use std::path::PathBuf;

use sediment::Size;
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
    let scene = grow::preset(&preset)?;
    let outputs = grow::GrowOutputs {
        path: GrowthPath::XfbRestream,
        look: grow::preset_look(&preset),
        camera: None,
        frame_every: None,
        mesh: true,
    };
    let grown = grow::grow(
        &ctx,
        &scene,
        Size::new(720, 480),
        &outputs,
        &mut |done, total| {
            eprint!("\rpass {done}/{total}");
        },
    )?;
    eprintln!();

    let png = out.join(format!("{preset}.png"));
    sediment::export::png::write_png(&png, &grown.image)?;
    println!("wrote {}", png.display());

    let mesh = grown.mesh.as_ref().ok_or("the growth kept no mesh")?;
    // One scene unit is one metre; the floor at y = floor_y becomes y = 0.
    let asset = grow::export_asset(&grown.plan, mesh, &preset, 1.0, scene.floor_y);
    let glb = out.join(format!("{preset}.glb"));
    println!(
        "{}",
        sediment::export::mesh::write_mesh(&glb, &asset)?.line()
    );
    Ok(())
}

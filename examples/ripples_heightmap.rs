//! Simulate wind ripples on the CPU (Nishimori & Ouchi's saltation and creep, the
//! paper's ripple values) and write the tile as a 16-bit PNG heightmap with its height
//! range in metres, ready for a terrain tool's displacement.
//!
//! ```sh
//! cargo run --release --example ripples_heightmap -- [OUT.png] [STEPS]   # ripples.png, 1200
//! ```

use std::path::PathBuf;

use sediment::export::heightmap::{Heightmap, write_heightmap};
use sediment::model::sand::{Heightfield, SandParams, SandSim};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args
        .next()
        .map_or_else(|| PathBuf::from("ripples.png"), PathBuf::from);
    let steps: u32 = args.next().map_or(Ok(1200), |s| s.parse())?;

    // A 256 x 256 tile of loose sand: flat plus a little noise, seeded.
    let size = 256;
    let start = Heightfield::random(size, size, 0.0, 1.0, 1);
    let mut sim = SandSim::new(start, SandParams::paper_ripples())?;
    let clock = std::time::Instant::now();
    sim.run(steps, &mut |done| {
        if done % 100 == 0 {
            eprint!("\rstep {done}/{steps}");
        }
    });
    eprintln!(
        "\r{steps} steps of {size}x{size} cells in {:.2} s",
        clock.elapsed().as_secs_f64()
    );

    // The tile covers 16 m (6.25 cm a cell); the model's sand amounts become heights
    // through its vertical scale, in cell widths.
    let cell_m = 16.0 / size as f64;
    let field = sim.field();
    let lo = field.data.iter().copied().fold(f64::INFINITY, f64::min);
    let scale = SandParams::paper_ripples().vertical_scale * cell_m;
    let map = Heightmap {
        width: field.width,
        height: field.height,
        cell_m,
        heights_m: field.data.iter().map(|&h| (h - lo) * scale).collect(),
        // The simulation's boundaries are periodic: the tile repeats seamlessly.
        periodic: true,
    };
    let (range, files) = write_heightmap(&out, &map)?;
    for f in &files {
        println!("wrote {}", f.display());
    }
    println!("{}", range.line());
    Ok(())
}

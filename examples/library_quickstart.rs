//! The README's library example: the wind-ripple model run on the CPU, no GPU needed
//! (`cargo run --release --example library_quickstart`). tests/docs.rs holds the
//! README's block equal to this program.

use sediment::model::sand::{Heightfield, SandParams, SandSim};

fn main() -> Result<(), sediment::Error> {
    // Wind ripples on a 32 x 32 tile: 20 steps of saltation and creep.
    let start = Heightfield::random(32, 32, 0.0, 1.0, 7);
    let mut sim = SandSim::new(start, SandParams::paper_ripples())?;
    sim.run(20, &mut |_step| {});
    let highest = sim.field().data.iter().fold(0.0_f64, |a, &b| a.max(b));
    println!("highest sand: {highest}");
    Ok(())
}

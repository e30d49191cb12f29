//! One interface over the four ways sediment grows Tortelli & Walter's rings: the
//! paper's geometry-shader / transform-feedback pass re-streaming the whole mesh
//! (`ring_growth`), the same shader fed only the growth front (`ring_growth_append`),
//! the same pass as a compute shader (`ring_growth_compute`) and the CPU reference
//! generating each pass and uploading it (`ring_growth_cpu`). All four give the CPU
//! reference's mesh (`tests/gpu/ring_growth.rs`); `grow`, `cave`, `view` and `bench` hold
//! a `Box<dyn Growth>` and never ask which.

use std::str::FromStr;
use std::sync::Arc;

use super::ring_growth::RingGrowth;
use super::ring_growth_append::AppendGrowth;
use super::ring_growth_compute::ComputeGrowth;
use super::ring_growth_cpu::CpuGrowth;
use crate::error::{Error, Result};
use crate::gpu::{Buffer, Commands, Context, XfbStream};
use crate::model::speleothem::{GrowthPlan, RingVertex};

/// Where the surface pass draws the current mesh from.
pub enum MeshSource<'a> {
    /// A buffer with a known vertex count (the base primitives, the compute and CPU
    /// paths' output).
    Counted {
        /// Vertex buffer of `RingVertex`es, `VERTEX_STRIDE` bytes apart.
        buffer: &'a Buffer,
        /// Vertices to draw from the start of `buffer`.
        vertices: u32,
    },
    /// A capture, drawn with the byte count its counter holds (DrawAuto).
    Captured(&'a XfbStream),
    /// The append-only path: the vertices frozen so far (drawn shifted by each
    /// speleothem's accumulated thickening, see `model::speleothem::unfreeze`) and
    /// the current front band.
    Appended {
        /// Every band appended so far, drawn shifted by the thickening since it froze.
        frozen: &'a XfbStream,
        /// The current growth front, drawn as is (and the only part that gets caps).
        front: &'a XfbStream,
    },
}

/// How many vertices a growth holds and has emitted, as the path itself counted them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GrowthCounts {
    /// Vertices of the current mesh.
    pub vertices: u64,
    /// Vertices written over every pass so far (a re-streaming path writes its whole
    /// output each pass, the append-only path only the front's share).
    pub emitted: u64,
}

/// A growth in progress.
pub trait Growth {
    /// Which path this is.
    fn path(&self) -> GrowthPath;
    /// Passes grown so far by `record` (at most the plan's); 0 at the start.
    fn passes_done(&self) -> u32;
    /// Records the next `passes` passes (clamped to the plan) into `cmd` and leaves
    /// the mesh ready to draw; the CPU path generates and uploads them here, before the
    /// submission.
    fn record(&mut self, cmd: &Commands<'_>, passes: u32) -> Result<()>;
    /// Continues with `plan` (the same scene re-planned after a parameter change,
    /// whose passes so far are unchanged); false (nothing changed) when it does not fit
    /// this growth's buffers. No submission may be running.
    fn set_plan(&mut self, plan: &GrowthPlan) -> Result<bool>;
    /// After the submissions: the counts, or an error if a capture ran out of room.
    fn counts(&self) -> Result<GrowthCounts>;
    /// The current mesh, for drawing.
    fn source(&self) -> MeshSource<'_>;
    /// After the submissions: the vertices in the append-only path's frozen capture
    /// (`MeshSource::Appended`); 0 on the other paths.
    fn frozen_vertices(&self) -> Result<u64> {
        Ok(0)
    }
    /// The current mesh as the re-streaming pass holds it, read back.
    fn read_back(&self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Vec<RingVertex>>;
}

/// The four growth paths.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum GrowthPath {
    /// The paper's pass: the whole mesh re-streamed through the GS every pass.
    #[default]
    XfbRestream,
    /// Only the growth front through the GS; new bands appended (O(one ring) a pass).
    XfbAppend,
    /// The same per-triangle pass as a compute shader (every core on lavapipe).
    ComputeRestream,
    /// The CPU reference generates each pass; the mesh is uploaded whole.
    CpuUpload,
}

impl GrowthPath {
    /// Every path, the default first; the bench's variants and the names `FromStr` takes.
    pub const ALL: [GrowthPath; 4] = [
        GrowthPath::XfbRestream,
        GrowthPath::XfbAppend,
        GrowthPath::ComputeRestream,
        GrowthPath::CpuUpload,
    ];

    /// The name used by `--growth` and the bench's variants.
    pub fn name(self) -> &'static str {
        match self {
            GrowthPath::XfbRestream => "xfb-restream",
            GrowthPath::XfbAppend => "xfb-append",
            GrowthPath::ComputeRestream => "compute-restream",
            GrowthPath::CpuUpload => "cpu-upload",
        }
    }

    /// The short form `sediment grow --growth` also takes.
    pub fn short_name(self) -> &'static str {
        match self {
            GrowthPath::XfbRestream => "restream",
            GrowthPath::XfbAppend => "append",
            GrowthPath::ComputeRestream => "compute",
            GrowthPath::CpuUpload => "cpu",
        }
    }

    /// True when the passes run on the GPU (timed by GPU timestamps); false when the
    /// CPU generates them (timed by the clock).
    pub fn on_gpu(self) -> bool {
        self != GrowthPath::CpuUpload
    }

    /// Vertex buffers this path holds for `plan`, bytes: the re-streaming paths two
    /// of the largest mesh (ping-pong), the others one (append: the frozen mesh; cpu:
    /// the uploaded one).
    pub fn buffer_bytes(self, plan: &GrowthPlan) -> u64 {
        let largest = crate::model::speleothem::vertex_counts(plan)
            .into_iter()
            .max()
            .unwrap_or(0);
        let copies = match self {
            GrowthPath::XfbRestream | GrowthPath::ComputeRestream => 2,
            GrowthPath::XfbAppend | GrowthPath::CpuUpload => 1,
        };
        copies * largest * u64::from(crate::model::speleothem::VERTEX_STRIDE)
    }

    /// Refuses, before anything is allocated, a growth whose vertex buffers would not
    /// fit the device's memory (a raw ERROR_OUT_OF_DEVICE_MEMORY says nothing of what to
    /// reduce: issue 17 #8). Half the largest device heap is the budget: the frame,
    /// the shading and the driver need the rest.
    pub fn check_budget(self, ctx: &Context, plan: &GrowthPlan) -> Result<()> {
        self.check_budget_in(plan, ctx.info().device_heap_bytes)
    }

    /// `check_budget` against a heap of `heap` bytes.
    pub fn check_budget_in(self, plan: &GrowthPlan, heap: u64) -> Result<()> {
        let needed = self.buffer_bytes(plan);
        let budget = heap / 2;
        if heap == 0 || needed <= budget {
            return Ok(());
        }
        let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
        Err(Error::invalid(
            "growth size",
            format!(
                "the {} growth needs {:.1} GiB of vertex buffers for its {} speleothems x {} passes x {} segments; this device has {:.1} GiB ({:.1} GiB budgeted): reduce --count, --passes or --segments{}",
                self.short_name(),
                gib(needed),
                plan.speleothems.len(),
                plan.passes,
                plan.segments,
                gib(heap),
                gib(budget),
                if copies_two(self) {
                    ", or use --growth append (one buffer)"
                } else {
                    ""
                }
            ),
        ))
    }

    /// Starts a growth of `plan` on this path.
    pub fn start(self, ctx: &Arc<Context>, plan: &GrowthPlan) -> Result<Box<dyn Growth>> {
        self.check_budget(ctx, plan)?;
        Ok(match self {
            GrowthPath::XfbRestream => Box::new(RingGrowth::new(ctx, plan, None)?),
            GrowthPath::XfbAppend => Box::new(AppendGrowth::new(ctx, plan)?),
            GrowthPath::ComputeRestream => Box::new(ComputeGrowth::new(ctx, plan)?),
            GrowthPath::CpuUpload => Box::new(CpuGrowth::new(ctx, plan)?),
        })
    }
}

fn copies_two(path: GrowthPath) -> bool {
    matches!(path, GrowthPath::XfbRestream | GrowthPath::ComputeRestream)
}

impl std::fmt::Display for GrowthPath {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for GrowthPath {
    type Err = Error;
    /// A path's name, or its short form (`restream`, `append`, `compute`, `cpu`).
    fn from_str(s: &str) -> Result<Self> {
        let s = s.trim().to_ascii_lowercase();
        GrowthPath::ALL
            .into_iter()
            .find(|p| p.name() == s || p.short_name() == s)
            .ok_or_else(|| {
                Error::invalid(
                    "--growth",
                    format!(
                        "\"{s}\" is not one of: restream, append, compute, cpu (or {})",
                        GrowthPath::ALL.map(GrowthPath::name).join(", ")
                    ),
                )
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_short_forms_parse() {
        for (text, path) in [
            ("restream", GrowthPath::XfbRestream),
            ("append", GrowthPath::XfbAppend),
            ("compute", GrowthPath::ComputeRestream),
            ("cpu", GrowthPath::CpuUpload),
        ] {
            assert_eq!(text.parse::<GrowthPath>().ok(), Some(path));
            assert_eq!(path.name().parse::<GrowthPath>().ok(), Some(path));
        }
        assert!("upload".parse::<GrowthPath>().is_err());
        assert!("xfb".parse::<GrowthPath>().is_err());
    }
}

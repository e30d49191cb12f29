//! The append-only capture redrawn with fewer triangles far away
//! (`model::speleothem::lod`): each speleothem with every second or fourth segment
//! where that polygon stays within a fraction of a pixel of the full one, nearest
//! first. What a frame appends is copied out before the next frame's growth and taken
//! in after it; until then those triangles are drawn straight from the capture (the
//! tail), so nothing lags on screen. Each speleothem's vertices live in a buffer of
//! their own, of which only what changed is rewritten as it grows.
//!
//! Only skipping segments pays: on lavapipe the same triangles redrawn from buffers of
//! their own, or through an index buffer over the capture, cost more than the capture
//! drawn as it is.

use std::sync::Arc;

use crate::camera::Camera;
use crate::error::Result;
use crate::gpu::{Buffer, BufferDesc, Commands, Context, XfbStream, vk};
use crate::model::speleothem::lod::{CaptureIndex, Part, segment_step};
use crate::model::speleothem::{RingVertex, VERTEX_STRIDE};

/// The viewer's default error bound: half a pixel, below what temporal anti-aliasing's
/// 4x4 samples resolve along a silhouette.
pub const DEFAULT_MAX_ERROR_PX: f32 = 0.5;

/// One speleothem as drawn: its part of the index and the vertices on the GPU.
#[derive(Default)]
struct Drawn {
    part: Part,
    vertices: Option<Buffer>,
}

/// The simplified capture of one growth.
pub struct CaptureLod {
    index: CaptureIndex,
    max_error_px: f32,
    segments: u32,
    /// A copy recorded this frame: the buffer and how many vertices it holds.
    copied: Option<(Buffer, u64)>,
    /// Vertices of the capture copied out so far (taken in, or in `copied`).
    copied_to: u64,
    drawn: Vec<Drawn>,
    /// Speleothems nearest first.
    order: Vec<usize>,
    /// Vertices of the capture the parts hold (the tail is drawn from there).
    covered: u32,
    ctx: Arc<Context>,
}

impl CaptureLod {
    /// For rings of `segments` segments, each speleothem's polygon within
    /// `max_error_px` pixels of the full one.
    pub fn new(ctx: &Arc<Context>, segments: u32, max_error_px: f32) -> Self {
        Self {
            index: CaptureIndex::new(segments),
            max_error_px,
            segments,
            copied: None,
            copied_to: 0,
            drawn: Vec::new(),
            order: Vec::new(),
            covered: 0,
            ctx: ctx.clone(),
        }
    }

    /// Records, before this frame's growth, a copy of what `frozen` gained up to
    /// `frozen_vertices` (its count after the last submission).
    pub fn record_copy(
        &mut self,
        cmd: &Commands<'_>,
        frozen: &XfbStream,
        frozen_vertices: u64,
    ) -> Result<()> {
        if frozen_vertices <= self.copied_to || self.copied.is_some() {
            return Ok(());
        }
        let stride = u64::from(VERTEX_STRIDE);
        let count = frozen_vertices - self.copied_to;
        let buffer = Buffer::new(
            &self.ctx,
            "speleothem capture copy",
            BufferDesc::readback(count * stride, vk::BufferUsageFlags::TRANSFER_DST),
        )?;
        frozen.copy_out(cmd, self.copied_to * stride, count * stride, &buffer)?;
        self.copied_to = frozen_vertices;
        self.copied = Some((buffer, count));
        Ok(())
    }

    /// After the submission: takes in what `record_copy` copied.
    pub fn take_in(&mut self) -> Result<()> {
        if let Some((buffer, count)) = self.copied.take() {
            let vertices: Vec<RingVertex> = buffer.read()?;
            let whole = (count as usize).min(vertices.len());
            self.index.extend(&vertices[..whole]);
        }
        Ok(())
    }

    /// Chooses each speleothem's step for `camera` over a target `height_px` tall and
    /// rewrites what changed.
    pub fn prepare(&mut self, camera: &Camera, height_px: u32) -> Result<()> {
        // Pixels per unit of length at distance 1.
        let scale =
            height_px as f32 / (2.0 * (camera.fov_y_degrees.to_radians() * 0.5).tan()).max(1e-6);
        let n = self.index.speleothems();
        self.drawn.resize_with(n, Drawn::default);
        let mut distance = vec![f32::INFINITY; n];
        for (i, drawn) in self.drawn.iter_mut().enumerate() {
            let mut step = 1;
            if let Some((lo, hi)) = self.index.bounds(i) {
                distance[i] = camera.eye.distance(camera.eye.clamp(lo, hi));
                let radius = 0.5 * (hi.x - lo.x).max(hi.z - lo.z);
                let radius_px = radius * scale / distance[i].max(camera.near);
                step = segment_step(radius_px, self.segments, self.max_error_px);
            }
            let from = self.index.refresh(i, step, &mut drawn.part);
            let indices = &drawn.part.indices;
            if from >= indices.len() && drawn.vertices.is_some() {
                continue;
            }
            let stride = VERTEX_STRIDE as usize;
            let needed = (indices.len().max(1) * stride) as u64;
            // Grown past its buffer: a larger one, written whole.
            let from = match &drawn.vertices {
                Some(b) if b.size() >= needed => from,
                _ => {
                    drawn.vertices = Some(Buffer::new(
                        &self.ctx,
                        "speleothem vertices",
                        BufferDesc::upload(
                            needed.next_power_of_two(),
                            vk::BufferUsageFlags::VERTEX_BUFFER,
                        ),
                    )?);
                    0
                }
            };
            let changed: Vec<RingVertex> = indices[from.min(indices.len())..]
                .iter()
                .filter_map(|&v| self.index.vertex(v).copied())
                .collect();
            // Nested, not a let-chain: the crate's MSRV (1.85) predates them.
            if let Some(buffer) = &mut drawn.vertices {
                if !changed.is_empty() {
                    buffer.write((from * stride) as u64, &changed)?;
                }
            }
        }
        // Nearest first: the depth test then rejects what near speleothems hide
        // before it is shaded (the capture's own order is pass by pass).
        self.order = (0..n).collect();
        self.order
            .sort_by(|&a, &b| distance[a].total_cmp(&distance[b]));
        self.covered = self.index.vertices();
        Ok(())
    }

    /// The vertices the parts cover, three a triangle, as captured.
    pub fn captured(&self) -> &[RingVertex] {
        &self.index.captured()[..self.covered as usize]
    }

    /// The triangles drawn for them, three vertices each, nearest speleothem first.
    pub fn simplified(&self) -> Vec<RingVertex> {
        self.order
            .iter()
            .flat_map(|&i| &self.drawn[i].part.indices)
            .filter_map(|&v| self.index.vertex(v).copied())
            .collect()
    }

    /// Draws `frozen` (pipeline, sets and push constants bound): each speleothem's
    /// part, nearest first, then what was appended since, straight from the capture.
    pub fn draw(&self, cmd: &Commands<'_>, frozen: &XfbStream) -> Result<()> {
        for &i in &self.order {
            let drawn = &self.drawn[i];
            if let (Some(buffer), n @ 1..) = (&drawn.vertices, drawn.part.indices.len()) {
                cmd.bind_vertex_buffer(buffer, 0);
                cmd.draw(n as u32, 1);
            }
        }
        frozen.draw_from(cmd, VERTEX_STRIDE, u64::from(self.covered))
    }
}

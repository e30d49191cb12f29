//! A transform-feedback self-test pass: proves on the running device that the `gpu`
//! XFB wrappers capture, feed back and count correctly. Each pass re-emits every
//! triangle moved by `offset` with its vertex IDs incremented by 2; pass 1 draws the
//! input with a CPU vertex count, later passes draw the previous capture with
//! `vkCmdDrawIndirectByteCountEXT`. All passes go in one command buffer.

use std::sync::Arc;

use glam::Vec4;

use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, CaptureMode, Context, GraphicsPipelineDesc, PipelineLayout, StreamCounts,
    StreamQueries, VertexLayout, XfbStream, vk,
};
use crate::shaders::{ShaderInterface, compiled};

/// `xfb_copy.vert`: no resources; hands each vertex (xyz position, w id) to the
/// geometry stage unchanged.
pub static VERTEX_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SELFTEST_XFB_COPY_VERT,
    bindings: &[],
    push_constant_bytes: 0,
};

/// Declared by hand: naga has no geometry stage.
pub static GEOMETRY_INTERFACE: ShaderInterface = ShaderInterface {
    shader: &compiled::SELFTEST_XFB_COPY_GEOM,
    bindings: &[],
    push_constant_bytes: size_of::<Vec4>() as u32,
};

/// What the passes captured.
pub struct SelftestResult {
    /// The last pass's captured vertices (xyz position, w id), as many as it wrote.
    pub vertices: Vec<[f32; 4]>,
    /// Stream-query counts of each pass.
    pub counts: Vec<StreamCounts>,
}

/// The CPU reference: what `passes` passes do to `input`.
pub fn reference(input: &[[f32; 4]], offset: Vec4, passes: u32) -> Vec<[f32; 4]> {
    input
        .iter()
        .map(|v| {
            let mut v = *v;
            for _ in 0..passes {
                v = [
                    v[0] + offset.x,
                    v[1] + offset.y,
                    v[2] + offset.z,
                    v[3] + 2.0,
                ];
            }
            v
        })
        .collect()
}

/// Runs `passes` ping-pong passes over `input` (whole triangles) with capture buffers
/// of `capacity_vertices` each.
pub fn run(
    ctx: &Arc<Context>,
    input: &[[f32; 4]],
    offset: Vec4,
    passes: u32,
    capacity_vertices: u32,
) -> Result<SelftestResult> {
    if input.is_empty() || input.len() % 3 != 0 || passes == 0 {
        return Err(Error::internal(
            "xfb self-test",
            "needs whole triangles and at least one pass",
        ));
    }
    const STRIDE: u32 = 16;
    let layout = PipelineLayout::new(
        ctx,
        "xfb self-test layout",
        &[&VERTEX_INTERFACE, &GEOMETRY_INTERFACE],
    )?;
    let pipeline = GraphicsPipelineDesc::new("xfb self-test", VERTEX_INTERFACE.shader)
        .geometry(GEOMETRY_INTERFACE.shader)
        .vertex_layout(VertexLayout {
            stride: STRIDE,
            attributes: vec![(0, vk::Format::R32G32B32A32_SFLOAT, 0)],
        })
        .rasterizer_discard(true)
        .build(ctx, &layout)?;
    let source = Buffer::with_data(
        ctx,
        "xfb self-test input",
        vk::BufferUsageFlags::VERTEX_BUFFER,
        input,
    )?;
    let bytes = u64::from(capacity_vertices.max(1)) * u64::from(STRIDE);
    let captures = [
        XfbStream::new(ctx, "xfb self-test capture A", bytes)?,
        XfbStream::new(ctx, "xfb self-test capture B", bytes)?,
    ];
    let queries = StreamQueries::new(ctx, "xfb self-test queries", passes)?;
    ctx.submit_and_wait("xfb self-test", |cmd| {
        queries.reset(cmd);
        for pass in 0..passes {
            let dst = &captures[(pass % 2) as usize];
            XfbStream::prepare_captures(cmd, &[(dst, CaptureMode::Restart)]);
            cmd.begin_rendering_without_attachments(1, 1);
            cmd.bind_pipeline(&pipeline, &layout, &[]);
            cmd.push_constants(&layout, &offset)?;
            queries.begin(cmd, pass)?;
            dst.begin(cmd, CaptureMode::Restart)?;
            if pass == 0 {
                cmd.bind_vertex_buffer(&source, 0);
                cmd.draw(input.len() as u32, 1);
            } else {
                captures[((pass + 1) % 2) as usize].draw(cmd, STRIDE, 1)?;
            }
            dst.end(cmd)?;
            queries.end(cmd, pass)?;
            cmd.end_rendering();
            XfbStream::finish_captures(cmd, &[dst]);
        }
        Ok(())
    })?;
    Ok(SelftestResult {
        vertices: captures[((passes - 1) % 2) as usize].read_back(ctx)?,
        counts: queries.results(passes)?,
    })
}

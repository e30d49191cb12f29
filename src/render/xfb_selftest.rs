//! A transform-feedback self-test pass: proves on the running device that the `gpu`
//! XFB wrappers capture, feed back and count correctly. Each pass re-emits every
//! triangle moved by `offset` with its vertex IDs incremented by 2; pass 1 draws the
//! input with a CPU vertex count, later passes draw the previous capture with
//! `vkCmdDrawIndirectByteCountEXT`. All passes go in one command buffer.

use std::sync::Arc;

use glam::Vec4;

use crate::error::{Error, Result};
use crate::gpu::{
    Buffer, BufferDesc, Context, GraphicsPipelineDesc, PipelineLayout, StreamCounts, StreamQueries,
    VertexLayout, capture_buffer, counter_buffer, vk,
};
use crate::shaders::{ShaderInterface, compiled};

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
        return Err(Error::invalid(
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
        capture_buffer(ctx, "xfb self-test capture A", bytes)?,
        capture_buffer(ctx, "xfb self-test capture B", bytes)?,
    ];
    // One counter per capture buffer: counter i holds the bytes captured into buffer i.
    let counters = counter_buffer(ctx, "xfb self-test counters", 2)?;
    let queries = StreamQueries::new(ctx, "xfb self-test queries", passes)?;
    let readback = Buffer::new(
        ctx,
        "xfb self-test readback",
        BufferDesc::readback(bytes + 4, vk::BufferUsageFlags::TRANSFER_DST),
    )?;
    let last = ((passes - 1) % 2) as usize;

    ctx.submit_and_wait("xfb self-test", |cmd| {
        queries.reset(cmd);
        cmd.fill_buffer(&counters, 0, 8, 0);
        cmd.transfer_to_all_barrier();
        for pass in 0..passes {
            let dst = (pass % 2) as usize;
            if pass >= 2 {
                // Buffer `dst` was the vertex input two passes ago.
                cmd.vertex_read_to_capture_barrier();
            }
            cmd.begin_rendering_without_attachments(1, 1);
            cmd.bind_pipeline(&pipeline, &layout, &[]);
            cmd.push_constants(&layout, &offset)?;
            cmd.bind_capture_buffer(0, &captures[dst], 0, None);
            queries.begin(cmd, pass)?;
            cmd.begin_capture(None);
            if pass == 0 {
                cmd.bind_vertex_buffer(&source, 0);
                cmd.draw(input.len() as u32, 1);
            } else {
                let src = 1 - dst;
                cmd.bind_vertex_buffer(&captures[src], 0);
                cmd.draw_indirect_byte_count(&counters, src as u64 * 4, STRIDE, 1);
            }
            cmd.end_capture(Some((&counters, dst as u64 * 4)));
            queries.end(cmd, pass)?;
            cmd.end_rendering();
            cmd.capture_to_vertex_read_barrier();
            cmd.counter_write_to_read_barrier();
        }
        cmd.copy_buffer(&captures[last], &readback, bytes);
        cmd.copy_buffer_region(&counters, last as u64 * 4, &readback, bytes, 4);
        cmd.transfer_to_host_barrier();
        Ok(())
    })?;

    let data: Vec<u8> = readback.mapped()?.to_vec();
    let byte_count = u32::from_le_bytes(
        data[bytes as usize..bytes as usize + 4]
            .try_into()
            .map_err(|_| Error::invalid("xfb self-test", "short readback"))?,
    );
    let captured_vertices = (byte_count / STRIDE) as usize;
    let vertices: Vec<[f32; 4]> = crate::gpu::from_bytes(&data[..bytes as usize]);
    Ok(SelftestResult {
        vertices: vertices.into_iter().take(captured_vertices).collect(),
        counts: queries.results(passes)?,
    })
}

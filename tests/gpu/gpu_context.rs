//! The Vulkan context on the test device: features, validation canary, device choice,
//! and the XFB wrappers against their CPU reference.

use crate::common;

use glam::Vec4;
use sediment::gpu::{Buffer, BufferDesc, Context, ContextOptions, GpuTimer, vk};
use sediment::render::xfb_selftest;

#[test]
fn required_features_are_reported_present() {
    let reports = sediment::gpu::probe_devices().expect("a Vulkan device (see README)");
    let ctx = common::gpu();
    let report = reports
        .iter()
        .find(|r| r.name == ctx.info().name)
        .expect("the chosen device is among the probed ones");
    for name in [
        "geometryShader",
        "transformFeedback",
        "transformFeedbackDraw",
        "transformFeedbackQueries",
        "timestamps",
    ] {
        let c = report
            .capabilities
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("{name} is not reported"));
        assert!(c.present && c.required, "{name}: {c:?}");
    }
}

#[test]
fn validation_errors_are_recorded() {
    let ctx = common::gpu();
    assert!(ctx.validating());
    // A fill into a buffer created without TRANSFER_DST usage is a validation error.
    let buffer = Buffer::new(
        &ctx,
        "canary",
        BufferDesc::upload(64, vk::BufferUsageFlags::UNIFORM_BUFFER),
    )
    .expect("buffer");
    ctx.submit_and_wait("canary", |cmd| {
        cmd.fill_buffer(&buffer, 0, 64, 0);
        Ok(())
    })
    .expect("submission");
    let errors = ctx.take_validation_errors();
    assert!(
        errors.iter().any(|e| e.contains("TRANSFER_DST")),
        "expected a usage error, got {errors:?}"
    );
    assert_eq!(ctx.validation_error_count(), 0, "errors are taken once");
}

#[test]
fn synchronization_hazards_are_recorded() {
    let ctx = common::gpu();
    // Two fills of one buffer with no barrier between them: a write-after-write hazard
    // that only synchronization validation reports.
    let buffer = Buffer::new(
        &ctx,
        "hazard canary",
        BufferDesc::gpu_only(64, vk::BufferUsageFlags::TRANSFER_DST),
    )
    .expect("buffer");
    ctx.submit_and_wait("hazard canary", |cmd| {
        cmd.fill_buffer(&buffer, 0, 64, 0);
        cmd.fill_buffer(&buffer, 0, 64, 1);
        Ok(())
    })
    .expect("submission");
    let errors = ctx.take_validation_errors();
    assert!(
        errors
            .iter()
            .any(|e| e.contains("SYNC-HAZARD-WRITE-AFTER-WRITE")),
        "expected a write-after-write hazard, got {errors:?}"
    );
}

#[test]
#[should_panic(expected = "1 validation error(s)")]
fn a_test_that_leaves_a_validation_error_fails_when_its_device_drops() {
    let ctx = common::gpu();
    let buffer = Buffer::new(
        &ctx,
        "guard canary",
        BufferDesc::upload(64, vk::BufferUsageFlags::UNIFORM_BUFFER),
    )
    .expect("buffer");
    ctx.submit_and_wait("guard canary", |cmd| {
        cmd.fill_buffer(&buffer, 0, 64, 0);
        Ok(())
    })
    .expect("submission");
}

#[test]
fn timer_spans_close_with_their_closure_or_scope() {
    let ctx = common::gpu();
    let mut timer = GpuTimer::new(&ctx, "span test", 2).expect("timer");
    ctx.submit_and_wait("spans", |cmd| {
        timer.reset(cmd);
        let value = timer.span(cmd, "closure", |_| Ok(7))?;
        assert_eq!(value, 7);
        {
            let _scope = timer.scope(cmd, "scope")?;
        }
        assert!(
            timer.scope(cmd, "one too many").is_err(),
            "a third span does not fit a timer of two"
        );
        Ok(())
    })
    .expect("submission");
    let spans = timer.read().expect("spans");
    let names: Vec<&str> = spans.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(names, ["closure", "scope"]);
    assert!(spans.iter().all(|s| s.milliseconds >= 0.0));
}

#[test]
fn an_unknown_device_name_is_a_clear_error() {
    let err = match Context::new(&ContextOptions {
        device: Some("no-such-gpu-xyz".to_owned()),
        validate: false,
        sync_validation: false,
        window: None,
        samples: None,
        sample_shading: None,
        supersample: None,
        temporal: false,
    }) {
        Ok(_) => panic!("no device is called no-such-gpu-xyz"),
        Err(e) => e.to_string(),
    };
    assert!(
        err.contains("no-such-gpu-xyz") && err.contains("Devices present"),
        "{err}"
    );
}

fn triangles(n: usize) -> Vec<[f32; 4]> {
    (0..n * 3)
        .map(|i| {
            let f = i as f32;
            [
                f * 0.25,
                (f * 0.5).sin(),
                -f * 0.125,
                if i % 3 == 0 { 0.0 } else { -1.0 },
            ]
        })
        .collect()
}

#[test]
fn transform_feedback_ping_pong_matches_cpu_reference() {
    common::with_gpu(|ctx| {
        let input = triangles(40);
        let offset = Vec4::new(0.5, -1.0, 0.25, 0.0);
        for passes in [1, 2, 5] {
            let result = xfb_selftest::run(ctx, &input, offset, passes, input.len() as u32)
                .expect("self-test runs");
            let expected = xfb_selftest::reference(&input, offset, passes);
            assert_eq!(
                result.vertices.len(),
                expected.len(),
                "captured vertex count"
            );
            let wrong = result
                .vertices
                .iter()
                .zip(&expected)
                .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| (x - y).abs() > 1e-5))
                .count();
            assert_eq!(
                wrong,
                0,
                "out of {}, {wrong} vertices were wrong",
                expected.len()
            );
            for (pass, c) in result.counts.iter().enumerate() {
                assert_eq!((c.written, c.needed), (40, 40), "pass {pass}");
            }
        }
    });
}

#[test]
fn stream_query_reports_overflow() {
    common::with_gpu(|ctx| {
        let input = triangles(10);
        // Room for 4 triangles only.
        let result = xfb_selftest::run(ctx, &input, Vec4::ZERO, 1, 12).expect("self-test runs");
        let c = result.counts[0];
        assert_eq!((c.written, c.needed), (4, 10));
        assert!(c.overflowed());
        assert_eq!(
            result.vertices.len(),
            12,
            "the counter is clamped to what fit"
        );
    });
}

#[test]
fn a_mip_chain_from_several_given_levels_completes_with_blits() {
    // Three levels given (16², 8², 4²), two blitted (2², 1²): every level must end in
    // the layout the barrier declares, which the validation layer tracks, and hold what
    // was copied or averaged into it.
    common::with_gpu(|ctx| {
        let sides = [16u32, 8, 4];
        let level = |k: usize| -> Vec<u8> {
            let n = (sides[k] * sides[k]) as usize;
            (0..n)
                .flat_map(|i| [40 * k as u8 + (i % 2) as u8 * 20, 100, 200, 255])
                .collect()
        };
        let bytes: Vec<u8> = (0..3).flat_map(level).collect();
        let offsets = [0u64, 16 * 16 * 4, (16 * 16 + 8 * 8) * 4];
        let buffer = Buffer::with_data(
            ctx,
            "mip levels",
            vk::BufferUsageFlags::TRANSFER_SRC,
            &bytes,
        )
        .expect("buffer");
        let image = sediment::gpu::Image::sampled_from_buffer_with_mips(
            ctx,
            "mip test",
            sediment::gpu::ImageDesc::new_2d(
                16,
                16,
                vk::Format::R8G8B8A8_UNORM,
                vk::ImageUsageFlags::SAMPLED,
            ),
            &buffer,
            &offsets,
            true,
        )
        .expect("image");
        assert_eq!(image.desc().mip_levels, 5);
        for k in 0..3 {
            assert_eq!(
                image.read_level(ctx, k as u32).expect("read"),
                level(k),
                "given level {k}"
            );
        }
        // Level 3 (2x2) is the box filter of level 2: red alternates 80/100 -> 90.
        for k in 3..5u32 {
            let texels = image.read_level(ctx, k).expect("read");
            for t in texels.chunks_exact(4) {
                assert!(
                    (i32::from(t[0]) - 90).abs() <= 1 && t[1] == 100 && t[2] == 200,
                    "level {k}: {t:?}"
                );
            }
        }
    });
}

#[test]
fn supersampling_is_lowered_to_what_the_device_and_the_budget_hold() {
    use sediment::Size;
    use sediment::frame::supersample::factor_for;
    let ctx = common::gpu();
    let max = ctx.info().max_image_dimension_2d;
    assert_eq!(factor_for(&ctx, Size::new(720, 480), 2), 2);
    assert_eq!(factor_for(&ctx, Size::new(720, 480), 4), 4);
    // Twice the side would pass the device's largest image.
    assert_eq!(factor_for(&ctx, Size::new(max / 2 + 1, 16), 2), 1);
    assert_eq!(factor_for(&ctx, Size::new(max / 3, 16), 4), 3);
    // 6000x6000 fits the 4 GiB host budget at 4 samples, 12000x12000 does not.
    assert_eq!(factor_for(&ctx, Size::new(3000, 3000), 2), 2);
    assert_eq!(factor_for(&ctx, Size::new(6000, 6000), 2), 1);
    common::assert_no_validation_errors(&ctx);
}

//! The one headless driver: any registered scene resolved, modelled, drawn through the
//! frame runner and written — the still picture, its animation streamed frame by frame,
//! its mesh and its own files. `sediment <scene>`, the demo gallery and library users
//! all render through [`render`]; each picture reaches the caller as a [`Shot`].

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use super::plugin::{AnyModel, AnyScene, OutputDef, OutputView, Progress, Resolved};
use super::{FrameRunner, Scene, Shot, Time};
use crate::Size;
use crate::camera::Camera;
use crate::error::Result;
use crate::gpu::{Context, Span};

/// What a headless run makes besides the still picture's pixels.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// Draw the still picture (`-o`); without it only the animation, mesh and files
    /// are made.
    pub picture: bool,
    /// Draw the animation (`--gif`), `Some(None)` with the scene's own frame count.
    pub animation: Option<Option<u32>>,
    /// Read the scene's asset (`--mesh`), named so.
    pub asset_title: Option<String>,
    /// Extra frames drawn after the picture and timed (`--timing-frames`).
    pub timing_frames: u32,
    /// The frame count an output of the scene's own animates over (`--gif-frames`
    /// without `--gif`).
    pub forming_frames: Option<u32>,
    /// The scene's own files (`SceneDef::outputs`) and where they go.
    pub outputs: Vec<(OutputDef, Option<PathBuf>)>,
    /// Say what the model made ([`super::SceneDef::made`], for `--json`).
    pub made: bool,
}

/// What a headless run made.
pub struct Rendered {
    /// The still picture, if asked for.
    pub picture: Option<Shot>,
    /// The scene's asset, if asked for.
    pub asset: Option<crate::export::asset::Asset>,
    /// GPU milliseconds of each timed frame.
    pub timed_ms: Vec<f64>,
    /// Status lines of the files the scene wrote itself ("wrote FILE ...").
    pub written: Vec<String>,
    /// Wall-clock milliseconds of the whole run (model included).
    pub wall_ms: f64,
    /// Wall-clock milliseconds of the CPU model (simulation, generation, planning).
    pub model_ms: f64,
    /// What the model made ([`super::SceneDef::made`]), if asked for.
    pub made: Option<serde_json::Value>,
}

/// Draws `scene` from each camera at each time, a picture each, handed to `on_shot`
/// as it is made (an animation of any length holds one frame).
pub fn shots(
    runner: &mut FrameRunner,
    scene: &mut dyn Scene,
    views: &[(Camera, Time)],
    on_shot: &mut dyn FnMut(usize, Shot) -> Result<()>,
) -> Result<()> {
    for (i, (camera, time)) in views.iter().enumerate() {
        let start = Instant::now();
        let (mut image, frame) = runner.render(scene, camera, *time)?;
        if let Some(label) = scene.label() {
            caption(&mut image, &label);
        }
        on_shot(
            i,
            Shot::still(image, frame.spans, start.elapsed().as_secs_f64() * 1e3),
        )?;
    }
    Ok(())
}

/// `label` at the top left of `image`, white over a shadow.
fn caption(image: &mut image::RgbaImage, label: &str) {
    use crate::export::font::{text, text_width};
    let size = (image.height() as f32 / 18.0).clamp(12.0, 48.0);
    let x = 10.0 + 0.5 * f64::from(text_width(label, size));
    text(image, label, x + 1.0, 9.0, size, [0, 0, 0]);
    text(image, label, x, 8.0, size, [255, 255, 255]);
}

/// Renders a resolved scene headless as `request` asks: the model (reported through
/// `progress`), then, unless a report switch replaces the picture, the frame: its
/// animation handed to `on_frame` frame by frame in the scene's time order, the still
/// picture, the timed frames, the asset and the scene's own files. `report` takes the
/// lines a report switch prints.
#[allow(
    clippy::too_many_arguments,
    reason = "the run's parts, each its own input"
)]
pub fn render(
    def: &dyn AnyScene,
    ctx: Option<&Arc<Context>>,
    resolved: &Resolved,
    size: Size,
    request: &Request,
    progress: Progress<'_>,
    on_frame: &mut dyn FnMut(usize, Shot) -> Result<()>,
    report: &mut dyn FnMut(&str),
) -> Result<Rendered> {
    let start = Instant::now();
    let model: AnyModel = def.model(resolved, progress)?;
    let model_ms = start.elapsed().as_secs_f64() * 1e3;
    let made = request
        .made
        .then(|| def.made(resolved, &model))
        .transpose()?;
    let mut written = Vec::new();
    let replaces = request
        .outputs
        .iter()
        .any(|(o, _)| o.value_name.is_empty() && def.output_replaces_picture(o));
    let drawn = request.picture
        || request.animation.is_some()
        || request.asset_title.is_some()
        || request.timing_frames > 0
        || request
            .outputs
            .iter()
            .any(|(o, _)| !o.value_name.is_empty());
    let Some(ctx) = ctx.filter(|_| drawn && !replaces) else {
        for (output, path) in &request.outputs {
            let view = OutputView {
                size,
                camera: None,
                frames: request.animation.flatten(),
            };
            written.extend(def.write_output(
                output,
                path.as_deref(),
                None,
                resolved,
                &model,
                None,
                view,
                report,
            )?);
        }
        return Ok(Rendered {
            picture: None,
            asset: None,
            timed_ms: Vec::new(),
            written,
            wall_ms: start.elapsed().as_secs_f64() * 1e3,
            model_ms,
            made,
        });
    };
    let camera = def.camera(resolved, &model)?;
    let mut scene = def.frame(ctx, resolved, &model, false)?;
    let mut runner = FrameRunner::new(ctx, size)?;
    let still = def.still_time(resolved);
    let views = match request.animation {
        Some(frames) => def.animation(resolved, &model, &camera, frames)?,
        None => Vec::new(),
    };
    if request.animation.is_some() && views.is_empty() {
        return Err(crate::Error::invalid(
            "--gif",
            format!(
                "{} has no animation with these parameters (`--help` says under Outputs what it animates)",
                def.name()
            ),
        ));
    }
    // A scene's clock only runs forward: the still first unless the animation starts
    // before it (a growth's animation ends where its still picture is taken).
    let still_first = views.first().is_none_or(|(_, t)| at(*t) >= at(still));
    let mut picture = None;
    let mut take_still = |runner: &mut FrameRunner, scene: &mut Box<dyn Scene>| -> Result<()> {
        if request.picture || views.is_empty() {
            let begun = Instant::now();
            let before = scene.advance_to(ctx, still, progress)?;
            let (image, frame) = runner.render(scene.as_mut(), &camera, still)?;
            picture = Some(Shot::still(
                image,
                with_time_before(frame.spans, before),
                begun.elapsed().as_secs_f64() * 1e3,
            ));
        }
        Ok(())
    };
    if still_first {
        take_still(&mut runner, &mut scene)?;
    }
    if !views.is_empty() {
        let total = views.len() as u32;
        shots(&mut runner, scene.as_mut(), &views, &mut |i, shot| {
            progress("animation frames", i as u32 + 1, total);
            on_frame(i, shot)
        })?;
    }
    if !still_first {
        take_still(&mut runner, &mut scene)?;
    }
    let timed_ms = runner
        .repeat(scene.as_mut(), &camera, request.timing_frames, &|_| still)?
        .iter()
        .map(super::Frame::gpu_ms)
        .collect();
    let asset = match &request.asset_title {
        Some(title) => match scene.exportable() {
            Some(e) => e.asset(ctx, title)?,
            None => None,
        },
        None => None,
    };
    // The picture's target is not needed by the scene's own files, which may draw
    // frames of their own (a desert forming): free it first.
    drop(runner);
    for (output, path) in &request.outputs {
        let view = OutputView {
            size,
            camera: Some(&camera),
            frames: request.animation.flatten().or(request.forming_frames),
        };
        written.extend(def.write_output(
            output,
            path.as_deref(),
            Some(ctx),
            resolved,
            &model,
            Some(scene.as_ref()),
            view,
            report,
        )?);
    }
    Ok(Rendered {
        picture,
        asset,
        timed_ms,
        written,
        wall_ms: start.elapsed().as_secs_f64() * 1e3,
        model_ms,
        made,
    })
}

/// The still picture of `params` of the scene `def` at `size`, as `sediment NAME -o`
/// draws it.
pub fn picture<D: super::SceneDef>(
    ctx: &Arc<Context>,
    def: &D,
    params: D::Params,
    size: Size,
) -> Result<Shot> {
    let request = Request {
        picture: true,
        ..Request::default()
    };
    let rendered = render(
        def,
        Some(ctx),
        &Resolved::of(params),
        size,
        &request,
        &|_, _, _| {},
        &mut |_, _| Ok(()),
        &mut |_| {},
    )?;
    rendered
        .picture
        .ok_or_else(|| crate::Error::internal("picture", "no picture drawn"))
}

/// A time's place on the clock (`Tick` only comes from the viewer).
fn at(time: Time) -> u32 {
    match time {
        Time::At(n) => n,
        Time::Tick => 0,
    }
}

/// `spans` with the work done before the frame (`Scene::advance_to`, named spans with
/// their milliseconds) added to spans of the same name.
fn with_time_before(mut spans: Vec<Span>, before: Vec<Span>) -> Vec<Span> {
    for b in before {
        match spans.iter_mut().find(|s| s.name == b.name) {
            Some(s) => s.milliseconds += b.milliseconds,
            None => spans.insert(0, b),
        }
    }
    spans
}

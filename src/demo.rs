//! The demo gallery: every registered scene's gallery pictures, each drawn by the one
//! headless driver.

use std::path::Path;
use std::sync::Arc;

use crate::Size;
use crate::error::{Error, Result};
use crate::frame::headless::{self, Request};
use crate::frame::{AnyScene, GalleryShot, Shot};
use crate::gpu::Context;

/// Every picture the gallery shows, scene by scene in the registry's order.
pub fn gallery() -> Vec<(&'static dyn AnyScene, GalleryShot)> {
    crate::scene::registry()
        .into_iter()
        .flat_map(|scene| scene.gallery().into_iter().map(move |shot| (scene, shot)))
        .collect()
}

/// Draws `shot` of `scene` at `size` with `seed`: its picture (returned), its
/// animation's frames handed to `on_frame` as they are made, and its files written
/// into `folder` as `NAME-SUFFIX` (their status lines returned beside the picture).
pub fn render(
    ctx: &Arc<Context>,
    scene: &dyn AnyScene,
    shot: &GalleryShot,
    size: Size,
    seed: u64,
    folder: &Path,
    on_frame: &mut dyn FnMut(usize, Shot) -> Result<()>,
) -> Result<(Shot, Vec<String>)> {
    let given: Vec<(&'static str, String)> = shot
        .set
        .iter()
        .map(|&(key, value)| (key, value.to_owned()))
        .collect();
    let resolved = scene.resolve(Some(shot.preset), seed, None, &given)?;
    let outputs = shot
        .files
        .iter()
        .map(|&(flag, suffix)| {
            let output = scene
                .outputs()
                .iter()
                .find(|o| o.flag == flag)
                .copied()
                .ok_or_else(|| Error::internal("gallery", format!("no output --{flag}")))?;
            Ok((output, Some(folder.join(format!("{}-{suffix}", shot.name)))))
        })
        .collect::<Result<Vec<_>>>()?;
    let request = Request {
        picture: true,
        animation: shot.animated.then_some(None),
        outputs,
        ..Request::default()
    };
    let rendered = headless::render(
        scene,
        Some(ctx),
        &resolved,
        size,
        &request,
        &|_, _, _| {},
        on_frame,
        &mut |_| {},
    )?;
    let picture = rendered
        .picture
        .ok_or_else(|| Error::internal("gallery", "no picture drawn"))?;
    Ok((
        Shot {
            wall_ms: rendered.wall_ms,
            ..picture
        },
        rendered.written,
    ))
}

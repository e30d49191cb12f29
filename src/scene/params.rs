//! Each scene's parameters, declared once: one struct per scene whose fields are all
//! optional, deriving clap's `Args` (the command line's overrides) and serde (the scene
//! file, TOML), with one `sync` that lists the fields once for both directions —
//! applying given values onto a scene, and capturing a scene's values (for
//! `--print-scene`). `resolve` applies preset, scene file and options in that order.

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::camera::CameraOptions;
use crate::error::{Error, Result};

/// Which way `SceneParams::sync` copies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Way {
    /// Every given value onto the scene.
    Apply,
    /// Every value of the scene into the parameters.
    Capture,
}

impl Way {
    /// One field: `Some(v)` onto `slot` (apply), or `slot` into the option (capture).
    pub fn field<T: Clone>(self, given: &mut Option<T>, slot: &mut T) {
        match self {
            Way::Apply => {
                if let Some(v) = given {
                    *slot = v.clone();
                }
            }
            Way::Capture => *given = Some(slot.clone()),
        }
    }
}

/// A scene's parameters as the command line and scene files give them.
pub trait SceneParams: Default + Clone + Serialize + DeserializeOwned {
    /// What they describe.
    type Scene: Clone;
    /// The preset named, if any.
    fn preset(&self) -> Option<&str>;
    /// Names the preset (`--preset`, a scene file's `preset`), or none.
    fn set_preset(&mut self, name: Option<String>);
    /// The scene a preset starts from (`None`: the defaults).
    fn base(preset: Option<&str>) -> Result<Self::Scene>;
    /// `--seed` (a scene file's `seed` overrides it).
    fn set_seed(scene: &mut Self::Scene, seed: u64);
    /// Applies or captures every value but the preset and the camera: the one list of
    /// the scene's parameters.
    fn sync(&mut self, scene: &mut Self::Scene, way: Way) -> Result<()>;
    /// Checks the scene's ranges.
    fn validate(scene: &Self::Scene) -> Result<()>;
    /// The camera's `eye`/`target`.
    fn camera(&self) -> &CameraOptions;
    /// The camera's `eye`/`target`, to set (capturing a resolved scene).
    fn camera_mut(&mut self) -> &mut CameraOptions;
}

/// The `SceneParams` methods that read a `Params` struct's `preset` and `camera`
/// fields, the same in every scene.
macro_rules! preset_and_camera_fields {
    () => {
        fn preset(&self) -> Option<&str> {
            self.preset.as_deref()
        }

        fn set_preset(&mut self, name: Option<String>) {
            self.preset = name;
        }

        fn camera(&self) -> &CameraOptions {
            &self.camera
        }

        fn camera_mut(&mut self) -> &mut CameraOptions {
            &mut self.camera
        }
    };
}
pub(crate) use preset_and_camera_fields;

/// The effective scene: preset, then scene file, then options.
#[derive(Clone, Debug)]
pub struct Resolved<S> {
    /// The scene with preset, scene file and options applied, and validated.
    pub scene: S,
    /// Where the camera goes, over the scene's default camera.
    pub camera: CameraOptions,
    /// The preset it started from (the options' over the scene file's); none: defaults.
    pub preset: Option<String>,
}

/// `--scene FILE.toml` and `--print-scene`, for every subcommand that renders a scene.
#[derive(clap::Args, Clone, Debug, Default)]
pub struct SceneFileArgs {
    /// A TOML scene file: the same parameters as this command's options (the option
    /// names with `_` for `-`, e.g. `ripple_size = 128`), applied over its `preset`;
    /// options given here override it. `--print-scene` writes one. Unknown keys are
    /// refused with their line (default: none, the preset alone).
    #[arg(long, value_name = "FILE.toml")]
    pub scene: Option<PathBuf>,
    /// Write the effective scene (preset, scene file and options together) as TOML to
    /// stdout and exit without rendering: `--scene` reads it back to the same scene.
    #[arg(long)]
    pub print_scene: bool,
}

/// The scene that `given` (the options), the scene file and `seed` describe.
pub fn resolve<P: SceneParams>(
    given: &P,
    file: Option<&Path>,
    seed: u64,
) -> Result<Resolved<P::Scene>> {
    let from_file = file
        .map(|path| read::<P>(path).map(|p| (path, p)))
        .transpose()?;
    let preset = given
        .preset()
        .or_else(|| from_file.as_ref().and_then(|(_, f)| f.preset()))
        .map(str::to_owned);
    let mut scene = P::base(preset.as_deref())?;
    P::set_seed(&mut scene, seed);
    let mut camera = CameraOptions::default();
    if let Some((path, f)) = &from_file {
        let in_file = |e: Error| match e {
            Error::InvalidArgument { argument, message } => Error::InvalidArgument {
                argument: format!("{argument} in {}", path.display()),
                message,
            },
            other => other,
        };
        f.clone().sync(&mut scene, Way::Apply).map_err(in_file)?;
        P::validate(&scene).map_err(in_file)?;
        camera = f.camera().clone();
    }
    given.clone().sync(&mut scene, Way::Apply)?;
    P::validate(&scene)?;
    let camera = camera.merged(given.camera());
    if let (Some(eye), Some(target)) = (camera.eye, camera.target) {
        // The rest is checked against the scene's default camera, once it exists.
        if eye == target {
            return Err(Error::invalid(
                "--eye/--target",
                "the camera must not look at its own position",
            ));
        }
    }
    Ok(Resolved {
        scene,
        camera,
        preset,
    })
}

/// The parameters that reproduce `resolved`: its preset and every value.
pub fn capture<P: SceneParams>(resolved: &Resolved<P::Scene>) -> Result<P> {
    let mut params = P::default();
    params.set_preset(resolved.preset.clone());
    params.sync(&mut resolved.scene.clone(), Way::Capture)?;
    *params.camera_mut() = resolved.camera.clone();
    Ok(params)
}

/// `resolved` as a scene file.
pub fn to_toml<P: SceneParams>(resolved: &Resolved<P::Scene>) -> Result<String> {
    toml::to_string(&capture::<P>(resolved)?)
        .map_err(|e| Error::internal("--print-scene", format!("the scene as TOML: {e}")))
}

/// Reads a scene file; a syntax error, a bad value or an unknown key is named with
/// the file and line.
pub fn read<P: SceneParams>(path: &Path) -> Result<P> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse(&text).map_err(|(line, message)| {
        Error::invalid(
            "--scene",
            match line {
                Some(line) => format!("{}:{line}: {message}", path.display()),
                None => format!("{}: {message}", path.display()),
            },
        )
    })
}

/// Parses a scene file's text; an error carries its (1-based) line where known, and
/// quotes that line.
pub fn parse<P: SceneParams>(text: &str) -> Result<P, (Option<usize>, String)> {
    toml::from_str(text).map_err(|e| {
        let line = e
            .span()
            .map(|span| 1 + text[..span.start.min(text.len())].matches('\n').count());
        let quoted = line
            .and_then(|l| text.lines().nth(l - 1))
            .map(|l| format!(" (`{}`)", crate::error::echo(l.trim())))
            .unwrap_or_default();
        // The message may quote the value: long input is cut there too.
        let message = e.message().trim();
        let message = match message.char_indices().nth(400) {
            Some((cut, _)) => format!("{}...", &message[..cut]),
            None => message.to_owned(),
        };
        (line, format!("{message}{quoted}"))
    })
}

/// `on` or `off` (`--lod`, `--cull`).
pub fn on_off(v: &str) -> Result<bool> {
    match v.trim().to_ascii_lowercase().as_str() {
        "on" | "true" => Ok(true),
        "off" | "false" => Ok(false),
        other => Err(Error::invalid(
            "on|off",
            format!("\"{other}\" is not on or off"),
        )),
    }
}

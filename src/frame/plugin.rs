//! A scene as a plugin: one [`SceneDef`] says everything the instruments need — its
//! parameters (declared once, `crate::params`), presets, the CPU model they make, the
//! frame that draws it, its default camera, its animation, the files it writes besides
//! pictures, its gallery pictures and its bench series. The registry
//! (`scene::registry`) lists each scene once; the command line, the viewer, the demo,
//! the bench and the tests walk it through the type-erased [`AnyScene`].

use std::any::Any;
use std::path::Path;
use std::sync::Arc;

use super::{BenchScene, Scene, Time};
use crate::Size;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::gpu::Context;
use crate::input_files::InputKind;
use crate::params::{Param, ParamSet, Point3, SceneFile};

/// Reports the progress of a long step: (what, done, total), from any thread.
pub type Progress<'a> = &'a (dyn Fn(&str, u32, u32) + Sync);

/// A file a scene writes besides the generic picture, animation and mesh (`--csv`,
/// `--heightmap`), or a report it prints instead of rendering (`--table`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OutputDef {
    /// The option's name without dashes ("heightmap").
    pub flag: &'static str,
    /// Its value's name in `--help` ("FILE.png|FILE.exr"); empty for a switch that
    /// prints a report on stdout and renders nothing.
    pub value_name: &'static str,
    /// The extensions the file may have ("png", "exr"); empty for a switch.
    pub extensions: &'static [&'static str],
    /// What it writes.
    pub help: &'static str,
    /// The files it writes beside its own path, as names in its folder with `{stem}`
    /// and `{ext}` its own (a heightmap's "{stem}.json", "{stem}-ripples.{ext}"):
    /// checked with every other output before the work.
    pub beside: &'static [&'static str],
}

impl OutputDef {
    /// The files it writes beside `path` ([`OutputDef::beside`]).
    pub fn beside(&self, path: &std::path::Path) -> Vec<std::path::PathBuf> {
        let part = |p: Option<&std::ffi::OsStr>| p.map(|s| s.to_string_lossy().into_owned());
        let (stem, ext) = (part(path.file_stem()), part(path.extension()));
        self.beside
            .iter()
            .map(|name| {
                let name = name
                    .replace("{stem}", stem.as_deref().unwrap_or(""))
                    .replace("{ext}", ext.as_deref().unwrap_or(""));
                path.with_file_name(name)
            })
            .collect()
    }
}

/// A picture of the demo gallery: a preset with some parameters changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GalleryShot {
    /// File stem of the PNG ("dunes-fig17").
    pub name: &'static str,
    /// The preset it starts from.
    pub preset: &'static str,
    /// Parameters set over the preset, as command-line words (key, value).
    pub set: &'static [(&'static str, &'static str)],
    /// Also its animation (`SceneDef::animation`) as `NAME.gif`.
    pub animated: bool,
    /// Also the scene's own files: (output flag, file name suffix), written as
    /// `NAME-SUFFIX` (`("section", "section.png")`).
    pub files: &'static [(&'static str, &'static str)],
    /// One line on what the picture shows.
    pub description: &'static str,
}

/// Everything the instruments need of one scene. Implement it, add the scene to the
/// registry (`scene::registry`), and the command line, the viewer, the demo gallery,
/// the bench and the tests that mean "every scene" take it up.
pub trait SceneDef: Send + Sync + 'static {
    /// Its parameters, one `params!` row each.
    type Params: ParamSet;
    /// What the CPU makes of the parameters before any GPU work (a simulated desert,
    /// a generated cave, a growth plan).
    type Model: Send + Sync + 'static;

    /// The scene's name: its subcommand and its bench rows ("dunes").
    fn name(&self) -> &'static str;
    /// What it shows, for `--help` (a paragraph).
    fn about(&self) -> &'static str;
    /// Presets (name, what it shows); the first paper figure first.
    fn presets(&self) -> &'static [(&'static str, &'static str)];
    /// The parameters of a preset; an unknown name is refused, listing the presets.
    fn preset(&self, name: &str) -> Result<Self::Params>;
    /// Puts the global `--seed` into the parameters (a scene file's own seed is applied
    /// after it and wins).
    fn set_seed(&self, params: &mut Self::Params, seed: u64);
    /// The files the parameters read (a climate record, a base), which no output may
    /// overwrite.
    fn inputs(&self, _params: &Self::Params) -> Vec<std::path::PathBuf> {
        Vec::new()
    }
    /// The CPU model: simulation, generation, planning; `progress` names the steps.
    fn model(&self, params: &Self::Params, progress: Progress<'_>) -> Result<Self::Model>;
    /// What the model made, for `--json`'s `made`: counts and sizes, each key naming
    /// its unit (`_m`, `_ms`, `_years`). The book's "Reports" chapter documents each
    /// scene's keys (default: an empty object).
    fn made(&self, _params: &Self::Params, _model: &Self::Model) -> Result<serde_json::Value> {
        Ok(serde_json::json!({}))
    }
    /// The scene's own view of the model (the parameters' `eye`/`target` go over it).
    fn camera(&self, params: &Self::Params, model: &Self::Model) -> Camera;
    /// The frame that draws the model. `realtime`: for the viewer and the bench
    /// (frames drawn one after another) rather than for pictures.
    fn frame(
        &self,
        ctx: &Arc<Context>,
        params: &Self::Params,
        model: &Arc<Self::Model>,
        realtime: bool,
    ) -> Result<Box<dyn Scene>>;
    /// When a still picture is taken on the scene's clock (default: the end of it).
    fn still_time(&self, _params: &Self::Params) -> Time {
        Time::At(u32::MAX)
    }
    /// The frames of its animation (`--gif`): a camera and a time each. `frames` is
    /// what the user asked for (`None`: the scene's own count). Default: none.
    fn animation(
        &self,
        _params: &Self::Params,
        _model: &Self::Model,
        _camera: &Camera,
        _frames: Option<u32>,
    ) -> Vec<(Camera, Time)> {
        Vec::new()
    }
    /// Its files besides the picture, the animation and the mesh.
    fn outputs(&self) -> &'static [OutputDef] {
        &[]
    }
    /// Refuses an output the parameters cannot give, before any work (default: none
    /// refused).
    fn check_output(&self, _params: &Self::Params, _output: &OutputDef) -> Result<()> {
        Ok(())
    }
    /// Writes `output` (one of [`SceneDef::outputs`]) to `path` (`None` for a switch:
    /// its report goes to `report`); returns the status lines ("wrote FILE ...").
    fn write_output(
        &self,
        output: &OutputDef,
        _path: Option<&Path>,
        _job: &Job<'_, Self::Params, Self::Model>,
        _report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        Err(Error::internal(
            "scene output",
            format!("{} writes no --{}", self.name(), output.flag),
        ))
    }
    /// Whether a switch output (`--table`) is the whole run: the scene is then not
    /// rendered (default: yes).
    fn output_replaces_picture(&self, _output: &OutputDef) -> bool {
        true
    }
    /// The viewer's keys for this scene, one line each (`Scene::key` handles them).
    fn controls(&self) -> &'static [&'static str] {
        &[]
    }
    /// Its pictures in the demo gallery (default: none).
    fn gallery(&self) -> Vec<GalleryShot> {
        Vec::new()
    }
    /// How the bench times it (`None`: it does not).
    fn bench(&self) -> Option<Box<dyn BenchScene>> {
        None
    }
}

/// What a scene's output sees: the parameters, the model, the rendered frame (when the
/// run rendered one) and the device.
pub struct Job<'a, P, M> {
    /// The device (None for a run that renders nothing).
    pub ctx: Option<&'a Arc<Context>>,
    /// The resolved parameters.
    pub params: &'a P,
    /// The CPU model.
    pub model: &'a Arc<M>,
    /// The frame after the picture was drawn.
    pub scene: Option<&'a dyn Scene>,
    /// The picture's size (`--size`).
    pub size: Size,
    /// The camera the picture was drawn from.
    pub camera: Option<&'a Camera>,
    /// The animation's frame count asked for (`--gif-frames`).
    pub frames: Option<u32>,
    /// The preset the parameters started from.
    pub preset: Option<&'a str>,
}

/// Parameters resolved from a preset, a scene file and the command line, of any
/// scene (a [`SceneDef`]'s `Params` behind `Any`).
pub struct Resolved {
    /// The scene's `Params`.
    pub params: Box<dyn Any + Send + Sync>,
    /// The preset they started from.
    pub preset: Option<String>,
}

impl Resolved {
    /// Parameters given as they are (a library user's, a test's), with no preset.
    pub fn of<P: ParamSet>(params: P) -> Self {
        Self {
            params: Box::new(params),
            preset: None,
        }
    }
}

/// A model of any scene, made from resolved parameters.
pub type AnyModel = Arc<dyn Any + Send + Sync>;

/// A [`SceneDef`] with its types erased: what the registry holds.
pub trait AnyScene: Send + Sync {
    /// [`SceneDef::name`].
    fn name(&self) -> &'static str;
    /// [`SceneDef::about`].
    fn about(&self) -> &'static str;
    /// [`SceneDef::presets`].
    fn presets(&self) -> &'static [(&'static str, &'static str)];
    /// Its parameters' rows.
    fn params(&self) -> &'static [Param];
    /// The text `--help` gives as a parameter's default (from `Params::default`).
    fn default_text(&self, key: &str) -> String;
    /// [`SceneDef::outputs`].
    fn outputs(&self) -> &'static [OutputDef];
    /// [`SceneDef::output_replaces_picture`].
    fn output_replaces_picture(&self, output: &OutputDef) -> bool;
    /// [`SceneDef::check_output`].
    fn check_output(&self, resolved: &Resolved, output: &OutputDef) -> Result<()>;
    /// [`SceneDef::gallery`].
    fn gallery(&self) -> Vec<GalleryShot>;
    /// [`SceneDef::controls`].
    fn controls(&self) -> &'static [&'static str];
    /// [`SceneDef::bench`].
    fn bench(&self) -> Option<Box<dyn BenchScene>>;
    /// Resolves the preset, the seed, a scene file and the command line's values (key,
    /// word), validated; errors name the key, or the file and line.
    fn resolve(
        &self,
        preset: Option<&str>,
        seed: u64,
        file: Option<&Path>,
        given: &[(&'static str, String)],
    ) -> Result<Resolved> {
        let text = file
            .map(|path| {
                crate::input_files::read_text(path, "--scene", InputKind::SceneFile)
                    .map(|t| (path.display().to_string(), t))
            })
            .transpose()?;
        self.resolve_text(
            preset,
            seed,
            text.as_ref().map(|(n, t)| (n.as_str(), t.as_str())),
            given,
        )
    }
    /// [`AnyScene::resolve`] with the scene file given as (name, text).
    fn resolve_text(
        &self,
        preset: Option<&str>,
        seed: u64,
        file: Option<(&str, &str)>,
        given: &[(&'static str, String)],
    ) -> Result<Resolved>;
    /// The resolved parameters as a scene file.
    fn to_toml(&self, resolved: &Resolved) -> Result<String>;
    /// [`SceneDef::inputs`].
    fn inputs(&self, resolved: &Resolved) -> Vec<std::path::PathBuf>;
    /// [`SceneDef::model`].
    fn model(&self, resolved: &Resolved, progress: Progress<'_>) -> Result<AnyModel>;
    /// [`SceneDef::made`].
    fn made(&self, resolved: &Resolved, model: &AnyModel) -> Result<serde_json::Value>;
    /// The camera: the scene's own view with the parameters' `eye`/`target` over it.
    fn camera(&self, resolved: &Resolved, model: &AnyModel) -> Result<Camera>;
    /// [`SceneDef::frame`].
    fn frame(
        &self,
        ctx: &Arc<Context>,
        resolved: &Resolved,
        model: &AnyModel,
        realtime: bool,
    ) -> Result<Box<dyn Scene>>;
    /// [`SceneDef::still_time`].
    fn still_time(&self, resolved: &Resolved) -> Time;
    /// [`SceneDef::animation`].
    fn animation(
        &self,
        resolved: &Resolved,
        model: &AnyModel,
        camera: &Camera,
        frames: Option<u32>,
    ) -> Result<Vec<(Camera, Time)>>;
    /// [`SceneDef::write_output`].
    #[allow(
        clippy::too_many_arguments,
        reason = "the job's parts, unerased one by one"
    )]
    fn write_output(
        &self,
        output: &OutputDef,
        path: Option<&Path>,
        ctx: Option<&Arc<Context>>,
        resolved: &Resolved,
        model: &AnyModel,
        scene: Option<&dyn Scene>,
        view: OutputView<'_>,
        report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>>;
}

/// How the run that writes a scene's output drew it.
#[derive(Clone, Copy, Debug)]
pub struct OutputView<'a> {
    /// The picture's size.
    pub size: Size,
    /// The camera, when the run drew.
    pub camera: Option<&'a Camera>,
    /// The animation's frame count asked for.
    pub frames: Option<u32>,
}

fn params_of<'a, D: SceneDef>(def: &D, resolved: &'a Resolved) -> Result<&'a D::Params> {
    resolved
        .params
        .downcast_ref::<D::Params>()
        .ok_or_else(|| Error::internal(def.name(), "parameters of another scene"))
}

fn model_of<D: SceneDef>(def: &D, model: &AnyModel) -> Result<Arc<D::Model>> {
    model
        .clone()
        .downcast::<D::Model>()
        .map_err(|_| Error::internal(def.name(), "a model of another scene"))
}

/// A point parameter (`eye`, `target`) of any parameter set.
fn point<P: ParamSet>(params: &P, key: &str) -> Option<[f32; 3]> {
    let value = params.get(key)?;
    <Point3 as crate::params::ParamValue>::from_toml(&value)
        .ok()
        .map(|p| p.0)
}

/// `camera` with the parameters' `eye` and `target` over it, checked.
pub fn camera_over<P: ParamSet>(params: &P, mut camera: Camera) -> Result<Camera> {
    let (eye, target) = (point(params, "eye"), point(params, "target"));
    if let Some(eye) = eye {
        camera.eye = eye.into();
    }
    if let Some(target) = target {
        camera.target = target.into();
    }
    let distance = camera.eye.distance(camera.target);
    if distance.is_finite() && distance >= 1e-6 {
        return Ok(camera);
    }
    Err(match (eye, target) {
        (Some(_), _) => Error::invalid(
            "eye",
            "the camera must not look at its own position (give another target)",
        ),
        (None, Some(_)) => Error::invalid(
            "target",
            "the camera must not look at its own position (give another eye)",
        ),
        // The scene framed itself: its size, not a camera the user gave, is at fault.
        (None, None) => Error::invalid(
            "scene",
            format!(
                "its own camera cannot frame it at these settings (its eye {} units from \
                 what it looks at): the scene's size options are beyond what can be drawn \
                 (see their ranges in --help)",
                crate::error::short_number(f64::from(distance))
            ),
        ),
    })
}

impl<D: SceneDef> AnyScene for D {
    fn name(&self) -> &'static str {
        SceneDef::name(self)
    }

    fn about(&self) -> &'static str {
        SceneDef::about(self)
    }

    fn presets(&self) -> &'static [(&'static str, &'static str)] {
        SceneDef::presets(self)
    }

    fn params(&self) -> &'static [Param] {
        D::Params::params()
    }

    fn default_text(&self, key: &str) -> String {
        crate::params::default_text::<D::Params>(key)
    }

    fn outputs(&self) -> &'static [OutputDef] {
        SceneDef::outputs(self)
    }

    fn output_replaces_picture(&self, output: &OutputDef) -> bool {
        SceneDef::output_replaces_picture(self, output)
    }

    fn check_output(&self, resolved: &Resolved, output: &OutputDef) -> Result<()> {
        SceneDef::check_output(self, params_of(self, resolved)?, output)
    }

    fn gallery(&self) -> Vec<GalleryShot> {
        SceneDef::gallery(self)
    }

    fn controls(&self) -> &'static [&'static str] {
        SceneDef::controls(self)
    }

    fn bench(&self) -> Option<Box<dyn BenchScene>> {
        SceneDef::bench(self)
    }

    fn resolve_text(
        &self,
        preset: Option<&str>,
        seed: u64,
        file: Option<(&str, &str)>,
        given: &[(&'static str, String)],
    ) -> Result<Resolved> {
        let scene_file = file
            .map(|(name, text)| SceneFile::from_text::<D::Params>(name, text))
            .transpose()?;
        // The command line's preset over the file's.
        let name = preset
            .map(str::to_owned)
            .or_else(|| scene_file.as_ref().and_then(|f| f.preset.clone()));
        let mut base = match &name {
            Some(n) => self.preset(n)?,
            None => D::Params::default(),
        };
        self.set_seed(&mut base, seed);
        let named = file.map(|(name, _)| name).zip(scene_file.as_ref());
        let params = crate::params::resolve(base, named, given)?;
        Ok(Resolved {
            params: Box::new(params),
            preset: name,
        })
    }

    fn to_toml(&self, resolved: &Resolved) -> Result<String> {
        crate::params::to_toml(params_of(self, resolved)?, resolved.preset.as_deref())
    }

    fn inputs(&self, resolved: &Resolved) -> Vec<std::path::PathBuf> {
        params_of(self, resolved).map_or_else(|_| Vec::new(), |p| SceneDef::inputs(self, p))
    }

    fn model(&self, resolved: &Resolved, progress: Progress<'_>) -> Result<AnyModel> {
        Ok(Arc::new(SceneDef::model(
            self,
            params_of(self, resolved)?,
            progress,
        )?))
    }

    fn made(&self, resolved: &Resolved, model: &AnyModel) -> Result<serde_json::Value> {
        SceneDef::made(
            self,
            params_of(self, resolved)?,
            model_of(self, model)?.as_ref(),
        )
    }

    fn camera(&self, resolved: &Resolved, model: &AnyModel) -> Result<Camera> {
        let params = params_of(self, resolved)?;
        let model = model_of(self, model)?;
        camera_over(params, SceneDef::camera(self, params, &model))
    }

    fn frame(
        &self,
        ctx: &Arc<Context>,
        resolved: &Resolved,
        model: &AnyModel,
        realtime: bool,
    ) -> Result<Box<dyn Scene>> {
        SceneDef::frame(
            self,
            ctx,
            params_of(self, resolved)?,
            &model_of(self, model)?,
            realtime,
        )
    }

    fn still_time(&self, resolved: &Resolved) -> Time {
        params_of(self, resolved).map_or(Time::At(u32::MAX), |p| SceneDef::still_time(self, p))
    }

    fn animation(
        &self,
        resolved: &Resolved,
        model: &AnyModel,
        camera: &Camera,
        frames: Option<u32>,
    ) -> Result<Vec<(Camera, Time)>> {
        Ok(SceneDef::animation(
            self,
            params_of(self, resolved)?,
            model_of(self, model)?.as_ref(),
            camera,
            frames,
        ))
    }

    fn write_output(
        &self,
        output: &OutputDef,
        path: Option<&Path>,
        ctx: Option<&Arc<Context>>,
        resolved: &Resolved,
        model: &AnyModel,
        scene: Option<&dyn Scene>,
        view: OutputView<'_>,
        report: &mut dyn FnMut(&str),
    ) -> Result<Vec<String>> {
        let model = model_of(self, model)?;
        let job = Job {
            ctx,
            params: params_of(self, resolved)?,
            model: &model,
            scene,
            size: view.size,
            camera: view.camera,
            frames: view.frames,
            preset: resolved.preset.as_deref(),
        };
        SceneDef::write_output(self, output, path, &job, report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Jitter;
    use glam::Vec3;

    fn camera(eye: Vec3, target: Vec3) -> Camera {
        Camera {
            eye,
            target,
            up: Vec3::Y,
            fov_y_degrees: 60.0,
            near: 0.05,
            far: 10.0,
            jitter: Jitter::NONE,
        }
    }

    /// The option or setting an error blames.
    fn blamed(e: Error) -> String {
        match e {
            Error::InvalidArgument { argument, .. } => argument,
            other => panic!("not an invalid value: {other}"),
        }
    }

    #[test]
    fn a_degenerate_camera_is_blamed_on_what_set_it() {
        let mut params = crate::scene::layers::LayersScene::default();
        // The scene's own camera (no eye, no target given): its size is at fault.
        for bad in [camera(Vec3::ONE, Vec3::ONE), camera(Vec3::NAN, Vec3::ZERO)] {
            let e = camera_over(&params, bad).expect_err("degenerate");
            assert!(
                e.to_string().contains("its own camera cannot frame it"),
                "{e}"
            );
            assert_eq!(blamed(e), "scene");
        }
        // An eye the user gave onto the scene's target: the eye is named.
        params.eye = Some(crate::params::Point3([1.0, 1.0, 1.0]));
        let e = camera_over(&params, camera(Vec3::ZERO, Vec3::ONE)).expect_err("eye on target");
        assert_eq!(blamed(e), "eye");
        params.eye = None;
        params.target = Some(crate::params::Point3([0.0, 0.0, 0.0]));
        let e = camera_over(&params, camera(Vec3::ZERO, Vec3::ONE)).expect_err("target on eye");
        assert_eq!(blamed(e), "target");
        assert!(camera_over(&params, camera(Vec3::ONE, Vec3::ONE)).is_ok());
    }
}

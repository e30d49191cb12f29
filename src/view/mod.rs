//! `sediment view`: the interactive viewer. A winit window with a Vulkan swapchain,
//! rendering continuously any `frame::Scene` through the same frame runner as the
//! headless commands: each frame draws into the runner's offscreen target exactly as
//! `sediment grow` does, and the target is blitted into the swapchain image with a text
//! panel on top. The scene's keys steer it (a growth's parameters while it grows, the
//! desert's sun, the cave's wall); the camera orbits or flies (`camera_control`). `--frames N` renders N frames and exits, and `--script`
//! feeds synthesised key presses through the same handler as real ones: that is how
//! the tests drive it under Xvfb.

mod camera_control;
mod overlay;

use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key as WinitKey, NamedKey};
use winit::platform::x11::EventLoopBuilderExtX11;
use winit::window::{Window, WindowId};

use crate::Size;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::export::asset::Asset;
use crate::frame::{FrameRunner, Scene, Time};
use crate::gpu::Span;
use crate::gpu::{
    Buffer, BufferDesc, Context, ContextOptions, FramesInFlight, Presented, Surface, Swapchain, vk,
};
use crate::input::{Key, Scripted, ScriptedKey};
use camera_control::CameraControl;

/// Frame slots: the next frame acquires its image and lays out its panel while the
/// GPU draws the last one.
const FRAMES_IN_FLIGHT: usize = 2;

/// Builds the scene to show once the window's device exists.
pub type SceneBuilder = Box<dyn FnOnce(&Arc<Context>) -> Result<Box<dyn Scene>>>;

/// How to show it.
pub struct ViewOptions {
    /// The device, validation and samples of the window's context.
    pub context: ContextOptions,
    /// The window's initial inner size.
    pub size: Size,
    /// Wait for the display's refresh (FIFO); off measures uncapped frame rates.
    pub vsync: bool,
    /// Render this many frames, then exit (non-interactive).
    pub frames: Option<u32>,
    /// Where the screenshot key (F2) writes, and where the last frame goes on exit
    /// with `frames`. Default for the key: sediment-view-FRAME.png.
    pub screenshot: Option<PathBuf>,
    /// Synthesised key presses and resizes.
    pub script: Vec<ScriptedKey>,
    /// Show the text panel (the scene's state and the keys) over the frame.
    pub overlay: bool,
    /// Read the scene's asset at exit under this title (`--mesh`); none: not read.
    pub asset_title: Option<String>,
}

/// What a viewing session did.
pub struct ViewReport {
    /// Frames rendered.
    pub frames: u32,
    /// Per frame: wall-clock milliseconds from the start of one frame to the next.
    pub frame_ms: Vec<f64>,
    /// Per frame: the GPU time of each named pass (the scene's spans).
    pub gpu_spans: Vec<Vec<Span>>,
    /// Frames up to the last one whose scene changed with its clock (a growth's
    /// passes): the frames "while growing".
    pub clock_frames: usize,
    /// Final size of the window's image.
    pub size: Size,
    /// The scene's asset at the end, for `--mesh` (scenes with something to export,
    /// `Scene::asset`), named `ViewOptions::title`.
    pub asset: Option<Asset>,
    /// What the validation layer reported as errors (empty without validation).
    pub validation_errors: Vec<String>,
}

/// The controls every scene shares, for the overlay and `--help`.
pub const CONTROLS: &[&str] = &[
    "drag orbit (fly: look)  wheel zoom  tab orbit/fly  wasd move  q/e down/up",
    "v print camera options  f2 screenshot  h hide this  esc quit",
];

/// Opens the window and runs until it is closed (or `frames` are done). `say` gets
/// the lines meant for the user's terminal (camera options, screenshots written).
/// `camera` is where the view starts.
pub fn run(
    options: ViewOptions,
    scene: SceneBuilder,
    camera: &Camera,
    say: &mut dyn FnMut(&str),
) -> Result<ViewReport> {
    let event_loop = EventLoop::builder()
        // Tests run the viewer off the main thread; X11 allows it.
        .with_any_thread(true)
        .build()
        .map_err(|e| Error::NoWindow {
            detail: format!("no X11 display could be opened ({e})"),
        })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        options,
        camera: CameraControl::from_camera(camera),
        scene: Some(scene),
        say,
        state: None,
        error: None,
        report: ViewReport {
            frames: 0,
            frame_ms: Vec::new(),
            gpu_spans: Vec::new(),
            clock_frames: 0,
            size: Size::new(0, 0),
            asset: None,
            validation_errors: Vec::new(),
        },
    };
    event_loop.run_app(&mut app).map_err(|e| Error::NoWindow {
        detail: format!("the window's event loop failed ({e})"),
    })?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    if let Some(state) = app.state.take() {
        state.finish(&mut app.report, app.options.asset_title.as_deref())?;
    }
    Ok(app.report)
}

struct App<'a> {
    options: ViewOptions,
    /// The camera the window opens with.
    camera: CameraControl,
    scene: Option<SceneBuilder>,
    say: &'a mut dyn FnMut(&str),
    // Dropped before the window (inside `State`, fields drop in order).
    state: Option<State>,
    error: Option<Error>,
    report: ViewReport,
}

/// Everything that lives while the window is open. Field order is drop order: the
/// frames in flight (waited for) before what they read, the swapchain before the
/// surface before the window.
struct State {
    frames: FramesInFlight,
    scene: Box<dyn Scene>,
    /// The offscreen target at the window's size (made with the first swapchain).
    runner: Option<FrameRunner>,
    /// The panel's pixels, one buffer per frame slot (a frame in flight reads its own).
    overlay_buffers: Vec<Buffer>,
    swapchain: Option<Swapchain>,
    surface: Surface,
    ctx: Arc<Context>,
    window: Window,
    camera: CameraControl,
    held: HashSet<char>,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    last_frame: Instant,
    frame: u32,
    stale: bool,
    overlay: bool,
    vsync: bool,
    fps: f64,
    last_gpu: Vec<Span>,
    /// A screenshot to write after the next frame.
    pending: Option<PathBuf>,
    /// A frame was submitted and its spans not yet taken in (`settle`).
    unsettled: bool,
    /// Frames settled but not yet in the report: their spans, and whether the scene's
    /// clock still changed them.
    settled: Vec<(Vec<Span>, bool)>,
}

impl ApplicationHandler for App<'_> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.state.is_some() {
            return;
        }
        match self.open(event_loop) {
            Ok(state) => self.state = Some(state),
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let result = self.handle(event_loop, event);
        if let Err(e) = result {
            self.error = Some(e);
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(state) = &self.state {
            state.window.request_redraw();
        }
    }
}

impl App<'_> {
    fn open(&mut self, event_loop: &ActiveEventLoop) -> Result<State> {
        let no_window = |what: &str, e: &dyn std::fmt::Display| Error::NoWindow {
            detail: format!("{what} ({e})"),
        };
        let size = self.options.size;
        let attributes = Window::default_attributes()
            .with_title("sediment view")
            .with_inner_size(PhysicalSize::new(size.width, size.height));
        let window = event_loop
            .create_window(attributes)
            .map_err(|e| no_window("the window could not be created", &e))?;
        let display = event_loop
            .display_handle()
            .map_err(|e| no_window("the display has no handle", &e))?
            .as_raw();
        let mut context = self.options.context.clone();
        context.window = Some(display);
        let ctx = Context::new(&context)?;
        let handle = window
            .window_handle()
            .map_err(|e| no_window("the window has no handle", &e))?
            .as_raw();
        // SAFETY: the window lives in the same `State` and is dropped after the
        // surface (field order).
        let surface = unsafe { Surface::new(&ctx, display, handle)? };
        let build = self
            .scene
            .take()
            .ok_or_else(|| Error::internal("view", "the scene was already shown"))?;
        let scene = build(&ctx)?;
        Ok(State {
            frames: FramesInFlight::new(&ctx, "view frame", FRAMES_IN_FLIGHT)?,
            scene,
            runner: None,
            overlay_buffers: Vec::new(),
            swapchain: None,
            surface,
            ctx,
            window,
            camera: self.camera.clone(),
            held: HashSet::new(),
            dragging: false,
            cursor: None,
            last_frame: Instant::now(),
            frame: 0,
            stale: true,
            overlay: self.options.overlay,
            vsync: self.options.vsync,
            fps: 0.0,
            last_gpu: Vec::new(),
            pending: None,
            unsettled: false,
            settled: Vec::new(),
        })
    }

    fn handle(&mut self, event_loop: &ActiveEventLoop, event: WindowEvent) -> Result<()> {
        let Some(state) = self.state.as_mut() else {
            return Ok(());
        };
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(_) => state.stale = true,
            WindowEvent::KeyboardInput { event, .. } => {
                let key = match &event.logical_key {
                    WinitKey::Named(named) => match named {
                        NamedKey::Space => Some(Key::Space),
                        NamedKey::Tab => Some(Key::Tab),
                        NamedKey::Enter => Some(Key::Enter),
                        NamedKey::Escape => Some(Key::Escape),
                        NamedKey::ArrowLeft => Some(Key::Left),
                        NamedKey::ArrowRight => Some(Key::Right),
                        NamedKey::ArrowUp => Some(Key::Up),
                        NamedKey::ArrowDown => Some(Key::Down),
                        NamedKey::F2 => Some(Key::F(2)),
                        _ => None,
                    },
                    WinitKey::Character(s) => {
                        s.chars().next().map(|c| Key::Char(c.to_ascii_lowercase()))
                    }
                    _ => None,
                };
                let Some(key) = key else { return Ok(()) };
                if let Key::Char(c @ ('w' | 'a' | 's' | 'd' | 'q' | 'e')) = key {
                    if event.state == ElementState::Pressed {
                        state.held.insert(c);
                    } else {
                        state.held.remove(&c);
                    }
                } else if event.state == ElementState::Pressed
                    && !event.repeat
                    && state.key(key, self.options.screenshot.as_deref(), self.say)?
                {
                    event_loop.exit();
                }
            }
            WindowEvent::MouseInput {
                state: pressed,
                button: MouseButton::Left,
                ..
            } => state.dragging = pressed == ElementState::Pressed,
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (state.dragging, state.cursor) {
                    state
                        .camera
                        .drag((position.x - x) as f32, (position.y - y) as f32);
                }
                state.cursor = Some((position.x, position.y));
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                state.camera.zoom(steps);
            }
            WindowEvent::RedrawRequested => {
                let frame = state.frame;
                for k in self.options.script.iter().filter(|k| k.frame == frame) {
                    match k.input {
                        Scripted::Key(key) => {
                            if state.key(key, self.options.screenshot.as_deref(), self.say)? {
                                event_loop.exit();
                                return Ok(());
                            }
                        }
                        Scripted::Resize(w, h) => {
                            // The answer arrives as a Resized event (or, where the
                            // window system applies it at once, a new inner size).
                            let _ = state.window.request_inner_size(PhysicalSize::new(w, h));
                            state.stale = true;
                        }
                    }
                }
                let last = self.options.frames.is_some_and(|n| state.frame + 1 >= n);
                if let (true, Some(path)) = (last, &self.options.screenshot) {
                    state.pending = Some(path.clone());
                }
                state.frame(&mut self.report)?;
                if last {
                    event_loop.exit();
                }
            }
            _ => {}
        }
        Ok(())
    }
}

impl State {
    /// Handles a key press; true to quit.
    fn key(
        &mut self,
        key: Key,
        screenshot: Option<&std::path::Path>,
        say: &mut dyn FnMut(&str),
    ) -> Result<bool> {
        match key {
            Key::Escape => return Ok(true),
            Key::Tab => self.camera.toggle_mode(),
            Key::Char('h') => self.overlay = !self.overlay,
            Key::Char('v') => say(&self.camera.options()),
            Key::F(2) => {
                // The frame being drawn next is read back and written after it.
                let default = PathBuf::from(format!("sediment-view-{:05}.png", self.frame));
                self.pending = Some(screenshot.map_or(default, Into::into));
            }
            Key::Char(c @ ('w' | 'a' | 's' | 'd' | 'q' | 'e')) => {
                // A scripted press of a movement key: a quarter second of movement.
                let (f, r, u) = movement(&HashSet::from([c]));
                self.camera.fly(f, r, u, 0.25);
            }
            other => {
                // A scene's key may rewrite what the frame in flight reads.
                self.settle()?;
                // A scene's key changes what it shows in ways depth does not tell (a
                // light, a look): what temporal anti-aliasing accumulated is dropped.
                let took = match self.scene.interactive() {
                    Some(keys) => keys.key(&self.ctx, other)?,
                    None => false,
                };
                if took {
                    if let Some(runner) = &mut self.runner {
                        runner.start_over();
                    }
                }
            }
        }
        Ok(false)
    }

    /// Writes the frame just rendered (the scene, without the panel) as PNG.
    fn screenshot(&self, path: &std::path::Path) -> Result<()> {
        let Some(runner) = &self.runner else {
            return Err(Error::internal(
                "screenshot",
                "no frame has been rendered yet",
            ));
        };
        // A frame the validation layer objected to is not trusted to a file: the run
        // exits 1 at the end with the errors, having written nothing (issue 17 #3).
        let errors = self.ctx.validation_error_count();
        if errors > 0 {
            log::warn!(
                "screenshot {} not written: the validation layer reported {errors} error(s)",
                path.display()
            );
            return Ok(());
        }
        crate::export::png::write_png(path, &runner.image()?)?;
        log::info!("wrote {}", path.display());
        Ok(())
    }

    /// (Re)creates the swapchain and the targets at the window's size; false while
    /// the window is minimised.
    fn ensure_swapchain(&mut self) -> Result<bool> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(false);
        }
        if !self.stale && self.swapchain.is_some() {
            return Ok(true);
        }
        // The swapchain, the target and the panel's buffers are replaced: nothing may
        // be drawing into or from them.
        self.settle()?;
        self.swapchain = None;
        let chain = Swapchain::new(
            &self.ctx,
            &self.surface,
            size.width,
            size.height,
            self.vsync,
        )?;
        let (w, h) = chain.size();
        if w == 0 || h == 0 {
            return Ok(false);
        }
        match &mut self.runner {
            Some(runner) => {
                // The window's size, not --size, is what changed (at least one target
                // pixel a window pixel, whatever the supersampling).
                let format = runner.target().format();
                format.check_budget_of("the window size", w, h)?;
                runner.resize(Size::new(w, h))?
            }
            None => {
                self.runner = Some(FrameRunner::for_window(
                    &self.ctx,
                    Size::new(w, h),
                    chain.format(),
                )?)
            }
        }
        self.overlay_buffers = (0..FRAMES_IN_FLIGHT)
            .map(|slot| {
                Buffer::new(
                    &self.ctx,
                    &format!("overlay pixels {slot}"),
                    BufferDesc::upload(
                        u64::from(w) * u64::from(h) * 4,
                        vk::BufferUsageFlags::TRANSFER_SRC,
                    ),
                )
            })
            .collect::<Result<_>>()?;
        self.swapchain = Some(chain);
        self.stale = false;
        Ok(true)
    }

    /// Waits for the frame in flight, if any, and takes in its spans (handing them to
    /// the scene too). What writes anything a frame reads — the scene's `set_frame`
    /// and keys, a new swapchain or target — comes after this.
    fn settle(&mut self) -> Result<()> {
        if !self.unsettled {
            return Ok(());
        }
        self.frames.wait_all()?;
        self.unsettled = false;
        if let Some(runner) = self.runner.as_mut() {
            self.last_gpu = runner.finish(self.scene.as_mut())?;
            let clock = self.scene.animated() && self.scene.steps().is_some();
            self.settled.push((self.last_gpu.clone(), clock));
        }
        Ok(())
    }

    /// Moves the settled frames' spans into `report`.
    fn report_settled(&mut self, report: &mut ViewReport) {
        for (spans, clock) in self.settled.drain(..) {
            report.gpu_spans.push(spans);
            if clock {
                report.clock_frames = report.gpu_spans.len();
            }
        }
    }

    /// One frame: its image acquired and its panel laid out while the last frame may
    /// still be drawing, then (once that one has finished) the scene set, recorded,
    /// submitted and presented without waiting for it.
    fn frame(&mut self, report: &mut ViewReport) -> Result<()> {
        let now = Instant::now();
        let seconds = now.duration_since(self.last_frame).as_secs_f32().min(0.25);
        self.last_frame = now;
        let (f, r, u) = movement(&self.held);
        self.camera.fly(f, r, u, seconds);
        if !self.ensure_swapchain()? {
            std::thread::sleep(std::time::Duration::from_millis(30));
            return Ok(());
        }
        let slot = self.frames.next_slot()?;
        let Some(chain) = self.swapchain.as_ref() else {
            return Ok(());
        };
        let Some(index) = chain.acquire(&self.frames, slot)? else {
            self.stale = true;
            return Ok(());
        };
        let (w, h) = chain.size();
        let bgra = chain.is_bgra();
        let panel = if self.overlay {
            let mut lines = vec![format!(
                "sediment view {}  {:.1} fps  cpu {:.1} ms  gpu {:.2} ms ({})  {}",
                self.scene.name(),
                self.fps,
                1e3 / self.fps.max(1e-3),
                self.last_gpu.iter().map(|s| s.milliseconds).sum::<f64>(),
                crate::frame::spans_line(&self.last_gpu),
                match self.camera.mode {
                    camera_control::CameraMode::Orbit => "orbit",
                    camera_control::CameraMode::Fly => "fly",
                }
            )];
            lines.extend(self.scene.status());
            let keys = self.scene.interactive();
            let (controls, message) = keys.map_or((&[][..], String::new()), |k| {
                (k.controls(), k.message().to_owned())
            });
            lines.extend(controls.iter().map(|s| s.to_string()));
            lines.extend(CONTROLS.iter().map(|s| s.to_string()));
            if !message.is_empty() {
                lines.push(message);
            }
            overlay::panel(&lines, w, h, bgra)
        } else {
            None
        };
        if let (Some(p), Some(pixels)) = (&panel, self.overlay_buffers.get_mut(slot)) {
            pixels.write(0, &p.pixels)?;
        }
        // The scene keeps one copy of what it writes for the GPU: the last frame must
        // be done with it first.
        self.settle()?;
        self.report_settled(report);
        let (Some(chain), Some(runner), Some(pixels)) = (
            self.swapchain.as_ref(),
            self.runner.as_mut(),
            self.overlay_buffers.get(slot),
        ) else {
            return Ok(());
        };
        runner.set_frame(self.scene.as_mut(), &self.camera.camera(), Time::Tick)?;
        let save = self.pending.is_some();
        let scene = &mut self.scene;
        let presented = chain.present(&mut self.frames, slot, index, |cmd, image| {
            // Only a frame to be saved is read back.
            runner.record(cmd, scene.as_mut(), save)?;
            cmd.blit_target(runner.shown(), image, chain.format(), w, h);
            if let Some(p) = &panel {
                cmd.copy_pixels(pixels, image, (0, 0), (p.width, p.height));
            }
            Ok(())
        })?;
        self.unsettled = true;
        if presented == Presented::Stale {
            self.stale = true;
        }
        if let Some(path) = self.pending.take() {
            self.settle()?;
            self.report_settled(report);
            self.screenshot(&path)?;
        }
        let frame_ms = now.elapsed().as_secs_f64() * 1e3;
        self.fps = 0.9 * self.fps + 0.1 * (1e3 / frame_ms.max(1e-3));
        report.frames += 1;
        report.frame_ms.push(frame_ms);
        report.size = Size::new(w, h);
        self.frame += 1;
        Ok(())
    }

    /// At exit: the scene's asset (when asked for) and the validation errors.
    fn finish(mut self, report: &mut ViewReport, title: Option<&str>) -> Result<()> {
        self.settle()?;
        self.report_settled(report);
        self.ctx.wait_idle()?;
        if let Some(title) = title {
            report.asset = match self.scene.exportable() {
                Some(e) => e.asset(&self.ctx, title)?,
                None => None,
            };
        }
        report.validation_errors = self.ctx.take_validation_errors();
        Ok(())
    }
}

/// (forward, right, up) from the held movement keys.
fn movement(held: &HashSet<char>) -> (f32, f32, f32) {
    let axis = |plus: char, minus: char| {
        f32::from(u8::from(held.contains(&plus))) - f32::from(u8::from(held.contains(&minus)))
    };
    (axis('w', 's'), axis('d', 'a'), axis('e', 'q'))
}

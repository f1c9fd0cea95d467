//! microray in embedded-graphics' desktop simulator: a window the size of a small display,
//! traced row by row through `Frame::draw` as a board's display driver takes it, the camera
//! orbiting under the arrow keys. `--headless OUT.png` draws the same frame without a window.
//!
//! `microray-simulator [SCENE.toml] [--size WxH] [--headless OUT.png] [--exit-after-frame SECONDS]`
//!
//! Exit codes: 0 done, 1 an I/O failure (or no window to be had), 2 invalid input.
#![deny(unsafe_code)]

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyleBuilder};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::Rectangle;
use embedded_graphics::text::{Baseline, Text};
use embedded_graphics_simulator::sdl2::Keycode;
use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay, SimulatorEvent, Window};
use microray::animation::View;
use microray::render::Heap;
use microray::scene_file::{self, Desktop};
use microray::{Camera, Frame, FrameStorage};

const USAGE: &str = "usage: microray-simulator [SCENE.toml] [--size WxH] [--headless OUT.png] \
                     [--exit-after-frame SECONDS]";

/// The scene shown when none is given: the repository's demo, wherever this runs from.
const DEMO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/demo.toml");

/// Degrees per arrow key: around the scene (left, right), and up or down over it.
const ORBIT_STEP: f32 = 15.0;
const TILT_STEP: f32 = 10.0;

/// The window shows the rows drawn so far at most this often: a monitor's refresh, so that
/// showing them takes little from the tracing (and the simulator's 60 fps limiter never sleeps).
const SHOW_EVERY: Duration = Duration::from_micros(16_667);

/// A failure and its exit code.
struct Failure(u8, String);

struct Args {
    scene: PathBuf,
    size: Size,
    headless: Option<PathBuf>,
    exit_after: Option<Duration>,
}

fn main() -> ExitCode {
    let args = match parse_args(std::env::args().skip(1)) {
        Ok(Some(args)) => args,
        Ok(None) => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(Failure(code, msg)) => {
            eprintln!("error: {msg}");
            return ExitCode::from(code);
        }
    };
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure(code, msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}

/// The arguments, or `None` for `--help`.
fn parse_args(mut it: impl Iterator<Item = String>) -> Result<Option<Args>, Failure> {
    let bad = |msg: String| Failure(2, msg);
    let mut args = Args {
        scene: PathBuf::from(DEMO),
        size: Size::new(320, 240),
        headless: None,
        exit_after: None,
    };
    let mut scene = None;
    while let Some(arg) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .ok_or_else(|| bad(format!("{name}: missing value")))
        };
        match arg.as_str() {
            "-h" | "--help" => return Ok(None),
            "--size" => {
                let v = value("--size")?;
                args.size = parse_size(&v).ok_or_else(|| {
                    bad(format!(
                        "--size {v}: expected WIDTHxHEIGHT, such as 240x240"
                    ))
                })?;
            }
            "--headless" => {
                let out = PathBuf::from(value("--headless")?);
                check_png(&out)?;
                args.headless = Some(out);
            }
            "--exit-after-frame" => {
                let v = value("--exit-after-frame")?;
                let secs = v
                    .parse::<f64>()
                    .ok()
                    .filter(|s| (0.0..=86_400.0).contains(s));
                let secs = secs.ok_or_else(|| {
                    bad(format!(
                        "--exit-after-frame {v}: expected seconds, 0 to 86400"
                    ))
                })?;
                args.exit_after = Some(Duration::from_secs_f64(secs));
            }
            s if s.starts_with('-') => return Err(bad(format!("unknown option {s} ({USAGE})"))),
            _ if scene.is_some() => return Err(bad(format!("{arg}: only one scene ({USAGE})"))),
            _ => scene = Some(PathBuf::from(arg)),
        }
    }
    if args.headless.is_some() && args.exit_after.is_some() {
        return Err(bad(
            "--exit-after-frame: only with a window, not --headless".into(),
        ));
    }
    if let Some(scene) = scene {
        args.scene = scene;
    }
    Ok(Some(args))
}

/// `WxH` with both at least 1 (the camera checks the upper bound).
fn parse_size(s: &str) -> Option<Size> {
    let (w, h) = s.split_once(['x', 'X'])?;
    let (w, h) = (w.parse::<u32>().ok()?, h.parse::<u32>().ok()?);
    (w > 0 && h > 0).then(|| Size::new(w, h))
}

/// The simulator writes PNG whatever the name: another extension is invalid input.
fn check_png(out: &Path) -> Result<(), Failure> {
    match out.extension() {
        Some(ext) if ext.eq_ignore_ascii_case("png") => Ok(()),
        _ => Err(Failure(
            2,
            format!("{}: the output is PNG: name it .png", out.display()),
        )),
    }
}

fn run(args: Args) -> Result<(), Failure> {
    let file: Box<Desktop> = scene_file::load(&args.scene)
        .map_err(|e| Failure(if e.io { 1 } else { 2 }, e.to_string()))?;
    let (w, h) = (args.size.width, args.size.height);
    let camera = file
        .view
        .camera(w, h)
        .map_err(|e| Failure(2, format!("--size {w}x{h}: {e}")))?;
    // The desktop capacity's per-frame tables (15.4 MB): on the heap, filled anew each frame.
    let mut storage = FrameStorage::on_heap();
    let mut display = SimulatorDisplay::<Rgb888>::new(args.size);
    match &args.headless {
        Some(out) => {
            let mut queued = Vec::new();
            let mut live = Live::new(&mut display, None, &mut queued);
            let Traced::Done(took) = trace(&file, &camera, &mut storage, &mut live)? else {
                unreachable!("only a window is closed");
            };
            // Scale 1 and no pixel spacing: the PNG holds the display's pixels as they are.
            display
                .to_rgb_output_image(&OutputSettings::default())
                .save_png(out)
                .map_err(|e| Failure(1, format!("{}: {e}", out.display())))?;
            println!("wrote {} ({w}x{h})", out.display());
            println!("frame: {:.1} ms", took.as_secs_f64() * 1e3);
            Ok(())
        }
        None => run_window(&file, camera, &mut storage, &mut display, args.exit_after),
    }
}

/// The window's loop: a frame for each new view, the arrow keys turning the view, Escape or
/// closing the window ending it (or `exit_after` past the last frame).
fn run_window(
    file: &Desktop,
    camera: Camera,
    storage: &mut FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }, Heap>,
    display: &mut SimulatorDisplay<Rgb888>,
    exit_after: Option<Duration>,
) -> Result<(), Failure> {
    check_video()?;
    let size = display.size();
    let mut window = Window::new(
        &format!("microray {}x{}", size.width, size.height),
        &OutputSettings::default(),
    );
    let mut view = file.view;
    let mut next = Some(camera);
    let mut queued = Vec::new();
    let mut finished = Instant::now();
    loop {
        if let Some(camera) = next.take() {
            let mut live = Live::new(display, Some(&mut window), &mut queued);
            match trace(file, &camera, storage, &mut live)? {
                Traced::Done(took) => {
                    let ms = took.as_secs_f64() * 1e3;
                    show_time(display, ms);
                    window.update(display);
                    // Printed once the frame is on screen (screenshot.sh waits for it).
                    println!("frame: {ms:.1} ms");
                    finished = Instant::now();
                }
                Traced::Quit => return Ok(()),
            }
        }
        window.update(display);
        queued.extend(window.events());
        for event in queued.drain(..) {
            let turned = match event {
                SimulatorEvent::Quit => return Ok(()),
                SimulatorEvent::KeyDown { keycode, .. } => match keycode {
                    Keycode::Left => Some(view.orbit(-ORBIT_STEP)),
                    Keycode::Right => Some(view.orbit(ORBIT_STEP)),
                    Keycode::Up => tilt(&view, TILT_STEP),
                    Keycode::Down => tilt(&view, -TILT_STEP),
                    _ => None,
                },
                _ => None,
            };
            // A view the camera rejects is ignored: the last good one stays.
            if let Some((turned, camera)) =
                turned.and_then(|v| Some((v, v.camera(size.width, size.height).ok()?)))
            {
                view = turned;
                next = Some(camera);
            }
        }
        if next.is_none() && exit_after.is_some_and(|after| finished.elapsed() >= after) {
            return Ok(());
        }
    }
}

/// The view tilted by `degrees`, or `None` past straight above or below the look-at point:
/// there the camera's right axis (`back × up`) turns round and the scene would flip over,
/// which the camera itself does not reject.
fn tilt(view: &View, degrees: f32) -> Option<View> {
    let turned = view.tilt(degrees);
    let right = |v: &View| (v.eye - v.look_at).cross(v.up);
    (right(view).dot(right(&turned)) > 0.0).then_some(turned)
}

/// Asks SDL for a video device before the simulator does, so that having none is a one-line
/// error: the simulator's window panics where SDL fails, and where SDL falls back to its
/// invisible drivers (`offscreen` without an X display) the loop would run with no window to
/// show. Those stay usable when chosen with `SDL_VIDEODRIVER`. SDL is shut down again before
/// the window starts it.
fn check_video() -> Result<(), Failure> {
    let driver = sdl2::init().and_then(|sdl| Ok(sdl.video()?.current_video_driver()));
    let chosen = |d: &str| std::env::var("SDL_VIDEODRIVER").is_ok_and(|v| v == d);
    let why = match driver {
        Err(e) => e,
        Ok(d @ ("offscreen" | "dummy")) if !chosen(d) => "no display".into(),
        Ok(_) => return Ok(()),
    };
    Err(Failure(
        1,
        format!("no window can be opened ({why}): run with a display, or with --headless OUT.png"),
    ))
}

/// The frame's time in the bottom-left corner, in embedded-graphics' 6×10 font: drawn after
/// the frame, and gone where the next frame's rows reach it.
fn show_time(display: &mut SimulatorDisplay<Rgb888>, ms: f64) {
    let style = MonoTextStyleBuilder::new()
        .font(&FONT_6X10)
        .text_color(Rgb888::WHITE)
        .background_color(Rgb888::BLACK)
        .build();
    let bottom_left = Point::new(0, display.size().height as i32);
    let text = format!(" {ms:.0} ms ");
    // SimulatorDisplay cannot fail to draw.
    let Ok(_) = Text::with_baseline(&text, bottom_left, style, Baseline::Bottom).draw(display);
}

/// How a frame ended.
enum Traced {
    /// Drawn, in this time (the window's showing of rows left out).
    Done(Duration),
    /// The window was closed while it was drawn.
    Quit,
}

/// One frame, as a board traces it: `Frame::new`, then `Frame::draw`, which hands the display
/// one `fill_contiguous` and traces each row as the display takes it.
fn trace(
    file: &Desktop,
    camera: &Camera,
    storage: &mut FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }, Heap>,
    live: &mut Live<'_>,
) -> Result<Traced, Failure> {
    let start = Instant::now();
    let frame = Frame::new(&file.scene, camera, file.options, storage)
        .map_err(|e| Failure(2, e.to_string()))?;
    Ok(match frame.draw(live) {
        Ok(()) => Traced::Done(start.elapsed().saturating_sub(live.showing)),
        Err(WindowClosed) => Traced::Quit,
    })
}

/// The window was closed while a frame was drawn.
#[derive(Debug)]
struct WindowClosed;

/// The simulator's display as a display driver sees a frame: one `fill_contiguous`, whose
/// pixels arrive row by row. Between rows it shows the window (when there is one) at up to
/// [`SHOW_EVERY`], so the frame appears as it is traced.
struct Live<'a> {
    display: &'a mut SimulatorDisplay<Rgb888>,
    window: Option<&'a mut Window>,
    /// Events that came while the frame was drawn, kept for after it.
    queued: &'a mut Vec<SimulatorEvent>,
    shown: Instant,
    /// Time spent showing the window: not the frame's.
    showing: Duration,
}

impl<'a> Live<'a> {
    fn new(
        display: &'a mut SimulatorDisplay<Rgb888>,
        window: Option<&'a mut Window>,
        queued: &'a mut Vec<SimulatorEvent>,
    ) -> Self {
        Live {
            display,
            window,
            queued,
            shown: Instant::now(),
            showing: Duration::ZERO,
        }
    }

    /// After a row: the window shows what is drawn, if it is time, and its events are kept.
    fn row_done(&mut self) -> Result<(), WindowClosed> {
        let Some(window) = self.window.as_deref_mut() else {
            return Ok(());
        };
        if self.shown.elapsed() < SHOW_EVERY {
            return Ok(());
        }
        let start = Instant::now();
        window.update(self.display);
        for event in window.events() {
            if event == SimulatorEvent::Quit {
                return Err(WindowClosed);
            }
            self.queued.push(event);
        }
        self.shown = Instant::now();
        self.showing += self.shown - start;
        Ok(())
    }
}

impl OriginDimensions for Live<'_> {
    fn size(&self) -> Size {
        self.display.size()
    }
}

impl DrawTarget for Live<'_> {
    type Color = Rgb888;
    type Error = WindowClosed;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), WindowClosed>
    where
        I: IntoIterator<Item = Pixel<Rgb888>>,
    {
        let Ok(()) = self.display.draw_iter(pixels);
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), WindowClosed>
    where
        I: IntoIterator<Item = Rgb888>,
    {
        let mut colors = colors.into_iter();
        let width = area.size.width as usize;
        for y in area.rows() {
            let row = Rectangle::new(
                Point::new(area.top_left.x, y),
                Size::new(area.size.width, 1),
            );
            // The simulator clips to its display, as a driver would.
            let Ok(()) = self
                .display
                .fill_contiguous(&row, colors.by_ref().take(width));
            self.row_done()?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn demo() -> Box<Desktop> {
        scene_file::load(DEMO).expect("the demo scene")
    }

    #[test]
    fn the_display_gets_the_renderers_pixels() {
        let file = demo();
        let camera = file.view.camera(40, 30).unwrap();
        let mut storage = FrameStorage::on_heap();
        let mut display = SimulatorDisplay::<Rgb888>::new(Size::new(40, 30));
        let mut queued = Vec::new();
        let mut live = Live::new(&mut display, None, &mut queued);
        assert!(matches!(
            trace(&file, &camera, &mut storage, &mut live),
            Ok(Traced::Done(_))
        ));
        let frame = Frame::new(&file.scene, &camera, file.options, &mut storage).unwrap();
        let mut image = vec![Rgb888::BLACK; 40 * 30];
        frame.render(&mut image).unwrap();
        let shown: Vec<_> = display
            .bounding_box()
            .points()
            .map(|p| display.get_pixel(p))
            .collect();
        assert_eq!(shown, image);
    }

    #[test]
    fn tilting_stops_short_of_the_poles() {
        let view = demo().view;
        let (mut up, mut steps) = (view, 0);
        while let Some(next) = tilt(&up, TILT_STEP) {
            (up, steps) = (next, steps + 1);
        }
        // The demo's eye is 7.3° above the look-at point: 8 steps reach 87.3°.
        assert_eq!(steps, 8);
        // One more is a valid camera looking from the far side: only the guard stops it.
        assert!(up.tilt(TILT_STEP).camera(320, 240).is_ok());
        let (mut down, mut steps) = (view, 0);
        while let Some(next) = tilt(&down, -TILT_STEP) {
            (down, steps) = (next, steps + 1);
        }
        assert_eq!(steps, 9);
    }

    #[test]
    fn arguments() {
        let parse = |args: &[&str]| parse_args(args.iter().map(|s| s.to_string()));
        let args = parse(&["scene.toml", "--size", "240x240"])
            .ok()
            .flatten()
            .unwrap();
        assert_eq!(
            (args.scene, args.size),
            ("scene.toml".into(), Size::new(240, 240))
        );
        assert!(matches!(parse(&["--help"]), Ok(None)));
        for bad in [
            &["--size", "240"][..],
            &["--size", "0x240"],
            &["--size"],
            &["--headless", "out.jpg"],
            &["--headless", "a.png", "--exit-after-frame", "1"],
            &["--exit-after-frame", "-1"],
            &["a.toml", "b.toml"],
            &["--bogus"],
        ] {
            assert!(matches!(parse(bad), Err(Failure(2, _))), "{bad:?}");
        }
    }
}

//! microray's desktop renderer: a TOML scene in, a PNG out, or an animation.
//!
//! `cargo run --release --example render -- [SCENE.toml] [-o OUT.png|OUT.gif] [--width N]
//! [--height N] [--samples N] [--threads N] [--frames N [--orbit DEGREES]]`
//!
//! Exit codes: 0 done, 1 an I/O failure, 2 invalid input. On any failure no file is written
//! and an existing file at the output path is left untouched.

mod animation;
mod bands;

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use clap::Parser;
use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::scene_file::{self, Desktop};
use microray::{Frame, FrameStorage, RenderOptions};

use animation::{Encoder, Format, Path as CameraPath};
use bands::Bands;

const DEMO: &str = include_str!("../scenes/demo.toml");

/// Renders a microray scene file to a PNG.
#[derive(Parser)]
#[command(about)]
struct Args {
    /// The scene (TOML); the built-in demo scene when left out.
    scene: Option<PathBuf>,
    /// Where to write the PNG (.png, or no extension for a device).
    #[arg(short, long, default_value = "render.png")]
    output: PathBuf,
    /// Image width, overriding the scene's (1..=16384).
    #[arg(long)]
    width: Option<u32>,
    /// Image height, overriding the scene's (1..=16384).
    #[arg(long)]
    height: Option<u32>,
    /// Samples per pixel along each axis, overriding the scene's (1..=16).
    #[arg(long)]
    samples: Option<u8>,
    /// Threads rendering bands of rows in parallel (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Renders an animation of N frames (an animated PNG, or a GIF for a .gif output): the
    /// scene's keyframes if it has any, else an orbit about the look-at point.
    #[arg(long, allow_negative_numbers = true)]
    frames: Option<u32>,
    /// The orbit's turn over all frames, in degrees (default 360; needs --frames).
    #[arg(long, allow_negative_numbers = true)]
    orbit: Option<f32>,
}

/// A failure and its exit code.
struct Failure(u8, String);

fn main() -> ExitCode {
    let args = match Args::try_parse() {
        Ok(args) => args,
        Err(e) if !e.use_stderr() => {
            // --help, --version: clap's own text, on stdout.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            // One line, as every other error: clap's first, without its usage and hints.
            let text = e.to_string();
            let line = text.lines().next().unwrap_or("invalid arguments");
            eprintln!("error: {}", line.trim_start_matches("error: "));
            return ExitCode::from(2);
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

fn run(args: Args) -> Result<(), Failure> {
    let read = Instant::now();
    let file: Box<Desktop> = match &args.scene {
        Some(path) => scene_file::load(path),
        None => scene_file::parse(DEMO),
    }
    .map_err(|e| Failure(if e.io { 1 } else { 2 }, e.to_string()))?;
    let read_ms = read.elapsed().as_secs_f64() * 1e3;
    let width = args.width.unwrap_or(file.width);
    let height = args.height.unwrap_or(file.height);
    let camera = file
        .view
        .camera(width, height)
        .map_err(|e| Failure(2, format!("--width {width} --height {height}: {e}")))?;
    let options = RenderOptions {
        samples: args.samples.unwrap_or(file.options.samples),
        ..file.options
    };
    let threads = match args.threads {
        Some(0) => return Err(Failure(2, "--threads: must be at least 1".into())),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    let format = check_format(&args.output)?;
    let path = match (args.frames, args.orbit) {
        (None, Some(_)) => return Err(Failure(2, "--orbit: needs --frames".into())),
        (Some(0), _) => return Err(Failure(2, "--frames: must be at least 1".into())),
        (_, Some(d)) if !d.is_finite() => {
            return Err(Failure(
                2,
                format!("--orbit: must be a finite number, not {d}"),
            ))
        }
        (Some(_), Some(_)) if !file.keyframes.keys().is_empty() => {
            return Err(Failure(
                2,
                "--orbit: the scene has keyframes, which set the camera of every frame".into(),
            ))
        }
        (Some(_), None) if !file.keyframes.keys().is_empty() => Some(CameraPath::Keyframes(&file)),
        (Some(_), degrees) => Some(CameraPath::Orbit(microray::animation::Orbit {
            view: file.view,
            degrees: degrees.unwrap_or(360.0),
        })),
        // A still written as GIF: a one-frame animation.
        (None, None) if format == Format::Gif => Some(CameraPath::Still(file.view)),
        (None, None) => None,
    };
    output_target(&args.output)?;
    if let Some(path) = path {
        let frames = args.frames.unwrap_or(1);
        let cameras = path.cameras(frames, (width, height))?;
        return animate(&args, &file, &cameras, (options, threads), format);
    }

    // The image the bands are rendered into, allocated and written before the clock starts:
    // the kernel maps a fresh page at its first write (~3 µs a page on this VM, ~1 ms for a
    // 640×480 image), which is the caller's allocation, not rendering. POV-Ray's trace time (its
    // trace tasks' own time) leaves its image out likewise: its front end makes the image with
    // the view. Magenta, so that a pixel no band wrote would show.
    let alloc = Instant::now();
    let mut image = image_buffer(width as usize * height as usize)?;
    let alloc_ms = alloc.elapsed().as_secs_f64() * 1e3;

    // A scene within `SMALL` spheres is rendered at that capacity: its frame's tables and
    // per-row lists are then sized for it, not for the desktop's 16 384 (the same pixels).
    let small = at_small(&file.scene);
    let (ms, pool_ms) = with_progress(height, |done| match &small {
        Some(small) => render(small, &camera, options, threads, &mut image, done),
        None => render(&file.scene, &camera, options, threads, &mut image, done),
    })?;

    write_png(&args.output, width, height, &image)?;
    println!("wrote {} ({width}x{height})", args.output.display());
    println!("scene file: {read_ms:.1} ms");
    println!("image buffer: {alloc_ms:.1} ms");
    if let Some(pool_ms) = pool_ms {
        println!("thread start-up: {pool_ms:.2} ms");
    }
    println!("render: {ms:.2} ms");
    Ok(())
}

/// Renders one frame per camera, encodes them as they come, and writes the file at the end.
fn animate(
    args: &Args,
    file: &Desktop,
    cameras: &[microray::Camera],
    (options, threads): (RenderOptions, usize),
    format: Format,
) -> Result<(), Failure> {
    let Some(first) = cameras.first() else {
        return Err(Failure(2, "--frames: must be at least 1".into()));
    };
    let size = (first.width(), first.height());
    let mut image = image_buffer(size.0 as usize * size.1 as usize)?;
    let mut encoder = Encoder::new(format, cameras.len() as u32, size)?;
    let mut times = Vec::with_capacity(cameras.len());
    // As for a still: a scene within `SMALL` spheres is rendered at that capacity.
    let small = at_small(&file.scene);
    with_progress(size.1 * cameras.len() as u32, |done| {
        for camera in cameras {
            let (ms, _) = match &small {
                Some(small) => render(small, camera, options, threads, &mut image, done),
                None => render(&file.scene, camera, options, threads, &mut image, done),
            }?;
            times.push(ms);
            encoder.frame(size, &image)?;
        }
        Ok(())
    })?;
    let bytes = encoder.finish()?;
    write_file(&args.output, bytes)?;
    let (w, h) = size;
    println!(
        "wrote {} ({w}x{h}, {} frames)",
        args.output.display(),
        cameras.len()
    );
    println!("render per frame: {}", animation::summary(&times));
    Ok(())
}

/// The capacity at which a scene is rendered when it fits: the frame of a
/// 16 384-sphere capacity sizes its per-row lists and tables for that many, which cost the
/// target scene 2–3 % of its time.
const SMALL: usize = 1024;

/// `scene` at the capacity [`SMALL`] where it fits: a copy, far cheaper than reading the file
/// again, on the heap (about 80 KB).
fn at_small<const S: usize, const L: usize>(
    scene: &microray::Scene<S, L>,
) -> Option<Box<microray::Scene<SMALL, L>>> {
    let mut small = Box::new(microray::Scene::new());
    small.copy_from(scene).ok()?;
    Some(small)
}

/// Renders `image` in bands of rows on `threads` threads through the library's band API,
/// counting the rows done in `done` (for the progress bar). Returns the `render:`
/// time in ms, from the start of `Frame::new` to the last band written, and for several threads
/// the time it took to start them, which comes before that clock.
///
/// One thread is this one: spawning a worker made one-thread frames 5–10% slower here
/// (interleaved runs). Several threads are spawned workers, started before the clock as a
/// renderer's thread pool is: on this VM a new thread first runs 50–190 µs after its spawn (its
/// idle vCPU has to be woken), program start-up rather than rendering (POV-Ray's trace time
/// leaves its threads' start out likewise). They wait for the start spinning, with `yield_now`
/// so that a thread sharing their CPU still runs, because a parked thread would take that
/// latency again to wake. For a scene of more than [`SMALL`] spheres the first worker builds the
/// one `Frame` they all render, in storage allocated before the clock, while the others spin
/// until it is there: one storage for any number of threads (15.4 MB at the desktop capacity,
/// which a frame per thread would multiply), built once (frames built by every thread at once
/// compete for memory and its first touch). A smaller scene's workers each build their own frame
/// (~0.1 ms, in parallel), which is sooner than waiting for a shared one. This thread does not
/// render with them: a worker it spawned was queued on its CPU, and the two took as long as one
/// thread alone (1.38× one over 21 interleaved runs instead of 1.85×). The last worker to
/// finish notes the time, which ends the clock, and unparks it: waiting in `join`, or spinning
/// with `yield_now`, it learned of the end ~0.1–0.25 ms late (after the thread's exit, or after
/// the scheduler's slice).
fn render<const S: usize, const L: usize>(
    scene: &microray::Scene<S, L>,
    camera: &microray::Camera,
    options: RenderOptions,
    threads: usize,
    image: &mut [Rgb888],
    done: &AtomicU32,
) -> Result<(f64, Option<f64>), Failure> {
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let failed = |e: microray::Error| Failure(2, format!("--samples: {e}"));
    let workers = threads.min(h);
    // Bands of a few rows, handed out in order (`bands.rs`).
    let bands = Mutex::new(Bands::new(image, w, workers));
    let work = |frame: &Frame<'_, S, L>| loop {
        let next = bands.lock().unwrap_or_else(|e| e.into_inner()).next();
        let Some((row, band)) = next else { break };
        // Every band holds whole rows inside the image, so this cannot fail.
        if let Ok(rows) = frame.render_rows(row as u32, band) {
            done.fetch_add(rows, Ordering::Relaxed);
        }
    };
    // How many workers wait for the start, whether to start (`GO`) or not (`STOP`), and how
    // many have not finished.
    let ready = AtomicUsize::new(0);
    let state = AtomicU8::new(WAIT);
    let left = AtomicUsize::new(workers);
    // When the last worker finished: the frame's end, which this thread learns of later.
    let end = Mutex::new(None::<Instant>);
    let waiter = std::thread::current();
    // The frame's tables on the heap, allocated before the clock; the frame the workers share,
    // and whether its build panicked.
    let mut shared = FrameStorage::on_heap();
    let (frame, broken) = (std::sync::OnceLock::new(), AtomicBool::new(false));
    std::thread::scope(|s| {
        if threads == 1 {
            // The stack the render will use, written once.
            touch_stack();
            let start = Instant::now();
            let made = Frame::new(scene, camera, options, &mut shared);
            made.as_ref().map(work).map_err(|&e| failed(e))?;
            return Ok((start.elapsed().as_secs_f64() * 1e3, None));
        }
        let pool = Instant::now();
        let mut spawned = Vec::with_capacity(workers);
        // The shared storage, for the first worker to build the frame in.
        let share = scene.spheres().len() > SMALL;
        let mut storage = share.then_some(&mut shared);
        for _ in 0..workers {
            let builds = storage.take();
            let (frame, broken, ready, state) = (&frame, &broken, &ready, &state);
            let (left, end, waiter, work) = (&left, &end, &waiter, &work);
            let worker = std::thread::Builder::new().spawn_scoped(s, move || {
                // A small scene's worker builds its own frame, in its own storage (freed after
                // `_finished` has ended the clock).
                let mut own = (!share).then(FrameStorage::on_heap);
                touch_stack();
                ready.fetch_add(1, Ordering::Release);
                loop {
                    match state.load(Ordering::Acquire) {
                        WAIT => std::thread::yield_now(),
                        GO => break,
                        _ => return Ok(()),
                    }
                }
                // Counted as finished however it ends, a panic included, so that the
                // waiting thread always wakes (and `join` then passes the panic on).
                let _finished = Finally(|| {
                    if left.fetch_sub(1, Ordering::Release) == 1 {
                        *end.lock().unwrap_or_else(|e| e.into_inner()) = Some(Instant::now());
                        waiter.unpark();
                    }
                });
                if let Some(storage) = own.as_mut() {
                    let made = Frame::new(scene, camera, options, storage);
                    return made.as_ref().map(work).map_err(|&e| e);
                }
                shared_frame(builds, frame, broken, (scene, camera, options), work)
            });
            match worker {
                Ok(worker) => spawned.push(worker),
                Err(e) => {
                    state.store(STOP, Ordering::Release);
                    return Err(Failure(1, format!("cannot start a thread: {e}")));
                }
            }
        }
        while ready.load(Ordering::Acquire) < workers {
            std::thread::yield_now();
        }
        let pool_ms = pool.elapsed().as_secs_f64() * 1e3;
        let start = Instant::now();
        state.store(GO, Ordering::Release);
        while left.load(Ordering::Acquire) > 0 {
            std::thread::park();
        }
        let last = *end.lock().unwrap_or_else(|e| e.into_inner());
        let ms = (last.unwrap_or_else(Instant::now) - start).as_secs_f64() * 1e3;
        let mut result = Ok(());
        for worker in spawned {
            let r = worker
                .join()
                .unwrap_or_else(|e| std::panic::resume_unwind(e));
            result = result.and(r);
        }
        result.map_err(failed).map(|()| (ms, Some(pool_ms)))
    })
}

/// A worker's part where the workers share one frame ([`render`]): the frame built in `builds` by
/// the worker given it, else waited for, spinning; then bands (`work`).
fn shared_frame<'f, const S: usize, const L: usize>(
    builds: Option<&'f mut FrameStorage<S, L, microray::render::Heap>>,
    frame: &'f std::sync::OnceLock<Result<Frame<'f, S, L>, microray::Error>>,
    broken: &AtomicBool,
    (scene, camera, options): (
        &'f microray::Scene<S, L>,
        &'f microray::Camera,
        RenderOptions,
    ),
    work: &impl Fn(&Frame<'_, S, L>),
) -> Result<(), microray::Error> {
    let made = match builds {
        Some(storage) => {
            // Were the build to panic, the others stop waiting for it.
            let _broken = Finally(|| {
                if frame.get().is_none() {
                    broken.store(true, Ordering::Release);
                }
            });
            frame.get_or_init(|| Frame::new(scene, camera, options, storage))
        }
        None => loop {
            if let Some(made) = frame.get() {
                break made;
            }
            if broken.load(Ordering::Acquire) {
                return Ok(());
            }
            std::thread::yield_now();
        },
    };
    made.as_ref().map(work).map_err(|&e| e)
}

/// Writes the stack a frame's render uses (its per-row candidate lists grow with the
/// capacity: about 147 KiB at the desktop's), as a renderer's threads have by their second
/// frame: the kernel's first touch of those pages is start-up, not rendering.
#[inline(never)]
fn touch_stack() {
    let mut stack = [0u8; 256 << 10];
    std::hint::black_box(&mut stack);
}

/// The PNG of `image` (8-bit RGB), encoded a row at a time: no copy of the image,
/// and its bytes in memory reserved fallibly, so that short memory is an error.
fn encode_png(w: u32, h: u32, image: &[Rgb888]) -> Result<Vec<u8>, Failure> {
    let mut sink = Fallible::default();
    let encoded = encode_into(&mut sink, w, h, image);
    match encoded {
        Ok(()) => Ok(sink.bytes),
        // The encoder passes the sink's error on as text: the sink's flag says what it was.
        Err(_) if sink.short => Err(Failure(1, "not enough memory for the PNG".into())),
        Err(e) => Err(Failure(1, format!("PNG encoding: {e}"))),
    }
}

fn encode_into(
    sink: &mut Fallible,
    w: u32,
    h: u32,
    image: &[Rgb888],
) -> Result<(), png::EncodingError> {
    let mut encoder = png::Encoder::new(sink, w, h);
    // RGB, opaque: an alpha channel of 255s would only add bytes to filter and compress.
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    // The fast level: ~10x the default's speed for ~1.2-1.4x its size on rendered scenes.
    encoder.set_compression(png::Compression::Fast);
    let mut writer = encoder.write_header()?;
    let mut stream = writer.stream_writer()?;
    let mut row = Vec::with_capacity(3 * w as usize);
    for pixels in image.chunks_exact(w as usize) {
        row.clear();
        row.extend(pixels.iter().flat_map(|p| [p.r(), p.g(), p.b()]));
        stream.write_all(&row)?;
    }
    stream.finish()?;
    writer.finish()
}

/// Bytes in a `Vec` whose failed allocation is an error (and `short`), not an abort.
#[derive(Default)]
struct Fallible {
    bytes: Vec<u8>,
    short: bool,
}

impl Write for Fallible {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.bytes.try_reserve(buf.len()).is_err() {
            self.short = true;
            return Err(std::io::ErrorKind::OutOfMemory.into());
        }
        self.bytes.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// Runs its closure when dropped.
struct Finally<F: FnMut()>(F);

impl<F: FnMut()> Drop for Finally<F> {
    fn drop(&mut self) {
        (self.0)();
    }
}

const WAIT: u8 = 0;
const GO: u8 = 1;
const STOP: u8 = 2;

/// Runs `f` with a counter of rows done, shown as a progress bar of `total` rows on a terminal
/// once the work takes more than a second.
fn with_progress<T>(total: u32, f: impl FnOnce(&AtomicU32) -> T) -> T {
    let done = AtomicU32::new(0);
    let finished = AtomicBool::new(false);
    let show = std::io::stderr().is_terminal();
    std::thread::scope(|s| {
        let bar = show.then(|| s.spawn(|| progress(&done, &finished, total)));
        // Stops the progress thread however this scope is left (an error, a worker's panic),
        // and at once rather than after its sleep, which would be counted in the render time.
        let _stop_bar = Finally(|| {
            finished.store(true, Ordering::Relaxed);
            if let Some(bar) = &bar {
                bar.thread().unpark();
            }
        });
        f(&done)
    })
}

fn progress(done: &AtomicU32, finished: &AtomicBool, total: u32) {
    let start = Instant::now();
    let mut shown = false;
    loop {
        std::thread::park_timeout(Duration::from_millis(100));
        if finished.load(Ordering::Relaxed) {
            break;
        }
        if start.elapsed() < Duration::from_secs(1) {
            continue;
        }
        let d = done.load(Ordering::Relaxed) as u64;
        let total = total.max(1) as u64;
        let filled = (40 * d / total).min(40) as usize;
        eprint!(
            "\r[{}{}] {:3}%",
            "#".repeat(filled),
            " ".repeat(40 - filled),
            100 * d / total
        );
        shown = true;
    }
    if shown {
        eprint!("\r{}\r", " ".repeat(48));
    }
}

/// `n` magenta pixels, or exit 1 where the memory is short (a plain `vec!` would abort).
fn image_buffer(n: usize) -> Result<Vec<Rgb888>, Failure> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| {
        let mb = (n as f64 * std::mem::size_of::<Rgb888>() as f64 / 1e6).ceil();
        Failure(1, format!("not enough memory for the image ({mb} MB)"))
    })?;
    v.resize(n, Rgb888::MAGENTA);
    Ok(v)
}

/// Writes the PNG of `image` to `out` ([`write_file`]).
fn write_png(out: &Path, w: u32, h: u32, image: &[Rgb888]) -> Result<(), Failure> {
    output_target(out)?;
    let png = encode_png(w, h, image)?;
    write_file(out, png)
}

/// Writes `bytes` to a temporary file beside `out`, then renames it: a failed write leaves no
/// file and never touches an existing one.
fn write_file(out: &Path, bytes: Vec<u8>) -> Result<(), Failure> {
    let io = |e: &dyn std::fmt::Display| Failure(1, format!("{}: {e}", out.display()));
    let target = output_target(out)?;
    let name = target.file_name().ok_or_else(|| io(&"not a file name"))?;
    // Written beside the file it replaces and renamed over it: never a partial file under the
    // output's name, whatever stops the write.
    let tmp = target.with_file_name(format!(
        ".{}.{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let existing = std::fs::metadata(&target).ok();
    if existing.as_ref().is_some_and(|m| !m.is_file()) {
        // A device or a pipe (`/dev/stdout`, `/dev/full`): written to, never replaced.
        return std::fs::write(&target, bytes).map_err(|e| io(&e));
    }
    let keep_mode = existing.map(|m| m.permissions());
    let result = std::fs::write(&tmp, bytes)
        .and_then(|()| match keep_mode {
            Some(mode) => std::fs::set_permissions(&tmp, mode),
            None => Ok(()),
        })
        .and_then(|()| std::fs::rename(&tmp, &target));
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io(&e));
    }
    Ok(())
}

/// The output's format, by its extension: PNG (`.png`, or no extension, as a device such as
/// `/dev/stdout` has) or GIF (`.gif`). Any other is invalid input, not a file under a
/// misleading name.
fn check_format(out: &Path) -> Result<Format, Failure> {
    match out.extension().map(|e| e.to_string_lossy()) {
        None => Ok(Format::Png),
        Some(ext) if ext.eq_ignore_ascii_case("png") => Ok(Format::Png),
        Some(ext) if ext.eq_ignore_ascii_case("gif") => Ok(Format::Gif),
        Some(ext) => Err(Failure(
            2,
            format!(
                "{}: cannot write .{ext} images (name it .png, or .gif for a GIF)",
                out.display()
            ),
        )),
    }
}

/// The file that writing to `out` replaces, as a plain write would treat it: a symlink's
/// target (so the link stays a link), and an error for a directory or a read-only file, which
/// a write could not replace. Checked before rendering too, so a long render does not end in
/// an error it could have given at the start.
fn output_target(out: &Path) -> Result<PathBuf, Failure> {
    let fail = |why: &str| Failure(1, format!("{}: {why}", out.display()));
    let target = match std::fs::symlink_metadata(out) {
        Ok(m) if m.file_type().is_symlink() => match std::fs::canonicalize(out) {
            Ok(t) => t,
            // A dangling link: its target is created, as a write through it would.
            Err(_) => {
                let link = std::fs::read_link(out).map_err(|e| fail(&e.to_string()))?;
                out.parent().unwrap_or(Path::new("")).join(link)
            }
        },
        _ => out.to_path_buf(),
    };
    match std::fs::metadata(&target) {
        Ok(m) if m.is_dir() => Err(fail("is a directory")),
        Ok(m) if m.permissions().readonly() => Err(fail("read-only file (not replaced)")),
        _ => Ok(target),
    }
}

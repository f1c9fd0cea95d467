//! microray on a Cortex-M in QEMU: renders the benchmark scene of `scene.rs` without a
//! framebuffer, twice:
//!
//! 1. through `Frame::draw` into [`scene::CrcDisplay`], which folds every `Rgb888` pixel into a
//!    CRC-32 (`crc32=`) — the pass that is timed for `instructions_per_pixel=`;
//! 2. row by row, ordered-dithered, into a one-row `Rgb565` strip buffer (`crc32_rgb565=`).
//!
//! It prints `key=value` lines over semihosting and exits QEMU with status 0 only when both
//! CRCs equal the values committed in `scene.rs` (which the host test also checks).
//!
//! Instructions are counted, not cycles: QEMU runs with `-icount shift=0`, so its virtual clock
//! advances a fixed time per instruction, and SysTick (24 bits, wraps counted in its interrupt)
//! measures that clock. A calibration loop of exactly 2 000 000 instructions converts SysTick
//! ticks into instructions, whatever the board's clock frequency.
//!
//! The stack is painted with a pattern before rendering; the deepest overwritten word gives
//! `stack_bytes=`. Scene, camera, frame and strip live in statics (`.bss`), not on the stack.
#![no_std]
#![no_main]

mod board;
mod scene;

use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use embedded_graphics::pixelcolor::Rgb565;
use microray::render::Small;
use microray::{Camera, Frame, FrameStorage};

use board::{exit, paint_stack, stack_high_water, start_clock, ticks};
use scene::{BenchScene, HEIGHT, LIGHTS, SPHERES, STRIP_ROWS, WIDTH};

#[cfg(target_abi = "eabihf")]
const BOARD: &str = "mps2-an386";
#[cfg(not(target_abi = "eabihf"))]
const BOARD: &str = "microbit";

/// The scene, built in place by `setup` (const-initialised empty: no copy on the stack).
static mut SCENE: BenchScene = BenchScene::new();
/// The frame's per-frame tables, in a static as the scene.
type Storage = FrameStorage<SPHERES, LIGHTS, Small>;
static mut STORAGE: Storage = FrameStorage::small();

/// The strip buffer: one `Rgb565` row, the firmware's only pixel memory (in `.bss`).
static mut STRIP: [Rgb565; WIDTH as usize * STRIP_ROWS] =
    [Rgb565::new(0, 0, 0); WIDTH as usize * STRIP_ROWS];

/// Set-up failed (it cannot with this scene): report it and exit QEMU with a failure status.
fn fail(what: &str, e: microray::Error) -> ! {
    hprintln!("error={}: {}", what, e);
    exit(false)
}

/// Builds scene, camera and frame in statics: the only code allowed to panic (it does not, with
/// this scene). Kept out of `main` so that its temporaries leave the stack before rendering.
#[inline(never)]
fn setup() -> &'static Frame<'static, SPHERES, LIGHTS> {
    // SAFETY: the only reference ever made to SCENE (setup runs once).
    let scene: &'static mut BenchScene = unsafe { &mut *addr_of_mut!(SCENE) };
    scene::build_scene(scene).unwrap_or_else(|e| fail("scene", e));
    let scene: &'static BenchScene = scene;
    let camera: &'static Camera = match scene::camera() {
        Ok(c) => cortex_m::singleton!(: Camera = c).unwrap_or_else(|| exit(false)),
        Err(e) => fail("camera", e),
    };
    // SAFETY: the only reference ever made to STORAGE (setup runs once).
    let storage: &'static mut Storage = unsafe { &mut *addr_of_mut!(STORAGE) };
    match Frame::new(scene, camera, scene::options(), storage) {
        Ok(f) => cortex_m::singleton!(: Frame<'static, SPHERES, LIGHTS> = f)
            .unwrap_or_else(|| exit(false)),
        Err(e) => fail("frame", e),
    }
}

#[entry]
fn main() -> ! {
    paint_stack();
    let cp = cortex_m::Peripherals::take().unwrap_or_else(|| exit(false));
    // Calibration: SysTick ticks per 2 000 000 instructions.
    let calib = start_clock(cp.SYST);

    let frame = setup();
    // SAFETY: the only reference ever made to STRIP (main runs once and never returns).
    let strip = unsafe { &mut *addr_of_mut!(STRIP) };
    let setup_stack = stack_high_water();
    // Repaint: from here on the high-water mark is the render passes' (plus main's small frame).
    paint_stack();

    // Pass 1: Frame::draw → CRC display (timed).
    let t0 = ticks();
    let (crc, pixels) = scene::crc_rgb888::<WIDTH, HEIGHT, SPHERES, LIGHTS>(frame);
    let t1 = ticks();
    // Pass 2: dithered Rgb565 strip.
    let crc565 = scene::crc_rgb565_dithered(frame, strip).unwrap_or_else(|e| fail("strip", e));
    let t2 = ticks();
    let render_stack = stack_high_water();

    let to_instr = |dt: u64| dt * 2_000_000 / calib;
    let instructions = to_instr(t1 - t0);
    let per_pixel_x10 = instructions * 10 / pixels as u64;
    hprintln!("board={}", BOARD);
    hprintln!("width={}", WIDTH);
    hprintln!("height={}", HEIGHT);
    hprintln!("pixels={}", pixels);
    hprintln!("crc32={:08x}", crc);
    hprintln!("crc32_expected={:08x}", scene::EXPECTED_CRC32);
    hprintln!("crc32_rgb565={:08x}", crc565);
    hprintln!("crc32_rgb565_expected={:08x}", scene::EXPECTED_CRC32_RGB565);
    hprintln!("systick_ticks_per_2M_instructions={}", calib);
    hprintln!("instructions={}", instructions);
    hprintln!(
        "instructions_per_pixel={}.{}",
        per_pixel_x10 / 10,
        per_pixel_x10 % 10
    );
    hprintln!("strip_instructions={}", to_instr(t2 - t1));
    hprintln!("stack_bytes={}", setup_stack.max(render_stack));
    hprintln!("render_stack_bytes={}", render_stack);
    let ok = crc == scene::EXPECTED_CRC32
        && crc565 == scene::EXPECTED_CRC32_RGB565
        && pixels == WIDTH * HEIGHT;
    hprintln!("crc_ok={}", if ok { 1 } else { 0 });
    exit(ok)
}

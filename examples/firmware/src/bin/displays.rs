//! microray's display paths on a Cortex-M in QEMU, on the benchmark scene of `scene.rs`:
//!
//! 1. `Frame::draw` into a digest display: one window, and the digest of the plain image;
//! 2. `Frame::draw_progressive` into the same: its final image's digest must equal the plain
//!    one, every pixel traced once (timed: `progressive_instructions_per_pixel=`);
//! 3. the same stopped by its callback after the first pass: 1/64 of the pixels;
//! 4. `Frame::draw_dithered` to `BinaryColor` and to `Gray4`: one window each, CRC-32s equal
//!    to the host's (committed in `displays.rs`).
//!
//! The stack is painted before the draws: `displays_stack_bytes=` is their high-water mark.
//! Prints `key=value` lines and exits QEMU with status 0 only when every check holds.
#![no_std]
#![no_main]

#[path = "../board.rs"]
mod board;
#[path = "../displays.rs"]
mod displays;
#[allow(dead_code)]
#[path = "../scene.rs"]
mod scene;

use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use microray::render::Small;
use microray::{Camera, Frame, FrameStorage};

use board::{exit, paint_stack, stack_high_water, start_clock, ticks};
use scene::{BenchScene, HEIGHT, LIGHTS, SPHERES, WIDTH};

static mut SCENE: BenchScene = BenchScene::new();
static mut STORAGE: FrameStorage<SPHERES, LIGHTS, Small> = FrameStorage::small();
static mut CAMERA: Option<Camera> = None;
static mut FRAME: Option<Frame<'static, SPHERES, LIGHTS>> = None;

/// Builds scene, camera and frame in statics, out of line: its temporaries leave the stack
/// before the draws, whose high-water mark is measured.
#[inline(never)]
fn setup() -> &'static Frame<'static, SPHERES, LIGHTS> {
    // SAFETY: the only references ever made to these statics (setup runs once).
    let (scene, camera, storage, frame) = unsafe {
        (
            &mut *addr_of_mut!(SCENE),
            &mut *addr_of_mut!(CAMERA),
            &mut *addr_of_mut!(STORAGE),
            &mut *addr_of_mut!(FRAME),
        )
    };
    if scene::build_scene(scene).is_err() {
        exit(false);
    }
    let camera: &'static Camera = camera.insert(scene::camera().unwrap_or_else(|_| exit(false)));
    let f = Frame::new(scene, camera, scene::options(), storage).unwrap_or_else(|_| exit(false));
    frame.insert(f)
}

#[entry]
fn main() -> ! {
    let cp = cortex_m::Peripherals::take().unwrap_or_else(|| exit(false));
    let calib = start_clock(cp.SYST);
    let frame = setup();
    let n = WIDTH * HEIGHT;
    // From here on the high-water mark is the display paths' (plus main's small frame).
    paint_stack();
    let to_instr = |dt: u64| dt * 2_000_000 / calib;

    let t0 = ticks();
    let plain = displays::plain_digest(frame);
    let t1 = ticks();
    let (prog, last, calls) = displays::progressive_digest(frame);
    let t2 = ticks();
    let (stopped, at) = displays::progressive_stopped(frame);
    let (crc1, px1, win1) = displays::crc_binary(frame);
    let (crc4, px4, win4) = displays::crc_gray4(frame);
    let stack = stack_high_water();

    let per_px = |dt: u64| to_instr(dt) * 10 / n as u64;
    let (plain_ipp, prog_ipp) = (per_px(t1 - t0), per_px(t2 - t1));
    hprintln!("draw_windows={}", plain.windows);
    hprintln!("plain_digest={:08x}{:08x}", plain.sum, plain.xor);
    hprintln!("progressive_digest={:08x}{:08x}", prog.sum, prog.xor);
    hprintln!("progressive_final_pixels={}", prog.pixels);
    hprintln!("progressive_blocks={}", prog.blocks);
    hprintln!("progressive_rows={}", prog.windows);
    hprintln!("progressive_callbacks={}", calls);
    hprintln!("progressive_stopped_traced={}", at.traced);
    hprintln!(
        "plain_instructions_per_pixel={}.{}",
        plain_ipp / 10,
        plain_ipp % 10
    );
    hprintln!(
        "progressive_instructions_per_pixel={}.{}",
        prog_ipp / 10,
        prog_ipp % 10
    );
    hprintln!("crc32_binary={:08x}", crc1);
    hprintln!("crc32_gray4={:08x}", crc4);
    hprintln!("displays_stack_bytes={}", stack);
    let ok = plain.windows == 1
        && plain.blocks == 0
        && plain.pixels == n
        && prog
            == Digest {
                windows: prog.windows,
                blocks: prog.blocks,
                ..plain
            }
        && prog.pixels == n
        && last.is_complete()
        && last.traced == n
        && stopped.pixels == at.traced
        && at.traced == WIDTH.div_ceil(8) * HEIGHT.div_ceil(8) + (WIDTH - 4).div_ceil(8)
        && crc1 == displays::EXPECTED_CRC32_BINARY
        && crc4 == displays::EXPECTED_CRC32_GRAY4
        && (px1, px4, win1, win4) == (n, n, 1, 1);
    hprintln!("displays_ok={}", ok as u32);
    exit(ok)
}

use displays::Digest;

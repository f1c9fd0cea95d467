//! microray on a Cortex-M in QEMU, on two well-known small ray tracers' scenes
//! (`figure_scenes.rs`: FTB's and tinyraytracer's, spheres only, 320×240): renders each through
//! `Frame::draw` into the CRC display of `scene.rs`, timed with SysTick as `firmware` times its
//! scene, and prints per scene `NAME_crc32=`, `NAME_instructions=` and
//! `NAME_instructions_per_pixel=` (QEMU -icount instructions, not cycles). Exits QEMU with
//! status 0 only when every CRC equals the one committed in `figure_scenes.rs`, which the host
//! test computes from the TOML files. `figures.sh` builds and runs it.
#![no_std]
#![no_main]

// This binary uses the clock and `exit`: the rest is for the others.
#[allow(dead_code)]
#[path = "../board.rs"]
mod board;
#[path = "../figure_scenes.rs"]
mod figure_scenes;
// The CRC display only; the benchmark scene's builders are `firmware`'s.
#[allow(dead_code)]
#[path = "../scene.rs"]
mod scene;

use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use microray::render::Small;
use microray::{Frame, FrameStorage};

use board::{exit, start_clock, ticks};
use figure_scenes::{FigureScene, FIGURES, HEIGHT, LIGHTS, SPHERES, WIDTH};

#[cfg(target_abi = "eabihf")]
const BOARD: &str = "mps2-an386";
#[cfg(not(target_abi = "eabihf"))]
const BOARD: &str = "microbit";

/// The scene, rebuilt in place for each figure (const-initialised empty: no copy on the stack).
static mut SCENE: FigureScene = FigureScene::new();
/// The frame's per-frame tables, refilled by each frame.
static mut STORAGE: FrameStorage<SPHERES, LIGHTS, Small> = FrameStorage::small();

/// Set-up failed: report it and exit QEMU with a failure status.
fn fail(name: &str, what: &str, e: microray::Error) -> ! {
    hprintln!("error={} {}: {}", name, what, e);
    exit(false)
}

#[entry]
fn main() -> ! {
    let cp = cortex_m::Peripherals::take().unwrap_or_else(|| exit(false));
    // Calibration: SysTick ticks per 2 000 000 instructions.
    let calib = start_clock(cp.SYST);
    // SAFETY: the only references ever made to SCENE and STORAGE (main runs once and never
    // returns).
    let (built, storage) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(STORAGE)) };
    hprintln!("board={}", BOARD);
    hprintln!("width={}", WIDTH);
    hprintln!("height={}", HEIGHT);
    hprintln!("systick_ticks_per_2M_instructions={}", calib);
    let mut differ = 0;
    for (k, figure) in FIGURES.iter().enumerate() {
        let name = figure.name;
        *built = FigureScene::new();
        let camera = figure_scenes::build(k, built).unwrap_or_else(|e| fail(name, "scene", e));
        let frame = Frame::new(built, &camera, figure_scenes::options(), storage)
            .unwrap_or_else(|e| fail(name, "frame", e));
        // Only the render is timed, as in `firmware`: not the set-up of scene and frame.
        let t0 = ticks();
        let (crc, pixels) = scene::crc_rgb888::<WIDTH, HEIGHT, SPHERES, LIGHTS>(&frame);
        let t1 = ticks();
        let instructions = (t1 - t0) * 2_000_000 / calib;
        let per_pixel_x10 = instructions * 10 / pixels.max(1) as u64;
        hprintln!("{}_file={}", name, figure.file);
        hprintln!("{}_crc32={:08x}", name, crc);
        hprintln!("{}_crc32_expected={:08x}", name, figure.crc32);
        hprintln!("{}_pixels={}", name, pixels);
        hprintln!("{}_instructions={}", name, instructions);
        hprintln!(
            "{}_instructions_per_pixel={}.{}",
            name,
            per_pixel_x10 / 10,
            per_pixel_x10 % 10
        );
        differ += (crc != figure.crc32 || pixels != WIDTH * HEIGHT) as u32;
    }
    hprintln!("figures={}", FIGURES.len());
    hprintln!("figures_differing={}", differ);
    exit(differ == 0)
}

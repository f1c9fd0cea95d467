//! microray on a Cortex-M in QEMU, on many scenes: renders each of `random_scenes.rs`'s
//! [`COUNT`] seeded scenes through `Frame::draw` into a CRC-32 and prints `scene_crc=K CRC` per
//! scene. Exits QEMU with status 0 only when every CRC equals the one committed in
//! `random_scenes.rs`, which the host test computes from the same file: the board and the host
//! then computed the same pixels on every scene.
#![no_std]
#![no_main]

// The clock is for the benchmark binaries.
#[allow(dead_code)]
#[path = "../board.rs"]
mod board;
#[path = "../random_scenes.rs"]
mod random_scenes;
#[allow(dead_code)]
#[path = "../scene.rs"]
mod scene;

use core::ptr::addr_of_mut;

use cortex_m_rt::entry;
use cortex_m_semihosting::hprintln;
use microray::render::Small;
use microray::FrameStorage;

use board::exit;
use random_scenes::{crc_of, RandomScene, COUNT, EXPECTED, LIGHTS, SPHERES};

/// The scene, rebuilt in place for each seed (const-initialised empty: no copy on the stack).
static mut SCENE: RandomScene = RandomScene::new();
/// The frame's per-frame tables, refilled by each frame.
static mut STORAGE: FrameStorage<SPHERES, LIGHTS, Small> = FrameStorage::small();

#[entry]
fn main() -> ! {
    // SAFETY: the only references ever made to SCENE and STORAGE (main runs once and never
    // returns).
    let (scene, storage) = unsafe { (&mut *addr_of_mut!(SCENE), &mut *addr_of_mut!(STORAGE)) };
    let mut differ = 0;
    for (k, &expected) in EXPECTED.iter().enumerate() {
        *scene = RandomScene::new();
        match crc_of(k, scene, storage) {
            Ok(crc) => {
                hprintln!("scene_crc={} {:08x}", k, crc);
                differ += (crc != expected) as u32;
            }
            Err(e) => {
                hprintln!("error=scene {}: {}", k, e);
                differ += 1;
            }
        }
    }
    hprintln!("scenes={}", COUNT);
    hprintln!("scenes_differing={}", differ);
    exit(differ == 0)
}

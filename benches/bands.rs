//! `cargo bench --bench bands -- [SCENE.toml ...]`: how the desktop renderer's band scheduler
//! (`examples/render`) would scale to 16 and 64 cores, from what one core measures.
//!
//! For each scene (default: bench/scenes/target.toml and target1080.toml) it times, on this
//! thread, every band of 8, 4 and 2 rows through `Frame::render_rows` (medians of `REPEATS`
//! passes after `WARMUP`, the band heights interleaved within each pass so that they see the
//! same load), and `Frame::new` in fresh storage (a worker's first frame: its page faults) and
//! in storage it has filled before. It then replays the renderer's scheduler on those band times:
//! every worker builds its own frame, then takes the next band in image order as soon as it is
//! free. The makespan of that replay, against one thread's, is the speed-up the scheduler
//! allows on `n` cores that each run as fast as this one; memory bandwidth, a shared cache and
//! the lock are left out (the lock is taken once a band, a few hundred times a frame). Rows 8,
//! 4 and 2 replay bands of one height; `queue` replays the renderer's own queue
//! (`examples/render/bands.rs`), whose heights fall towards the end of the image.
//! `bench/threads.sh` measures two real threads, to compare with the replay's `n = 2`.

use std::time::Instant;

use embedded_graphics::pixelcolor::Rgb888;
use microray::scene_file::{self, Desktop};
use microray::{Camera, Frame, FrameStorage, RenderOptions};

#[path = "../examples/render/bands.rs"]
#[allow(dead_code)]
mod bands;

const WARMUP: usize = 3;
const REPEATS: usize = 15;
const HEIGHTS: [usize; 3] = [8, 4, 2];
const CORES: [usize; 7] = [1, 2, 4, 8, 16, 32, 64];

type Storage = FrameStorage<{ scene_file::SPHERES }, { scene_file::LIGHTS }>;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// The makespan of `n` workers that each start after `new_ms` and take bands in order.
fn replay(bands: &[f64], n: usize, new_ms: f64) -> f64 {
    let mut free = vec![new_ms; n];
    for &b in bands {
        // The worker free first takes the next band (ties: any, the result is the same).
        let (k, _) = free
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .expect("n ≥ 1");
        free[k] += b;
    }
    free.into_iter().fold(0.0, f64::max)
}

fn main() {
    let scenes: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let scenes = if scenes.is_empty() {
        vec![
            "bench/scenes/target.toml".to_string(),
            "bench/scenes/target1080.toml".to_string(),
        ]
    } else {
        scenes
    };
    for path in scenes {
        let file: Box<Desktop> = scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
        measure(&path, &file.scene, &file.camera, file.options);
    }
}

fn measure(
    path: &str,
    scene: &microray::Scene<{ scene_file::SPHERES }, { scene_file::LIGHTS }>,
    camera: &Camera,
    options: RenderOptions,
) {
    let (w, h) = (camera.width() as usize, camera.height() as usize);
    let mut image = vec![Rgb888::new(0, 0, 0); w * h];
    let mut storage: Box<Storage> = Box::new(FrameStorage::new());
    // Per height, per band, the times of every pass.
    let mut times: Vec<Vec<Vec<f64>>> = HEIGHTS
        .iter()
        .map(|&rows| vec![Vec::new(); h.div_ceil(rows)])
        .collect();
    let (mut new_cold, mut new_warm) = (Vec::new(), Vec::new());
    // Fresh storages stay allocated until the end, so that each is new memory, whose pages the
    // first frame faults in (a freed one would be handed out again, its pages already there).
    let mut fresh: Vec<Box<Storage>> = Vec::new();
    for pass in 0..WARMUP + REPEATS {
        let keep = pass >= WARMUP;
        // A fresh storage, allocated before the clock as the renderer's workers do.
        fresh.push(Box::new(FrameStorage::new()));
        if let Some(new) = fresh.last_mut() {
            let t = Instant::now();
            Frame::new(scene, camera, options, new).expect("the file's options");
            if keep {
                new_cold.push(ms(t));
            }
        }
        let t = Instant::now();
        let frame = Frame::new(scene, camera, options, &mut storage).expect("the file's options");
        if keep {
            new_warm.push(ms(t));
        }
        for (hk, &rows) in HEIGHTS.iter().enumerate() {
            for (b, band) in image.chunks_mut(w * rows).enumerate() {
                let t = Instant::now();
                frame
                    .render_rows((b * rows) as u32, band)
                    .expect("whole rows inside the image");
                if keep {
                    times[hk][b].push(ms(t));
                }
            }
        }
    }
    let (cold, warm) = (median(new_cold), median(new_warm));
    println!("{path}: {w}x{h}; Frame::new {cold:.3} ms in fresh storage, {warm:.3} ms again");
    let mut header = String::from("| band rows | bands | one thread ms |");
    for n in CORES.iter().skip(1) {
        header += &format!(" {n} cores |");
    }
    println!("{header}");
    println!("|---:|---:|---:|{}", "---:|".repeat(CORES.len() - 1));
    for (hk, &rows) in HEIGHTS.iter().enumerate() {
        let bands: Vec<f64> = times[hk].iter().map(|t| median(t.clone())).collect();
        let one = replay(&bands, 1, cold);
        let mut line = format!("| {rows} | {} | {one:.2} |", bands.len());
        for &n in CORES.iter().skip(1) {
            line += &format!(" {:.2}× |", one / replay(&bands, n, cold));
        }
        println!("{line}");
    }
    // The renderer's queue: its bands are bands of the tables above (heights only fall, and
    // each band starts on a multiple of its height).
    let table = |rows: usize| HEIGHTS.iter().position(|&r| r == rows).map(|k| &times[k]);
    let queue = |n: usize| -> Vec<f64> {
        let mut row = 0;
        let mut bands = Vec::new();
        while row < h {
            let rows = bands::band_height(h - row, n);
            let t = table(rows).expect("a measured height");
            bands.push(median(t[row / rows].clone()));
            row += rows;
        }
        bands
    };
    let one = replay(&queue(1), 1, cold);
    let mut line = format!("| queue | | {one:.2} |");
    for &n in CORES.iter().skip(1) {
        line += &format!(" {:.2}× |", one / replay(&queue(n), n, cold));
    }
    println!("{line}");
    println!();
}

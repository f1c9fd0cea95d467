//! The firmware check: the microcontroller and the host compute identical pixels.
//!
//! `examples/firmware/src/scene.rs` is compiled here unchanged (the firmware compiles the same
//! file), and the CRC-32 of its frame must equal the constant committed there, which is what the
//! firmware prints under QEMU on both boards. The QEMU run itself is the ignored test below.

#[allow(dead_code)]
#[path = "../examples/firmware/src/displays.rs"]
mod displays;
#[path = "../examples/firmware/src/random_scenes.rs"]
mod random_scenes;
#[allow(dead_code)]
#[path = "../examples/firmware/src/scene.rs"]
mod scene;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::Frame;

fn frame_crcs() -> (u32, u32, u32) {
    let mut scene = scene::BenchScene::new();
    scene::build_scene(&mut scene).unwrap();
    let camera = scene::camera().unwrap();
    let mut storage = microray::FrameStorage::new();
    let frame = Frame::new(&scene, &camera, scene::options(), &mut storage).unwrap();
    let (crc, pixels) = scene::crc_rgb888::<
        { scene::WIDTH },
        { scene::HEIGHT },
        { scene::SPHERES },
        { scene::LIGHTS },
    >(&frame);
    let mut strip = vec![
        embedded_graphics::pixelcolor::Rgb565::new(0, 0, 0);
        scene::WIDTH as usize * scene::STRIP_ROWS
    ];
    let crc565 = scene::crc_rgb565_dithered(&frame, &mut strip).unwrap();
    (crc, crc565, pixels)
}

#[test]
fn host_crc_matches_the_committed_firmware_crc() {
    let (crc, crc565, pixels) = frame_crcs();
    assert_eq!(pixels, scene::WIDTH * scene::HEIGHT);
    assert_eq!(crc, scene::EXPECTED_CRC32, "host crc32={crc:08x}");
    assert_eq!(
        crc565,
        scene::EXPECTED_CRC32_RGB565,
        "host crc32_rgb565={crc565:08x}"
    );
}

/// The display paths of the `displays` firmware, on the host: the plain draw is one window,
/// the progressive draw ends in the plain image (by digest; `tests/display.rs` compares
/// every pixel), and the dithered draws give the CRCs committed in `displays.rs`.
#[test]
fn host_display_paths_match_the_committed_values() {
    let mut scene = scene::BenchScene::new();
    scene::build_scene(&mut scene).unwrap();
    let camera = scene::camera().unwrap();
    let mut storage = microray::FrameStorage::new();
    let frame = Frame::new(&scene, &camera, scene::options(), &mut storage).unwrap();
    let n = scene::WIDTH * scene::HEIGHT;
    let plain = displays::plain_digest(&frame);
    assert_eq!((plain.windows, plain.blocks, plain.pixels), (1, 0, n));
    let (prog, last, _) = displays::progressive_digest(&frame);
    assert!(last.is_complete());
    assert_eq!((prog.sum, prog.xor, prog.pixels), (plain.sum, plain.xor, n));
    let (crc1, px1, win1) = displays::crc_binary(&frame);
    let (crc4, px4, win4) = displays::crc_gray4(&frame);
    assert_eq!((px1, win1, px4, win4), (n, 1, n, 1));
    assert_eq!(
        crc1,
        displays::EXPECTED_CRC32_BINARY,
        "host crc32_binary={crc1:08x}"
    );
    assert_eq!(
        crc4,
        displays::EXPECTED_CRC32_GRAY4,
        "host crc32_gray4={crc4:08x}"
    );
}

/// Every seeded scene builds, renders the brute-force pixels, and has the CRC committed in
/// `random_scenes.rs`, which the `scenes` firmware checks on both boards (`run.sh`).
#[test]
fn random_scenes_match_the_committed_crcs() {
    use random_scenes::{build, crc_of, kind, RandomScene, COUNT, EXPECTED, HEIGHT, WIDTH};
    let mut storage = Box::new(microray::FrameStorage::small());
    let mut crcs = [0u32; COUNT];
    let (mut lit, mut mirrors, mut samples) = (0, 0, [0; 4]);
    for (k, crc) in crcs.iter_mut().enumerate() {
        let mut scene = RandomScene::new();
        *crc = crc_of(k, &mut scene, &mut storage)
            .unwrap_or_else(|e| panic!("scene {k} ({:?}): {e}", kind(k)));
        // The accelerated frame is the brute-force one (what `accelerated.rs` asserts on its
        // own scenes), so the CRCs pin down the model's pixels, not only agreement.
        let (camera, options) = build(k, &mut RandomScene::new()).unwrap();
        let frame = Frame::new(&scene, &camera, options, &mut storage).unwrap();
        let n = (WIDTH * HEIGHT) as usize;
        let (mut fast, mut brute) = (vec![Rgb888::BLACK; n], vec![Rgb888::BLACK; n]);
        frame.render_rows(0, &mut fast).unwrap();
        frame.render_rows_brute(0, &mut brute).unwrap();
        assert!(
            fast == brute,
            "scene {k} ({:?}): accelerated differs from brute force",
            kind(k)
        );
        // Not a flat image: the scene shows something.
        assert!(
            fast.iter().any(|&p| p != fast[0]),
            "scene {k} ({:?}) is flat",
            kind(k)
        );
        lit += !scene.lights().is_empty() as u32;
        let mirror = |m: &microray::Material| m.mirror != microray::Color::splat(0.0);
        mirrors += (scene.max_depth() > 0 && scene.materials().iter().any(mirror)) as u32;
        samples[options.samples as usize] += 1;
    }
    assert_eq!(lit as usize, COUNT);
    assert!(
        mirrors >= 7 && samples[1..].iter().all(|&n| n >= 15),
        "{mirrors} {samples:?}"
    );
    let differ: Vec<_> = (0..COUNT).filter(|&k| crcs[k] != EXPECTED[k]).collect();
    assert!(
        differ.is_empty(),
        "scenes {differ:?} differ; host CRCs:\n{}",
        crcs.iter()
            .map(|c| format!("0x{c:08x},"))
            .collect::<Vec<_>>()
            .join(" ")
    );
}

#[test]
fn crc32_is_the_standard_one() {
    // The check value of CRC-32/ISO-HDLC (zip, PNG).
    let mut c = scene::Crc32::new();
    c.update(b"123456789");
    assert_eq!(c.value(), 0xCBF4_3926);
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|d| d.join(program).is_file()))
}

/// Runs `examples/firmware/run.sh` for both boards (builds the firmware, runs it in QEMU, which
/// exits non-zero unless its CRCs equal the committed ones). Needs `qemu-system-arm` and the
/// targets `thumbv7em-none-eabihf` and `thumbv6m-none-eabi`.
#[test]
#[ignore = "needs qemu-system-arm; run with --ignored"]
fn firmware_in_qemu_prints_the_host_crc() {
    if !on_path("qemu-system-arm") {
        // A check that did not run must not be reported as passed: fail with the reason. (A
        // plain `cargo test` never gets here: the test is ignored.)
        println!("skipped: qemu-system-arm not found");
        panic!("skipped: qemu-system-arm not found (the firmware check did not run)");
    }
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/firmware/run.sh");
    for board in ["m4f", "m0"] {
        let out = std::process::Command::new(script)
            .arg(board)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        println!("{stdout}{}", String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "run.sh {board} failed");
        let crc = format!("crc32={:08x}", scene::EXPECTED_CRC32);
        assert!(
            stdout.lines().any(|l| l == crc),
            "run.sh {board} did not print {crc}"
        );
    }
}

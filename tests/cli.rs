//! The desktop renderer as a user runs it: output, exit codes, and that a failure never leaves
//! a PNG behind or touches an existing one.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::cli::{fails, fails_as, renderer, run, scratch, stderr};
use microray::scene_file;

#[test]
fn renders_a_scene_and_reports_the_time() {
    let dir = scratch("ok");
    let out = dir.join("flat.png");
    let o = run(&[
        "tests/data/flat.toml",
        "-o",
        out.to_str().unwrap(),
        "--threads",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains(&format!("wrote {} (160x120)", out.display())),
        "{stdout}"
    );
    for line in ["scene file: ", "render: "] {
        assert!(
            stdout
                .lines()
                .any(|l| l.starts_with(line) && l.ends_with(" ms")),
            "{stdout}"
        );
    }
    assert!(
        stderr(&o).is_empty(),
        "no progress bar when stderr is not a terminal: {}",
        stderr(&o)
    );
    let png = tiny_skia::Pixmap::load_png(&out).unwrap();
    assert_eq!((png.width(), png.height()), (160, 120));
    let want = tiny_skia::Pixmap::load_png("tests/data/flat.png").unwrap();
    let off = png
        .data()
        .iter()
        .zip(want.data())
        .filter(|(a, b)| a.abs_diff(**b) > 1)
        .count();
    assert_eq!(off, 0);
}

#[test]
fn size_and_sample_overrides() {
    let dir = scratch("override");
    let out = dir.join("small.png");
    let o = run(&[
        "tests/data/lit.toml",
        "-o",
        out.to_str().unwrap(),
        "--width",
        "40",
        "--height",
        "30",
        "--samples",
        "2",
        "--threads",
        "1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = tiny_skia::Pixmap::load_png(&out).unwrap();
    assert_eq!((png.width(), png.height()), (40, 30));
}

#[test]
fn the_demo_renders_without_a_scene() {
    let dir = scratch("demo");
    let out = dir.join("demo.png");
    let o = run(&[
        "-o",
        out.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(out.exists());
}

#[test]
fn invalid_input_exits_2_and_writes_nothing() {
    let dir = scratch("bad");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[sphere]]\ncenter = [0, 0, 0]\nradius = 0\n").unwrap();
    let bad = bad.to_str().unwrap();
    fails(
        &dir,
        &[bad],
        2,
        "bad.toml: line 6: sphere[0].radius: radius must be finite and > 0",
    );
    fails(
        &dir,
        &["tests/data/flat.toml", "--width", "0"],
        2,
        "--width",
    );
    fails(
        &dir,
        &["tests/data/flat.toml", "--height", "20000"],
        2,
        "--height",
    );
    fails(
        &dir,
        &["tests/data/flat.toml", "--samples", "17"],
        2,
        "--samples",
    );
    fails(
        &dir,
        &["tests/data/flat.toml", "--threads", "0"],
        2,
        "--threads",
    );
    fails(&dir, &["tests/data/flat.toml", "--bogus"], 2, "--bogus");
    // Bytes that are not text: invalid input, located, not an I/O failure.
    let binary = dir.join("binary.toml");
    std::fs::write(&binary, b"[camera]\neye = [0, 0, 5]\n\xc3\x28 = 1\n").unwrap();
    fails(
        &dir,
        &[binary.to_str().unwrap()],
        2,
        "binary.toml: line 3: not UTF-8 text (byte offset 25)",
    );
    let noise: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    assert!(std::str::from_utf8(&noise).is_err());
    let noise_file = dir.join("noise.toml");
    std::fs::write(&noise_file, &noise).unwrap();
    fails(&dir, &[noise_file.to_str().unwrap()], 2, "not UTF-8 text");
    // An empty file is text: the error names what is missing.
    let empty = dir.join("empty.toml");
    std::fs::write(&empty, b"").unwrap();
    fails(&dir, &[empty.to_str().unwrap()], 2, "empty.toml");
    let single = stderr(&run(&[bad, "-o", dir.join("x.png").to_str().unwrap()]));
    assert_eq!(single.trim_end().lines().count(), 1, "{single}");
}

/// The renderer writes PNG: an output named for another format is invalid input that names
/// the extension, found before rendering, with nothing written and an existing file kept.
/// `.PNG` and a name without an extension (as a device has) get PNG.
#[test]
fn an_output_of_another_format_is_an_error() {
    let dir = scratch("format");
    for (name, ext) in [
        ("out.jpg", ".jpg"),
        ("out.png.bmp", ".bmp"),
        ("a.b/out.webp", ".webp"),
    ] {
        let out = dir.join(name);
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        std::fs::write(&out, b"precious").unwrap();
        let o = run(&["tests/data/flat.toml", "-o", out.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.lines().count() == 1 && err.contains(&format!("cannot write {ext} images")),
            "{name}: {err}"
        );
        assert_eq!(std::fs::read(&out).unwrap(), b"precious", "{name}");
        std::fs::remove_file(&out).unwrap();
    }
    let left = walk(&dir);
    assert!(left.is_empty(), "files left behind: {left:?}");
    for name in ["OUT.PNG", "out"] {
        let out = dir.join(name);
        let o = run(&["tests/data/flat.toml", "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let png = std::fs::read(&out).unwrap();
        assert_eq!(png_size(&png), (160, 120), "{name}");
    }
}

/// Every file under `dir`, at any depth (directories themselves left out).
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut files = vec![];
    for e in std::fs::read_dir(dir).unwrap() {
        let path = e.unwrap().path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path);
        }
    }
    files
}

#[test]
fn io_failures_exit_1() {
    let dir = scratch("io");
    fails(&dir, &["no/such/scene.toml"], 1, "no/such/scene.toml");
    // A directory where the scene should be: it cannot be read.
    fails(&dir, &["tests/data"], 1, "tests/data");
    // the output directory does not exist: nothing is written anywhere
    let o = run(&[
        "tests/data/flat.toml",
        "-o",
        dir.join("missing/dir/out.png").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("out.png"));
}

/// The output is replaced as a plain write would replace it: through a symlink (the link kept),
/// keeping an existing file's mode, and never over a read-only file or a directory.
#[cfg(unix)]
#[test]
fn the_output_is_written_as_a_plain_write_would() {
    use std::os::unix::fs::{symlink, PermissionsExt};
    let dir = scratch("output");
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let png = |p: &Path| std::fs::read(p).unwrap().starts_with(b"\x89PNG");

    let read_only = dir.join("read-only.png");
    std::fs::write(&read_only, b"precious").unwrap();
    std::fs::set_permissions(&read_only, std::fs::Permissions::from_mode(0o444)).unwrap();
    let o = run(&["tests/data/flat.toml", "-o", read_only.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("read-only.png: read-only file"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(&read_only).unwrap(), b"precious");
    assert_eq!(mode(&read_only), 0o444);

    let private = dir.join("private.png");
    std::fs::write(&private, b"old").unwrap();
    std::fs::set_permissions(&private, std::fs::Permissions::from_mode(0o600)).unwrap();
    let o = run(&["tests/data/flat.toml", "-o", private.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(png(&private));
    assert_eq!(mode(&private), 0o600);

    let sub = dir.join("sub");
    std::fs::create_dir(&sub).unwrap();
    let real = sub.join("real.png");
    std::fs::write(&real, b"old").unwrap();
    let link = dir.join("link.png");
    symlink("sub/real.png", &link).unwrap();
    let o = run(&["tests/data/flat.toml", "-o", link.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(png(&real));

    let o = run(&["tests/data/flat.toml", "-o", sub.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("is a directory"), "{}", stderr(&o));

    // A device is written to, not replaced: a full one is an I/O failure, and stays a device.
    let full = Path::new("/dev/full");
    if full.exists() {
        use std::os::unix::fs::FileTypeExt;
        let o = run(&["tests/data/flat.toml", "-o", "/dev/full"]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("/dev/full: No space left"),
            "{}",
            stderr(&o)
        );
        assert!(std::fs::metadata(full)
            .unwrap()
            .file_type()
            .is_char_device());
    }

    let left: Vec<_> = walk(&dir)
        .into_iter()
        .filter(|p| p.to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// A render stopped by SIGINT or SIGTERM leaves neither a PNG nor a temporary file.
#[cfg(unix)]
#[test]
fn an_interrupted_render_leaves_nothing() {
    for signal in ["INT", "TERM"] {
        let dir = scratch(&format!("signal-{signal}"));
        let out = dir.join("big.png");
        let mut child = Command::new(renderer())
            .args(["tests/data/lit.toml", "--width", "8000", "--height", "8000"])
            .args([
                "--samples",
                "4",
                "--threads",
                "1",
                "-o",
                out.to_str().unwrap(),
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(500));
        let killed = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let status = child.wait().unwrap();
        assert!(!status.success(), "SIG{signal}: the render finished first");
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert!(left.is_empty(), "SIG{signal} left {left:?}");
    }
}

/// The width and height in a PNG's header.
fn png_size(png: &[u8]) -> (u32, u32) {
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && &png[12..16] == b"IHDR");
    let be = |i: usize| u32::from_be_bytes(png[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The largest image the renderer accepts renders; one pixel more is invalid input.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "a 16384² render takes minutes unoptimised: run with --release"
)]
fn the_largest_image_renders_and_one_more_is_an_error() {
    let dir = scratch("largest");
    let out = dir.join("largest.png");
    let size = microray::camera::MAX_SIZE.to_string();
    let o = run(&[
        "tests/data/flat.toml",
        "--width",
        &size,
        "--height",
        &size,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(&out).unwrap();
    assert_eq!(
        png_size(&png),
        (microray::camera::MAX_SIZE, microray::camera::MAX_SIZE)
    );
    std::fs::remove_file(&out).unwrap();
    let over = (microray::camera::MAX_SIZE + 1).to_string();
    fails(
        &dir,
        &["tests/data/flat.toml", "--width", &over],
        2,
        "width",
    );
}

/// Memory too short for the image is an error (exit 1) that leaves the output as it was, not
/// an abort; the largest image, encoded a row at a time, needs little more than the image
/// itself. Run under limits of the address space, on one thread so that no worker's stack
/// counts.
#[cfg(target_os = "linux")]
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "a 16384² render takes minutes unoptimised: run with --release"
)]
fn short_memory_is_an_error_not_an_abort() {
    let dir = scratch("memory");
    let size = microray::camera::MAX_SIZE.to_string();
    let args = ["tests/data/flat.toml", "--width", &size, "--height", &size];
    let limited = |limit_kb: &str, args: &[&str]| {
        Command::new("sh")
            .args(["-c", &format!("ulimit -v {limit_kb} && exec \"$0\" \"$@\"")])
            .arg(renderer())
            .args(["--threads", "1"])
            .args(args)
            .output()
            .unwrap()
    };
    // The image (1 074 MB) does not fit in 1 GB.
    fails_as(
        &dir,
        &args,
        1,
        "not enough memory for the image (1074 MB)",
        |all| limited("1000000", all),
    );
    // In 1.3 GB the image, its PNG and the program fit.
    let out = dir.join("largest.png");
    let o = limited(
        "1300000",
        &[&args[..], &["-o", out.to_str().unwrap()]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        png_size(&std::fs::read(&out).unwrap()),
        (microray::camera::MAX_SIZE, microray::camera::MAX_SIZE)
    );
}

/// A disk that fills while the PNG is written: exit 1 with the system's message, the existing
/// output as it was, no temporary file. On a 64 KiB tmpfs mounted in a user namespace
/// (`unshare`); where none can be mounted, on `/dev/full`
/// (`the_output_is_written_as_a_plain_write_would`), and this test says so.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_exits_1_and_keeps_the_existing_output() {
    let dir = scratch("full");
    let mnt = dir.join("disk");
    std::fs::create_dir(&mnt).unwrap();
    // Inside the namespace: mount, put a 40 KB output there, render a PNG that does not fit in
    // the rest, and report what is left. The mount ends with the namespace.
    let script = r#"
        mount -t tmpfs -o size=64k tmpfs "$1" || exit 99
        head -c 40000 /dev/urandom > "$1/out.png"
        cp "$1/out.png" "$2/before.png"
        "$3" tests/data/lit.toml --width 640 --height 480 -o "$1/out.png"
        echo "code=$?"
        cmp -s "$1/out.png" "$2/before.png" && echo "output=kept"
        echo "files=$(ls -A "$1" | tr '\n' ' ')"
    "#;
    let o = Command::new("unshare")
        .args(["-rm", "sh", "-c", script, "sh"])
        .arg(&mnt)
        .arg(&dir)
        .arg(renderer())
        .output();
    let o = match o {
        Ok(o) if o.status.code() != Some(99) && o.status.success() => o,
        other => {
            eprintln!(
                "skipped: no tmpfs in a user namespace here ({other:?}); /dev/full is tested"
            );
            return;
        }
    };
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("code=1"), "{out}{}", stderr(&o));
    assert!(
        stderr(&o).contains("No space left on device"),
        "{}",
        stderr(&o)
    );
    assert!(out.contains("output=kept"), "{out}");
    assert!(out.contains("files=out.png \n"), "{out}");
}

/// A scene at the desktop capacities (`SPHERES` spheres, `LIGHTS` lights, shadows, a mirror) renders the
/// library's pixels; one sphere or one light more is invalid input naming the key.
#[test]
fn a_scene_at_the_capacities_renders_and_one_more_is_an_error() {
    let dir = scratch("capacity");
    // 96×72, or 24×18 unoptimised: there a pixel of this scene (every one a hit, 32 lights,
    // thousands of spheres near each shadow ray) costs ~25 ms, and 96×72 took 8 minutes.
    let (w, h) = if cfg!(debug_assertions) {
        (24, 18)
    } else {
        (96, 72)
    };
    let mut toml = format!(
        "[camera]\neye = [0, 0, 40]\nlook_at = [0, 0, 0]\n\n\
         [render]\nwidth = {w}\nheight = {h}\nshadows = true\nmax_depth = 2\n\n",
    );
    // A square grid of spheres 32 across in the plane z = 0, one near the middle a mirror.
    let side = scene_file::SPHERES.isqrt();
    assert_eq!(
        side * side,
        scene_file::SPHERES,
        "the grid fills the capacity"
    );
    let pitch = 32.0 / side as f32;
    for i in 0..scene_file::SPHERES {
        let (x, y) = (
            ((i % side) as f32 + 0.5) * pitch - 16.0,
            ((i / side) as f32 + 0.5) * pitch - 16.0,
        );
        let middle = side * side / 2 + side / 2;
        let mirror = if i == middle { "mirror = 0.8\n" } else { "" };
        toml += &format!(
            "[[sphere]]\ncenter = [{x}, {y}, {}]\nradius = {}\n{mirror}\n",
            (i % 7) as f32 * 0.1,
            0.45 * pitch
        );
    }
    // Point lights in a ring in front of the grid, every fourth one a directional light.
    for i in 0..32 {
        let a = i as f32 * core::f32::consts::TAU / 32.0;
        let (s, c) = (libm::sinf(a), libm::cosf(a));
        toml += &if i % 4 == 0 {
            format!("[[light]]\nkind = \"directional\"\ndirection = [{s}, {c}, -2]\nintensity = 0.03\n\n")
        } else {
            format!(
                "[[light]]\nkind = \"point\"\nposition = [{}, {}, 12]\nintensity = 0.03\n\n",
                20.0 * c,
                20.0 * s
            )
        };
    }
    let scene = dir.join("full.toml");
    std::fs::write(&scene, &toml).unwrap();
    let out = dir.join("full.png");
    let o = run(&[scene.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));

    let file: Box<microray::scene_file::Desktop> = microray::scene_file::load(&scene).unwrap();
    assert_eq!(
        (file.scene.spheres().len(), file.scene.lights().len()),
        (scene_file::SPHERES, scene_file::LIGHTS)
    );
    let camera = file.view.camera(w, h).unwrap();
    let mut storage = microray::FrameStorage::on_heap();
    let frame = microray::Frame::new(&file.scene, &camera, file.options, &mut storage).unwrap();
    let mut want = vec![embedded_graphics::pixelcolor::Rgb888::new(0, 0, 0); (w * h) as usize];
    frame.render(&mut want).unwrap();
    let png = tiny_skia::Pixmap::load_png(&out).unwrap();
    assert_eq!((png.width(), png.height()), (w, h));
    use embedded_graphics::pixelcolor::RgbColor;
    let got: Vec<[u8; 3]> = png
        .pixels()
        .iter()
        .map(|p| [p.red(), p.green(), p.blue()])
        .collect();
    let want: Vec<[u8; 3]> = want.iter().map(|p| [p.r(), p.g(), p.b()]).collect();
    assert!(got == want, "the renderer's PNG differs from Frame::render");
    let distinct: std::collections::HashSet<_> = want.iter().collect();
    assert!(
        distinct.len() > 50,
        "a flat image proves nothing: {} colours",
        distinct.len()
    );

    std::fs::remove_file(&out).unwrap();
    std::fs::write(
        &scene,
        format!("{toml}[[sphere]]\ncenter = [0, 0, 5]\nradius = 1\n"),
    )
    .unwrap();
    fails(
        &dir,
        &[scene.to_str().unwrap()],
        2,
        &format!(
            "{} spheres, more than the capacity of {}",
            scene_file::SPHERES + 1,
            scene_file::SPHERES
        ),
    );
    std::fs::write(
        &scene,
        format!("{toml}[[light]]\nkind = \"point\"\nposition = [0, 0, 9]\n"),
    )
    .unwrap();
    fails(
        &dir,
        &[scene.to_str().unwrap()],
        2,
        "33 lights, more than the capacity of 32",
    );
}

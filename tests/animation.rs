//! The desktop renderer's animations as a user runs them: every frame of an animated PNG is
//! `Frame::render`'s image for that frame's camera (an orbit, or the scene's keyframes), a GIF
//! has the frames in order, and bad input is a one-line error with nothing written.

mod common;

use embedded_graphics::pixelcolor::{Rgb888, RgbColor};
use microray::animation::Orbit;
use microray::scene_file::{self, Desktop};
use microray::{Camera, Frame, FrameStorage};

use common::cli::{fails, run, scratch, stderr};

/// `Frame::render`'s pixels for `camera`, as RGB bytes.
fn rendered(file: &Desktop, camera: &Camera) -> Vec<u8> {
    let mut storage = FrameStorage::on_heap();
    let frame = Frame::new(&file.scene, camera, file.options, &mut storage).unwrap();
    let mut px = vec![Rgb888::BLACK; (camera.width() * camera.height()) as usize];
    frame.render(&mut px).unwrap();
    px.iter().flat_map(|p| [p.r(), p.g(), p.b()]).collect()
}

/// The frames of an animated PNG, as RGB bytes, and its loop count and frame delay.
fn apng_frames(path: &std::path::Path) -> (Vec<Vec<u8>>, u32, (u16, u16)) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let control = reader.info().animation_control.expect("an animated PNG");
    let mut frames = Vec::new();
    let mut delay = (0, 0);
    for _ in 0..control.num_frames {
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        buf.truncate(info.buffer_size());
        let fc = reader
            .info()
            .frame_control
            .expect("a frame control per frame");
        delay = (fc.delay_num, fc.delay_den);
        frames.push(buf);
    }
    (frames, control.num_plays, delay)
}

#[test]
fn every_frame_of_an_orbit_is_the_render_of_its_camera() {
    let dir = scratch("orbit");
    let out = dir.join("orbit.png");
    let o = run(&[
        "tests/data/lit.toml",
        "--frames",
        "5",
        "--orbit",
        "120",
        "--width",
        "48",
        "--height",
        "36",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("5 frames"), "{stdout}");
    assert!(stdout.contains("render per frame: median"), "{stdout}");
    let (frames, plays, delay) = apng_frames(&out);
    assert_eq!(
        (frames.len(), plays),
        (5, 0),
        "five frames, looping forever"
    );
    assert!(delay.0 > 0 && delay.1 > 0);
    let file: Box<Desktop> = scene_file::load("tests/data/lit.toml").unwrap();
    let orbit = Orbit {
        view: file.view,
        degrees: 120.0,
    };
    for (k, got) in frames.iter().enumerate() {
        let camera = orbit.view(k as u32, 5).camera(48, 36).unwrap();
        assert!(*got == rendered(&file, &camera), "frame {k}");
    }
    // The frames differ: the camera moved.
    assert!(frames[0] != frames[1]);
}

#[test]
fn keyframes_from_the_scene_file_set_each_frame() {
    let dir = scratch("keys");
    let scene = dir.join("keys.toml");
    let base = std::fs::read_to_string("tests/data/lit.toml").unwrap();
    std::fs::write(
        &scene,
        format!(
            "{base}\n[[keyframe]]\nat = 0\n[[keyframe]]\nat = 0.5\neye = [3, 2, 4]\n\
             [[keyframe]]\nat = 1\neye = [-3, 1, 4]\nvfov = 30\n"
        ),
    )
    .unwrap();
    let out = dir.join("keys.png");
    let scene_path = scene.to_str().unwrap();
    let o = run(&[
        scene_path,
        "--frames",
        "4",
        "--width",
        "40",
        "--height",
        "30",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (frames, _, _) = apng_frames(&out);
    let file: Box<Desktop> = scene_file::load(scene_path).unwrap();
    assert_eq!(file.keyframes.keys().len(), 3);
    for (k, got) in frames.iter().enumerate() {
        let camera = file
            .keyframes
            .view(k as u32, 4)
            .unwrap()
            .camera(40, 30)
            .unwrap();
        assert!(*got == rendered(&file, &camera), "frame {k}");
    }
    // The last frame is the last key's view.
    let last = file.keyframes.keys()[2].view.camera(40, 30).unwrap();
    assert!(frames[3] == rendered(&file, &last));
    // Keyframes and --orbit both set the camera: an error.
    std::fs::remove_file(&out).unwrap();
    fails(
        &dir,
        &[scene_path, "--frames", "4", "--orbit", "90"],
        2,
        "--orbit",
    );
}

#[test]
fn a_gif_has_the_frames_in_order() {
    let dir = scratch("gif");
    let out = dir.join("orbit.gif");
    let args = [
        "tests/data/lit.toml",
        "--frames",
        "3",
        "--orbit",
        "60",
        "--width",
        "40",
        "--height",
        "30",
    ];
    let o = run(&[&args[..], &["-o", out.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(&out).unwrap())
        .unwrap();
    assert_eq!((decoder.width(), decoder.height()), (40, 30));
    let file: Box<Desktop> = scene_file::load("tests/data/lit.toml").unwrap();
    let orbit = Orbit {
        view: file.view,
        degrees: 60.0,
    };
    let expected: Vec<Vec<u8>> = (0..3)
        .map(|k| rendered(&file, &orbit.view(k, 3).camera(40, 30).unwrap()))
        .collect();
    let mut k = 0;
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert!(frame.delay > 0);
        let rgb: Vec<u8> = frame
            .buffer
            .chunks(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        // 256 colours a frame: near the frame's render, nearer than to any other frame's.
        let distance = |e: &Vec<u8>| {
            rgb.iter()
                .zip(e)
                .map(|(&a, &b)| (a as i32 - b as i32).unsigned_abs() as u64)
                .sum::<u64>()
        };
        let mean = distance(&expected[k]) as f64 / rgb.len() as f64;
        assert!(mean < 3.0, "frame {k}: mean difference {mean}");
        for (j, e) in expected.iter().enumerate() {
            if j != k {
                assert!(
                    distance(&expected[k]) < distance(e),
                    "frame {k} is nearer frame {j}"
                );
            }
        }
        k += 1;
    }
    assert_eq!(k, 3);
}

#[test]
fn bad_animation_input_exits_2_and_writes_nothing() {
    let dir = scratch("bad-animation");
    let lit = "tests/data/lit.toml";
    fails(&dir, &[lit, "--frames", "-3"], 2, "--frames");
    fails(&dir, &[lit, "--frames", "0"], 2, "--frames");
    fails(&dir, &[lit, "--frames", "x"], 2, "--frames");
    fails(&dir, &[lit, "--orbit", "30"], 2, "--orbit: needs --frames");
    fails(
        &dir,
        &[lit, "--frames", "3", "--orbit", "nan"],
        2,
        "--orbit",
    );
    fails(
        &dir,
        &[lit, "--frames", "3", "--orbit", "inf"],
        2,
        "--orbit",
    );
    let base = std::fs::read_to_string(lit).unwrap();
    for (name, keys, needle) in [
        (
            "single.toml",
            "[[keyframe]]\nat = 0\n",
            "keyframe: an animation by keyframes needs at least two",
        ),
        (
            "nan.toml",
            "[[keyframe]]\nat = 0\n[[keyframe]]\nat = nan\n",
            "keyframe[1].at",
        ),
        (
            "eye.toml",
            "[[keyframe]]\nat = 0\n[[keyframe]]\nat = 1\neye = [0, nan, 1]\n",
            "keyframe[1].eye",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, format!("{base}\n{keys}")).unwrap();
        fails(&dir, &[path.to_str().unwrap(), "--frames", "3"], 2, needle);
    }
    // An unknown extension, for an animation as for a still: named, nothing written.
    let o = run(&[
        lit,
        "--frames",
        "3",
        "-o",
        dir.join("a.webp").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("cannot write .webp images"),
        "{}",
        stderr(&o)
    );
    assert!(!dir.join("a.webp").exists());
    // Every one of these is one line.
    for args in [&[lit, "--frames", "-3"][..], &[lit, "--orbit", "x"]] {
        let o = run(args);
        assert_eq!(
            stderr(&o).trim_end().lines().count(),
            1,
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

//! The scene format: what it accepts, and a clear error naming field and line for everything it
//! rejects. The desktop renderer calls the same `scene_file::load`.

use microray::scene_file::{parse, Desktop, KEYFRAMES};
use microray::{Color, Encoding, Light, Vec3};

const CAMERA: &str = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n";

fn parse_desktop(text: &str) -> Result<Box<Desktop>, microray::scene_file::SceneError> {
    parse(text)
}

/// Parses `CAMERA + rest`, expects a rejection, and checks the error names `field` on `line`.
fn rejects(rest: &str, line: usize, field: &str, message: &str) {
    let text = format!("{CAMERA}{rest}");
    let err = parse_desktop(&text)
        .err()
        .unwrap_or_else(|| panic!("accepted:\n{text}"));
    assert_eq!(err.line, Some(line), "{err}");
    assert_eq!(err.field.as_deref(), Some(field), "{err}");
    assert!(err.message.contains(message), "{err}: expected {message:?}");
    assert!(!err.io);
    assert!(!err.to_string().contains('\n'), "one line: {err}");
}

#[test]
fn defaults_and_shorthands() {
    let text = format!(
        "{CAMERA}[[sphere]]\ncenter = [1, 2, 3]\nradius = 2\ndiffuse = 0.5\n\
         [[light]]\nkind = \"point\"\nposition = [0, 9, 0]\n\
         [[light]]\nkind = \"directional\"\ndirection = [0, -3, 0]\nintensity = [1, 0.5, 0]\n"
    );
    let f = parse_desktop(&text).unwrap();
    assert_eq!(
        (f.width, f.height, f.options.samples, f.options.encoding),
        (640, 480, 1, Encoding::Linear)
    );
    assert_eq!(f.view.up, Vec3::new(0.0, 1.0, 0.0));
    assert_eq!(f.view.vfov, 60.0);
    assert!(f.scene.shadows());
    assert_eq!(
        (f.scene.max_depth(), f.scene.ambient(), f.scene.background()),
        (3, Color::ZERO, Color::ZERO)
    );
    let m = f.scene.materials()[0];
    assert_eq!(
        (m.diffuse, m.specular, m.shininess, m.mirror),
        (Color::splat(0.5), Color::ZERO, 32.0, Color::ZERO)
    );
    assert_eq!(f.scene.spheres()[0].center, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(
        f.scene.lights()[0],
        Light::Point {
            position: Vec3::new(0.0, 9.0, 0.0),
            intensity: Color::ONE
        }
    );
    assert_eq!(
        f.scene.lights()[1],
        Light::Directional {
            direction: Vec3::new(0.0, -1.0, 0.0),
            intensity: Color::new(1.0, 0.5, 0.0)
        }
    );
}

#[test]
fn render_section() {
    let f = parse_desktop(&format!(
        "{CAMERA}[render]\nwidth = 32\nheight = 16\nbackground = [0.1, 0.2, 0.3]\nambient = 1\n\
         shadows = false\nmax_depth = 0\nsamples = 16\nencoding = \"srgb\"\n"
    ))
    .unwrap();
    assert_eq!(
        (f.width, f.height, f.camera.width(), f.camera.height()),
        (32, 16, 32, 16)
    );
    assert_eq!(f.scene.background(), Color::new(0.1, 0.2, 0.3));
    assert_eq!(f.scene.ambient(), Color::ONE);
    assert!(!f.scene.shadows());
    assert_eq!(
        (f.scene.max_depth(), f.options.samples, f.options.encoding),
        (0, 16, Encoding::Srgb)
    );
}

#[test]
fn unknown_keys() {
    rejects(
        "[render]\nwidht = 3\n",
        5,
        "render.widht",
        "unknown field `widht`",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\ncolour = 1\n",
        7,
        "sphere[0].colour",
        "unknown field",
    );
    rejects("[lights]\n", 4, "lights", "unknown field `lights`");
    rejects(
        "[[light]]\nkind = \"point\"\nposition = [0, 1, 0]\ndirection = [0, 1, 0]\n",
        7,
        "light[0].direction",
        "not allowed",
    );
}

#[test]
fn missing_fields() {
    let err = parse_desktop("[camera]\neye = [0, 0, 5]\n").unwrap_err();
    assert_eq!((err.line, err.field.as_deref()), (Some(1), Some("camera")));
    assert!(err.message.contains("missing field `look_at`"), "{err}");
    assert!(parse_desktop("")
        .unwrap_err()
        .message
        .contains("missing field `camera`"));
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n[[sphere]]\nradius = 1\n",
        7,
        "sphere[1]",
        "missing field `center`",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\n",
        4,
        "sphere[0]",
        "missing field `radius`",
    ); // the header line
    rejects(
        "[[light]]\nkind = \"point\"\n",
        4,
        "light[0].position",
        "missing",
    );
    rejects(
        "[[light]]\nkind = \"directional\"\n",
        4,
        "light[0].direction",
        "missing",
    );
    rejects(
        "[[light]]\nposition = [0, 1, 0]\n",
        4,
        "light[0]",
        "missing field `kind`",
    );
}

#[test]
fn wrong_types() {
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = \"big\"\n",
        6,
        "sphere[0].radius",
        "invalid type",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0]\nradius = 1\n",
        5,
        "sphere[0].center",
        "invalid length 2",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0, 0]\nradius = 1\n",
        5,
        "sphere[0].center",
        "invalid length",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\ndiffuse = \"red\"\n",
        7,
        "sphere[0].diffuse",
        "invalid type",
    );
    rejects("[render]\nwidth = 1.5\n", 5, "render.width", "invalid type");
    rejects(
        "[render]\nshadows = 1\n",
        5,
        "render.shadows",
        "invalid type",
    );
    rejects(
        "[render]\nencoding = \"gamma\"\n",
        5,
        "render.encoding",
        "\"linear\" or \"srgb\"",
    );
    rejects(
        "[[light]]\nkind = \"spot\"\nposition = [0, 1, 0]\n",
        5,
        "light[0].kind",
        "\"point\" or \"directional\"",
    );
}

#[test]
fn nan_and_infinity() {
    rejects(
        "[[sphere]]\ncenter = [0, nan, 0]\nradius = 1\n",
        5,
        "sphere[0].center",
        "finite",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = inf\n",
        6,
        "sphere[0].radius",
        "finite",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1e39\n",
        6,
        "sphere[0].radius",
        "f32 range",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nspecular = nan\n",
        7,
        "sphere[0].specular",
        "finite",
    );
    rejects(
        "[[light]]\nkind = \"point\"\nposition = [0, -inf, 0]\n",
        6,
        "light[0].position",
        "finite",
    );
    let err = parse_desktop("[camera]\neye = [0, 0, nan]\nlook_at = [0, 0, 0]\n").unwrap_err();
    assert_eq!(
        (err.line, err.field.as_deref()),
        (Some(2), Some("camera.eye"))
    );
}

#[test]
fn invalid_values() {
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 0\n",
        6,
        "sphere[0].radius",
        "> 0",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = -2\n",
        6,
        "sphere[0].radius",
        "> 0",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\ndiffuse = [0.5, -0.1, 0]\n",
        7,
        "sphere[0].diffuse",
        ">= 0",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmirror = -1\n",
        7,
        "sphere[0].mirror",
        ">= 0",
    );
    rejects(
        "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nshininess = 0\n",
        7,
        "sphere[0].shininess",
        "> 0",
    );
    rejects(
        "[render]\nbackground = [0, 0, -1]\n",
        5,
        "render.background",
        ">= 0",
    );
    rejects("[render]\nambient = -0.5\n", 5, "render.ambient", ">= 0");
    rejects(
        "[[light]]\nkind = \"point\"\nposition = [0, 1, 0]\nintensity = -1\n",
        7,
        "light[0].intensity",
        ">= 0",
    );
    rejects(
        "[[light]]\nkind = \"directional\"\ndirection = [0, 0, 0]\n",
        6,
        "light[0].direction",
        "zero",
    );
}

/// `refraction` (a colour, default 0) and `ior` (default 1.5, finite and > 0), checked like
/// every other field.
#[test]
fn glass_fields() {
    let text = format!(
        "{CAMERA}[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n\
         [[sphere]]\ncenter = [0, 3, 0]\nradius = 1\nrefraction = [0.9, 1, 0.8]\nior = 1.33\n"
    );
    let f = parse_desktop(&text).unwrap();
    let (plain, glass) = (f.scene.materials()[0], f.scene.materials()[1]);
    assert_eq!((plain.refraction, plain.ior), (Color::ZERO, 1.5));
    assert_eq!(
        (glass.refraction, glass.ior),
        (Color::new(0.9, 1.0, 0.8), 1.33)
    );
    let sphere = "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n";
    rejects(
        &format!("{sphere}refraction = -0.1\n"),
        7,
        "sphere[0].refraction",
        ">= 0",
    );
    rejects(
        &format!("{sphere}refraction = [0, nan, 0]\n"),
        7,
        "sphere[0].refraction",
        "finite",
    );
    rejects(&format!("{sphere}ior = 0\n"), 7, "sphere[0].ior", "> 0");
    rejects(&format!("{sphere}ior = -1.5\n"), 7, "sphere[0].ior", "> 0");
    rejects(
        &format!("{sphere}ior = inf\n"),
        7,
        "sphere[0].ior",
        "finite",
    );
    rejects(
        &format!("{sphere}ior = 1e39\n"),
        7,
        "sphere[0].ior",
        "f32 range",
    );
    rejects(
        &format!("{sphere}ior = \"glass\"\n"),
        7,
        "sphere[0].ior",
        "invalid type",
    );
}

#[test]
fn invalid_cameras() {
    let cases = [
        (
            "eye = [1, 2, 3]\nlook_at = [1, 2, 3]\n",
            3,
            "camera.look_at",
            "must differ",
        ),
        (
            "eye = [0, 5, 0]\nlook_at = [0, 0, 0]\n",
            1,
            "camera.up",
            "parallel",
        ),
        (
            "eye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 2]\n",
            4,
            "camera.up",
            "parallel",
        ),
        (
            "eye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 0]\n",
            4,
            "camera.up",
            "zero",
        ),
        (
            "eye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 0\n",
            4,
            "camera.vfov",
            "(0, 180)",
        ),
        (
            "eye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 180\n",
            4,
            "camera.vfov",
            "(0, 180)",
        ),
        (
            "eye = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = -10\n",
            4,
            "camera.vfov",
            "(0, 180)",
        ),
    ];
    for (body, line, field, msg) in cases {
        let err = parse_desktop(&format!("[camera]\n{body}")).unwrap_err();
        assert_eq!(
            (err.line, err.field.as_deref()),
            (Some(line), Some(field)),
            "{err}"
        );
        assert!(err.message.contains(msg), "{err}");
    }
}

#[test]
fn out_of_range_settings() {
    rejects("[render]\nwidth = 0\n", 5, "render.width", "1..=16384");
    rejects(
        "[render]\nheight = 16385\n",
        5,
        "render.height",
        "1..=16384",
    );
    rejects("[render]\nwidth = -640\n", 5, "render.width", "1..=16384");
    rejects("[render]\nsamples = 0\n", 5, "render.samples", "1..=16");
    rejects("[render]\nsamples = 17\n", 5, "render.samples", "1..=16");
    rejects(
        "[render]\nmax_depth = 17\n",
        5,
        "render.max_depth",
        "0..=16",
    );
    rejects(
        "[render]\nmax_depth = -1\n",
        5,
        "render.max_depth",
        "0..=16",
    );
}

#[test]
fn more_than_capacity_is_an_error_not_a_truncation() {
    let sphere = "[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\n";
    let light = "[[light]]\nkind = \"point\"\nposition = [0, 9, 0]\n";
    let n = microray::scene_file::SPHERES;
    assert_eq!(
        parse_desktop(&format!("{CAMERA}{}", sphere.repeat(n)))
            .unwrap()
            .scene
            .spheres()
            .len(),
        n
    );
    rejects(
        &sphere.repeat(n + 1),
        4 + 3 * n,
        "sphere",
        &format!("{} spheres, more than the capacity of {n}", n + 1),
    );
    assert_eq!(
        parse_desktop(&format!("{CAMERA}{}", light.repeat(32)))
            .unwrap()
            .scene
            .lights()
            .len(),
        32
    );
    rejects(
        &light.repeat(33),
        4 + 3 * 32,
        "light",
        "33 lights, more than the capacity of 32",
    );
    // a small capacity chosen by the caller is enforced the same way
    let err = parse::<2, 1>(&format!("{CAMERA}{}", sphere.repeat(3))).unwrap_err();
    assert!(err.message.contains("capacity of 2"), "{err}");
}

#[test]
fn syntax_errors_have_a_line() {
    rejects(
        "[[sphere]\ncenter = [0, 0, 0]\n",
        4,
        "sphere[0]",
        "unclosed array table",
    );
    let err = parse_desktop("[camera]\neye = [0, 0, 5\nlook_at = [0, 0, 0]\n").unwrap_err();
    assert!(err.line.is_some(), "{err}");
}

#[test]
fn keyframe_fields() {
    // No keyframes: none. Two: their fields default to the camera's.
    assert!(parse_desktop(CAMERA).unwrap().keyframes.keys().is_empty());
    let text =
        format!("{CAMERA}[[keyframe]]\nat = 0\n[[keyframe]]\nat = 1\neye = [5, 0, 0]\nvfov = 30\n");
    let f = parse_desktop(&text).unwrap();
    let keys = f.keyframes.keys();
    assert_eq!(keys.len(), 2);
    assert_eq!(keys[0].view, f.view);
    assert_eq!(keys[1].view.eye, Vec3::new(5.0, 0.0, 0.0));
    assert_eq!(
        (keys[1].view.look_at, keys[1].view.up, keys[1].view.vfov),
        (f.view.look_at, f.view.up, 30.0)
    );
    assert_eq!(
        f.keyframes.view(1, 3).unwrap().vfov,
        f.view.vfov * 0.5 + 15.0
    );

    let key = |at: &str| format!("[[keyframe]]\nat = {at}\n");
    // A single key is no animation.
    rejects(&key("0"), 4, "keyframe", "at least two");
    // Times: from 0, increasing, within [0, 1], finite.
    rejects(
        &format!("{}{}", key("0.1"), key("1")),
        5,
        "keyframe[0].at",
        "start at 0",
    );
    rejects(
        &format!("{}{}", key("0"), key("nan")),
        7,
        "keyframe[1].at",
        "increase",
    );
    rejects(
        &format!("{}{}", key("0"), key("0")),
        7,
        "keyframe[1].at",
        "increase",
    );
    rejects(
        &format!("{}{}", key("0"), key("1.5")),
        7,
        "keyframe[1].at",
        "[0, 1]",
    );
    // A key's view must make a camera, and its fields must be finite numbers.
    rejects(
        &format!(
            "{}{}look_at = [0, 0, 5]\neye = [0, 0, 5]\n",
            key("0"),
            key("1")
        ),
        8,
        "keyframe[1].look_at",
        "must differ",
    );
    rejects(
        &format!("{}{}vfov = 180\n", key("0"), key("1")),
        8,
        "keyframe[1].vfov",
        "(0, 180)",
    );
    rejects(
        &format!("{}{}up = [0, 0, 1]\n", key("0"), key("1")),
        8,
        "keyframe[1].up",
        "parallel",
    );
    rejects(
        &format!("{}{}eye = [nan, 0, 0]\n", key("0"), key("1")),
        8,
        "keyframe[1].eye",
        "finite",
    );
    // Unknown keys are errors, as in every table.
    let err = parse_desktop(&format!("{CAMERA}{}time = 2\n{}", key("0"), key("1"))).unwrap_err();
    assert!(err.to_string().contains("time"), "{err}");
    // Past the capacity.
    let many: String = (0..=KEYFRAMES)
        .map(|k| key(&format!("{}", k as f32 / KEYFRAMES as f32)))
        .collect();
    let err = parse_desktop(&format!("{CAMERA}{many}")).unwrap_err();
    assert_eq!(err.field.as_deref(), Some("keyframe"), "{err}");
    assert!(err.message.contains("capacity"), "{err}");
}

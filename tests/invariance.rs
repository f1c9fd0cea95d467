//! Scale and translation invariance, as property tests: random ordinary scenes translated 10⁴
//! from the origin and scaled by 10⁻⁴ and 10⁴ render the same image as the original scene,
//! and each matches the f64 reference of its own (f32-rounded) numbers.
//!
//! Scene coordinates are multiples of 1/64, so the translation by 10⁴ is exact in f32 and the
//! image may differ only by microray's own rounding; the scalings round the scene as well, so
//! they compare under the same rule as the reference (pixels that move when the rays move by
//! 2 ulp of their direction are left out, for either scene, and so are pixels where the two
//! scenes' references themselves differ: there rounding the scene changed the picture).

mod common;

use common::reference::Reference;
use common::rng::Rng;
use common::{agreement, Image};
use microray::scene_file::{parse, Desktop};

/// A random scene as (spheres: centre, radius, material TOML), lights and camera, untransformed.
struct Random {
    spheres: Vec<([f64; 3], f64, String)>,
    light: [f64; 3],
    sun: [f64; 3],
    eye: [f64; 3],
    look_at: [f64; 3],
}

fn random_scene(seed: u64) -> Random {
    let mut g = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut spheres = vec![(
        [0.0, -1000.0, 0.0],
        1000.0,
        "diffuse = 0.6\nmirror = 0.2".to_string(),
    )];
    let n = 3 + g.next() % 4;
    for _ in 0..n {
        let r = g.grid(0.25, 1.0);
        let c = [g.grid(-2.5, 2.5), r + g.grid(-0.1, 0.5), g.grid(-2.5, 1.5)];
        let mat = format!(
            "diffuse = [{}, {}, {}]\nspecular = {}\nshininess = {}\nmirror = {}",
            g.grid(0.1, 0.9),
            g.grid(0.1, 0.9),
            g.grid(0.1, 0.9),
            g.grid(0.0, 0.8),
            [8, 32, 128, 1000][(g.next() % 4) as usize],
            if g.next().is_multiple_of(3) { 0.5 } else { 0.0 },
        );
        spheres.push((c, r, mat));
    }
    Random {
        spheres,
        light: [g.grid(-5.0, 5.0), g.grid(3.0, 8.0), g.grid(-2.0, 6.0)],
        sun: [g.grid(-1.0, 1.0), -1.0, g.grid(-1.0, 1.0)],
        eye: [g.grid(-3.0, 3.0), g.grid(0.5, 3.0), g.grid(5.0, 8.0)],
        look_at: [g.grid(-0.5, 0.5), g.grid(0.0, 1.0), 0.0],
    }
}

/// The scene as TOML, with every position `p` mapped to `s p + t` and every radius to `s r`.
fn toml(sc: &Random, s: f64, t: [f64; 3]) -> String {
    let p = |v: [f64; 3]| {
        format!(
            "[{:e}, {:e}, {:e}]",
            s * v[0] + t[0],
            s * v[1] + t[1],
            s * v[2] + t[2]
        )
    };
    let mut out = format!(
        "[camera]\neye = {}\nlook_at = {}\nvfov = 50\n[render]\nwidth = 80\nheight = 60\n\
         background = [0.1, 0.12, 0.2]\nambient = 0.05\n",
        p(sc.eye),
        p(sc.look_at)
    );
    for (c, r, m) in &sc.spheres {
        out += &format!(
            "[[sphere]]\ncenter = {}\nradius = {:e}\n{m}\n",
            p(*c),
            s * r
        );
    }
    out += &format!(
        "[[light]]\nkind = \"point\"\nposition = {}\nintensity = 0.7\n\
         [[light]]\nkind = \"directional\"\ndirection = [{}, {}, {}]\nintensity = 0.3\n",
        p(sc.light),
        sc.sun[0],
        sc.sun[1],
        sc.sun[2]
    );
    out
}

fn load(text: &str) -> Box<Desktop> {
    parse(text).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Pixels off by more than 1 and by more than 8 between two f32 images, leaving out pixels
/// sensitive to 2 ulp of direction in either scene's reference.
fn compare(a: &Image, b: &Image, ra: &Reference, rb: &Reference) -> (usize, usize, usize) {
    let (mut over1, mut over8, mut excused) = (0, 0, 0);
    for (k, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        let m = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap();
        if m <= 1 {
            continue;
        }
        let (i, j) = (k as u32 % ra.width, k as u32 / ra.width);
        // Rounding the transformed scene to f32 may change the picture itself: then the
        // references differ too, and no renderer is to blame.
        let (pa, pb) = (ra.pixel(i, j, [0.0; 3]), rb.pixel(i, j, [0.0; 3]));
        let scene_changed = (0..3).any(|c| pa[c].abs_diff(pb[c]) > 1);
        if scene_changed || ra.sensitive(i, j) || rb.sensitive(i, j) {
            excused += 1;
            continue;
        }
        over1 += 1;
        over8 += (m > 8) as usize;
    }
    (over1, over8, excused)
}

/// Random scenes per transform.
const SEEDS: u64 = 200;

fn invariant(name: &str, s: f64, t: [f64; 3]) {
    let (mut failed, mut checked) = (vec![], 0);
    for seed in 1..=SEEDS {
        let sc = random_scene(seed);
        let base = load(&toml(&sc, 1.0, [0.0; 3]));
        let moved = load(&toml(&sc, s, t));
        let (img0, img1) = (common::render(&base), common::render(&moved));
        // Each against its own reference.
        let a = agreement(&moved, &img1);
        // A camera that sees mostly background tests little: such seeds are skipped.
        if a.covered * 2 <= a.total {
            continue;
        }
        checked += 1;
        // And the image itself unchanged.
        let (r0, r1) = (Reference::new(&base), Reference::new(&moved));
        let (over1, over8, excused) = compare(&img0, &img1, &r0, &r1);
        let n = img0.pixels.len() - excused;
        println!("{name}, seed {seed}: {a:?}; against the original: over1 {over1} over8 {over8} excused {excused}");
        let unchanged = over8 == 0 && over1 as f64 <= 0.005 * n as f64;
        if !a.holds() || !unchanged {
            println!("  FAILS: reference {}, unchanged {unchanged}", a.holds());
            failed.push(seed);
        }
    }
    assert!(
        failed.is_empty(),
        "{name}: seeds failing the goal: {failed:?}"
    );
    assert!(
        checked >= SEEDS * 9 / 10,
        "{name}: only {checked} scenes checked"
    );
}

#[test]
fn translated_by_1e4() {
    invariant("translated", 1.0, [1e4, 1e4, -1e4]);
}

#[test]
fn scaled_by_1e_minus_4() {
    invariant("scaled 1e-4", 1e-4, [0.0; 3]);
}

#[test]
fn scaled_by_1e4() {
    invariant("scaled 1e4", 1e4, [0.0; 3]);
}

#[test]
fn scaled_by_1e_minus_4_and_translated() {
    invariant("scaled 1e-4, translated", 1e-4, [1.0, -2.0, 3.0]);
}

/// Translating by a vector on the scenes' 1/64 grid is exact in f32, and every ray leaves a
/// hit from its offset or its path from the eye, never from the rounded point: the image must
/// not change in a single bit.
#[test]
fn exact_translation_is_bit_identical() {
    for seed in 1..=SEEDS {
        let sc = random_scene(seed);
        let img0 = common::render(&load(&toml(&sc, 1.0, [0.0; 3])));
        for t in [[1e4, 1e4, -1e4], [-3000.0, 0.0, 7777.0]] {
            let img1 = common::render(&load(&toml(&sc, 1.0, t)));
            let diff = img0
                .pixels
                .iter()
                .zip(&img1.pixels)
                .filter(|(a, b)| a != b)
                .count();
            assert_eq!(diff, 0, "seed {seed}, translation {t:?}");
        }
    }
}

/// Scaling by a power of two is exact in f32: the image must not change in a single bit, from
/// 2⁻⁶⁰ to 2⁶⁰. Above 2⁴⁰ or so the tests' products overflow and take the scaled roots; below
/// 2⁻³⁵ a point light's shadow ray, as small as the scene, underflowed them (~5% of the pixels
/// at 2⁻⁴⁰) until shading scaled it up (`shading::shadow_ray`).
#[test]
fn scaled_by_powers_of_two_is_bit_identical() {
    for seed in 1..=6u64 {
        let sc = random_scene(seed);
        let img0 = common::render(&load(&toml(&sc, 1.0, [0.0; 3])));
        for s in [-60, -40, -20, 20, 40, 60].map(|e| 2f64.powi(e)) {
            let img1 = common::render(&load(&toml(&sc, s, [0.0; 3])));
            assert!(img0.pixels == img1.pixels, "seed {seed}, scale {s:e}");
        }
    }
}

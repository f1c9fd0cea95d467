//! What each numerical choice costs in speed against what it buys in error.
//!
//! `cargo run --release --example speed_vs_error [-- --quick] [--plot PATH]`
//!
//! Prints one table per question (intersection formula, square root, specular power, whole
//! image) and writes `docs/speed_vs_error.png` (or PATH): every intersection variant as a point,
//! ns per ray-sphere test (x, log) against the worst error of t in ulp on the hard ray sets
//! (y, log).
//! Times are medians over repeated, interleaved runs after a warm-up; the machine may be shared
//! and noisy, so compare the ratios, which are measured in one run, not the absolute times.
//! The "Cortex-M4F instructions/test" columns come from examples/firmware/numbench.sh, which
//! counts the same variants (examples/common/variants.rs) in QEMU; without qemu-system-arm or
//! the thumbv7em-none-eabihf target they say "not measured".

// `!(x >= 0.0)` is deliberate, as in the library: NaN must fail.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[path = "../tests/common/mod.rs"]
mod common;
#[path = "common/variants.rs"]
mod variants;

use std::collections::HashMap;
use std::hint::black_box;
use std::ops::Add;
use std::time::Instant;

use common::reference::reference_t;
use common::rng::Rng;
use microray::scene_file::{self, Desktop};
use microray::{Frame, Prepared, Sphere, Vec3};
use variants::*;

// ---- the intersection variants ----------------------------------------------------------------

/// An intersection: the first root t > 0 of a ray from `o` along `d`.
type Isect = fn(Vec3, Vec3, &Sphere) -> Option<f32>;

// ---- ray sets -----------------------------------------------------------------------------------

/// `w` made perpendicular to the unit vector `u`, normalised.
fn perpendicular(w: [f64; 3], u: [f64; 3]) -> [f64; 3] {
    let k = w[0] * u[0] + w[1] * u[1] + w[2] * u[2];
    let p = [w[0] - k * u[0], w[1] - k * u[1], w[2] - k * u[2]];
    let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
    [p[0] / n, p[1] / n, p[2] / n]
}

fn v32(v: [f64; 3]) -> Vec3 {
    Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)
}

/// One ray-sphere case: unit f32 direction, and the reference's near positive root (or None).
struct Case {
    o: Vec3,
    d: Vec3,
    s: Sphere,
    t_ref: Option<f64>,
    /// Counted for ulp statistics (a hit that does not graze).
    clean: bool,
    ground: bool,
}

/// Far and small spheres (distance/radius 10¹ … 10⁵; 80% aimed inside 0.9 r, 20% missing by
/// 1.1 … 3 r) and huge grounds (radius 10³ … 10⁶) seen from 1 unit above.
fn hard_rays(n: usize) -> Vec<Case> {
    let mut g = Rng(2024);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        if out.len() % 4 == 3 {
            let radius = 10f64.powf(g.range(3.0, 6.0)) as f32;
            let s = Sphere::new(Vec3::new(0.0, -radius, 0.0), radius);
            let (o, d) = g.ground_ray();
            let t_ref = reference_t(o, d, &s);
            let clean = t_ref.is_some_and(|t| {
                let r = radius as f64;
                let p = [
                    o.x as f64 + t * d.x as f64,
                    o.y as f64 + t * d.y as f64 + r,
                    o.z as f64 + t * d.z as f64,
                ];
                -(p[0] * d.x as f64 + p[1] * d.y as f64 + p[2] * d.z as f64) / r >= 0.1
            });
            out.push(Case {
                o,
                d,
                s,
                t_ref,
                clean,
                ground: true,
            });
        } else {
            let ratio = 10f64.powf(g.range(1.0, 5.0));
            let r = 10f64.powf(g.range(-4.0, 2.0));
            let m = g.dir();
            let m = [m[0] * 100.0 * r, m[1] * 100.0 * r, m[2] * 100.0 * r];
            let u = g.dir();
            let o = [
                m[0] + u[0] * ratio * r,
                m[1] + u[1] * ratio * r,
                m[2] + u[2] * ratio * r,
            ];
            let miss = g.u() < 0.25;
            // aim at a point of the disc through the centre facing the origin, `k` from the
            // centre: the ray passes the centre at (about) k
            let w = perpendicular(g.dir(), u);
            let k = if miss {
                g.range(1.1, 3.0)
            } else {
                g.u().sqrt() * 0.9
            } * r;
            let target = [m[0] + w[0] * k, m[1] + w[1] * k, m[2] + w[2] * k];
            let dv = [target[0] - o[0], target[1] - o[1], target[2] - o[2]];
            let nd = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
            let (o, d) = (v32(o), v32([dv[0] / nd, dv[1] / nd, dv[2] / nd]));
            let s = Sphere::new(v32(m), r as f32);
            let t_ref = reference_t(o, d, &s);
            if miss && t_ref.is_some() {
                continue; // rounding made an aimed miss graze after all: it counts nowhere
            }
            let clean = !miss;
            out.push(Case {
                o,
                d,
                s,
                t_ref,
                clean,
                ground: false,
            });
        }
    }
    out
}

#[derive(Default, Clone)]
struct Errors {
    max_ulp: f64,
    median_ulp: f64,
    max_ulp_far: f64,
    max_ulp_ground: f64,
    max_rel_ground: f64,
    false_hits: usize,
    misses: usize,
}

fn errors(cases: &[Case], f: impl Fn(Vec3, Vec3, &Sphere) -> Option<f32>) -> Errors {
    let mut ulps = vec![];
    let mut e = Errors::default();
    for c in cases {
        let t = f(c.o, c.d, &c.s);
        match (t, c.t_ref) {
            (Some(t), Some(tr)) => {
                let err = (t as f64 - tr).abs();
                if c.clean {
                    let u = err / common::reference::ulp32(tr);
                    ulps.push(u);
                    if c.ground {
                        e.max_ulp_ground = e.max_ulp_ground.max(u);
                    } else {
                        e.max_ulp_far = e.max_ulp_far.max(u);
                    }
                }
                if c.ground {
                    e.max_rel_ground = e.max_rel_ground.max(err / tr);
                }
            }
            (Some(_), None) => e.false_hits += 1,
            (None, Some(_)) if c.clean => e.misses += 1,
            _ => {}
        }
    }
    ulps.sort_by(|a, b| a.partial_cmp(b).unwrap());
    e.max_ulp = ulps.last().cloned().unwrap_or(0.0);
    e.median_ulp = ulps.get(ulps.len() / 2).cloned().unwrap_or(0.0);
    e
}

// ---- timing -------------------------------------------------------------------------------------

/// Median of `runs` timings (ns per item) of each closure, interleaved, after a warm-up.
fn time_all(items: usize, runs: usize, fs: &mut [&mut dyn FnMut() -> f32]) -> Vec<f64> {
    for f in fs.iter_mut() {
        black_box(f());
    }
    let mut samples = vec![vec![]; fs.len()];
    for _ in 0..runs {
        for (k, f) in fs.iter_mut().enumerate() {
            let t = Instant::now();
            black_box(f());
            samples[k].push(t.elapsed().as_nanos() as f64 / items as f64);
        }
    }
    samples
        .into_iter()
        .map(|mut s| {
            s.sort_by(|a, b| a.partial_cmp(b).unwrap());
            s[s.len() / 2]
        })
        .collect()
}

/// Primary-ray-like timing set: one eye, many directions, a few spheres of all sizes.
fn timing_set(n: usize) -> (Vec3, Vec<Vec3>, Vec<Sphere>) {
    let mut g = Rng(SEED_PRIMARY);
    let dirs = (0..n)
        .map(|_| {
            let x = g.range(-0.6, 0.6);
            primary_dir(x, g.range(-0.5, 0.3))
        })
        .collect();
    (EYE, dirs, PRIMARY_SPHERES.to_vec())
}

// Every variant is inlined into its own copy of the loop (generic `f`), as a renderer would
// inline it: called through a pointer, each paid the call and the passing of two `Vec3`s,
// whose cost swung by 2× with unrelated changes of code layout. Each copy is a function of its
// own rather than part of `main`, where one variant's change moved the others' times.
#[inline(never)]
fn sum_hits(
    eye: Vec3,
    dirs: &[Vec3],
    spheres: &[Sphere],
    f: impl Fn(Vec3, Vec3, &Sphere) -> Option<f32>,
) -> f32 {
    let mut acc = 0.0;
    let eye = black_box(eye);
    for &d in dirs {
        for s in spheres {
            if let Some(t) = f(eye, d, s) {
                acc += t;
            }
        }
    }
    acc
}

/// The refracted rays that a 160×120 render of `file` (glass.toml) casts, one ray a pixel, in
/// [`shadow_loop`]'s form: from every primary hit on glass the ray into it, and from the hit
/// where that ray meets a sphere (leaving the glass) the next refracted ray.
fn refracted_rays(file: &Desktop) -> Vec<(Vec3, Vec3, usize)> {
    let scene = &file.scene;
    let glass = |i: usize| scene.materials()[i].refraction != Vec3::ZERO;
    let (w, h) = (file.camera.width(), file.camera.height());
    let mut out = vec![];
    for j in 0..h {
        for i in 0..w {
            let ray = file.camera.view_ray(i, j, 0, 0, 1);
            let Some(hit) = scene.find_intersection(&ray, f32::MIN_POSITIVE, f32::INFINITY) else {
                continue;
            };
            if !glass(hit.sphere) {
                continue;
            }
            let ior = scene.materials()[hit.sphere].ior;
            let inside = microray::shading::refract(&ray, &hit, ior);
            out.push((hit.point(), inside.dir, hit.sphere));
            if let Some(exit) = microray::shading::find_from(scene, &inside, &hit) {
                if glass(exit.sphere) {
                    let ior = scene.materials()[exit.sphere].ior;
                    let out_ray = microray::shading::refract(&inside, &exit, ior);
                    out.push((exit.point(), out_ray.dir, exit.sphere));
                }
            }
        }
    }
    out
}

// ---- a plain f32 renderer of the model with a pluggable intersection ---------------------------

/// The model rendered the plain way, in f32: hit point `o + t d`, normal `(p − m)/r`, shadow,
/// mirror and refracted rays from `p`, the sphere a ray leaves met only at its other root. Only the
/// intersection formula changes between variants, so the images show what it alone buys;
/// microray's own image adds the other remedies (see docs/numerics.md).
struct Plain<'a> {
    file: &'a Desktop,
    isect: Isect,
}

impl Plain<'_> {
    fn closest(&self, o: Vec3, d: Vec3, from: Option<usize>) -> Option<(f32, usize)> {
        let spheres = self.file.scene.spheres();
        let mut best: Option<(f32, usize)> = None;
        for (j, s) in spheres.iter().enumerate() {
            let t = if Some(j) == from {
                let t = -2.0 * (o - s.center).dot(d) / d.dot(d);
                (t > 0.0).then_some(t)
            } else {
                (self.isect)(o, d, s)
            };
            if let Some(t) = t {
                if best.is_none_or(|b| t < b.0) {
                    best = Some((t, j));
                }
            }
        }
        best
    }

    fn blocked(&self, p: Vec3, from: usize, d: Vec3, tmax: f32) -> bool {
        self.file.scene.spheres().iter().enumerate().any(|(j, s)| {
            let t = if j == from {
                Some(-2.0 * (p - s.center).dot(d) / d.dot(d))
            } else {
                (self.isect)(p, d, s)
            };
            t.is_some_and(|t| t > 0.0 && t < tmax)
        })
    }

    fn trace(&self, o: Vec3, d: Vec3, from: Option<usize>, depth: u8) -> Vec3 {
        let scene = &self.file.scene;
        let Some((t, i)) = self.closest(o, d, from) else {
            return scene.background();
        };
        let (s, m) = (&scene.spheres()[i], &scene.materials()[i]);
        let p = o + d * t;
        let mut n = (p - s.center) / s.radius;
        if d.dot(n) > 0.0 {
            n = -n;
        }
        let v = -(d / d.length());
        let mut col = m.diffuse.mul_elem(scene.ambient());
        for light in scene.lights() {
            let (l, dl, tmax) = match *light {
                microray::Light::Point { position, .. } => {
                    let dl = position - p;
                    (dl / dl.length(), dl, 1.0)
                }
                microray::Light::Directional { direction, .. } => {
                    (-direction, -direction, f32::INFINITY)
                }
            };
            let nl = n.dot(l);
            if !(nl > 0.0) || (scene.shadows() && self.blocked(p, i, dl, tmax)) {
                continue;
            }
            let h = v + l;
            let nh = n.dot(h / h.length());
            let spec = if nh > 0.0 {
                libm::powf(nh, m.shininess)
            } else {
                0.0
            };
            col += light
                .intensity()
                .mul_elem(m.diffuse * nl + m.specular * spec);
        }
        if m.mirror != Vec3::ZERO && depth < scene.max_depth() {
            let r = d - n * (2.0 * d.dot(n));
            col += m.mirror.mul_elem(self.trace(p, r, Some(i), depth + 1));
        }
        if m.refraction != Vec3::ZERO && depth < scene.max_depth() {
            // Snell's law as textbooks write it, η = 1/ior entering and ior leaving.
            let u = d / d.length();
            let eta = if (p - s.center).dot(n) > 0.0 {
                1.0 / m.ior
            } else {
                m.ior
            };
            let c = -u.dot(n);
            let k = 1.0 - eta * eta * (1.0 - c * c);
            let r = if k < 0.0 {
                d - n * (2.0 * d.dot(n))
            } else {
                u * eta + n * (eta * c - libm::sqrtf(k))
            };
            col += m.refraction.mul_elem(self.trace(p, r, Some(i), depth + 1));
        }
        col
    }

    fn render(&self) -> common::Image {
        let cam = &self.file.camera;
        let (w, h) = (cam.width(), cam.height());
        let n = self.file.options.samples as u32;
        let mut pixels = Vec::with_capacity((w * h) as usize);
        for j in 0..h {
            for i in 0..w {
                let mut sum = Vec3::ZERO;
                for sy in 0..n {
                    for sx in 0..n {
                        let ray = cam.view_ray(i, j, sx, sy, n);
                        sum += self.trace(ray.origin, ray.dir, None, 0);
                    }
                }
                let c = sum / (n * n) as f32;
                let e = self.file.options.encoding;
                let enc = microray::render::encode_channel;
                pixels.push([enc(c.x, e), enc(c.y, e), enc(c.z, e)]);
            }
        }
        common::Image {
            width: w,
            height: h,
            pixels,
        }
    }
}

// ---- Cortex-M4F instruction counts ------------------------------------------------------------

/// The `key=value` lines of examples/firmware/numbench.sh, or why there are none.
struct M4f(Result<HashMap<String, String>, String>);

impl M4f {
    /// Runs numbench.sh (it builds the firmware and runs it in QEMU) if QEMU is installed.
    fn measure() -> M4f {
        let qemu = std::process::Command::new("qemu-system-arm")
            .arg("--version")
            .output();
        if !qemu.is_ok_and(|o| o.status.success()) {
            return M4f(Err("no qemu-system-arm".into()));
        }
        let script = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/firmware/numbench.sh");
        eprintln!("counting Cortex-M4F instructions: {script}");
        let out = match std::process::Command::new("bash").arg(script).output() {
            Ok(out) => out,
            Err(e) => return M4f(Err(format!("{script}: {e}"))),
        };
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        let keys: HashMap<String, String> = stdout
            .lines()
            .filter_map(|l| l.split_once('='))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        if out.status.success() && keys.get("ok").is_some_and(|v| v == "1") {
            return M4f(Ok(keys));
        }
        // The script's `error=` line (a missing target, a failed run), else its exit status.
        let why = stderr
            .lines()
            .chain(stdout.lines())
            .find_map(|l| l.strip_prefix("error="))
            .map_or_else(
                || format!("numbench.sh failed: {}", out.status),
                String::from,
            );
        eprint!("{stderr}");
        M4f(Err(why))
    }

    /// The instructions per test under `key`, or "not measured (why)"; never a made-up number.
    fn cell(&self, key: &str) -> String {
        if key.is_empty() {
            // A host-only path: Cortex-M has no f32 vectors.
            return "— (hosts only)".into();
        }
        match &self.0 {
            Ok(keys) => keys
                .get(key)
                .cloned()
                .unwrap_or_else(|| format!("not measured (numbench printed no {key})")),
            Err(why) => format!("not measured ({why})"),
        }
    }

    /// [`M4f::cell`] with its ratio to the count under `base` (the textbook quadratic with the
    /// same square root, so that the ratio compares formulas): "67.4 (3.09×)".
    fn cell_vs(&self, key: &str, base: &str) -> String {
        let cell = self.cell(key);
        let num = |k: &str| self.0.as_ref().ok()?.get(k)?.parse::<f64>().ok();
        match (num(key), num(base)) {
            (Some(n), Some(b)) if b > 0.0 => format!("{cell} ({:.2}×)", n / b),
            _ => cell,
        }
    }
}

/// The colour of a table row that the plot leaves out.
const NOT_PLOTTED: [u8; 3] = [0, 0, 0];

// ---- the plot -----------------------------------------------------------------------------------

/// Points (x = ns, y = max ulp, colour) on log-log axes, a grey grid line at every power of
/// ten (the axes start at one) and a dashed line at 4 ulp.
fn plot(points: &[(f64, f64, [u8; 3])], path: &str) {
    use tiny_skia::{Color, Paint, PathBuilder, Pixmap, Stroke, Transform};
    let (w, h, m) = (640.0f32, 480.0f32, 50.0f32);
    let mut pm = Pixmap::new(w as u32, h as u32).unwrap();
    pm.fill(Color::WHITE);
    let (x0, x1) = (
        points
            .iter()
            .map(|p| p.0)
            .fold(f64::MAX, f64::min)
            .log10()
            .floor()
            - 0.0,
        points
            .iter()
            .map(|p| p.0)
            .fold(0.0, f64::max)
            .log10()
            .ceil(),
    );
    let (y0, y1) = (
        -1.0f64,
        points
            .iter()
            .map(|p| p.1.max(0.1))
            .fold(0.0, f64::max)
            .log10()
            .add(0.3) // room above the highest point
            .ceil()
            .max(1.0),
    );
    let px = |x: f64| m + (w - 2.0 * m) * ((x.log10() - x0) / (x1 - x0)) as f32;
    let py = |y: f64| h - m - (h - 2.0 * m) * ((y.max(0.1).log10() - y0) / (y1 - y0)) as f32;
    let mut black = Paint::default();
    black.set_color_rgba8(0, 0, 0, 255);
    let mut grey = Paint::default();
    grey.set_color_rgba8(210, 210, 210, 255);
    let stroke = Stroke {
        width: 1.5,
        ..Stroke::default()
    };
    // grid and ticks at decades
    let mut dec = x0;
    while dec <= x1 + 1e-9 {
        let x = m + (w - 2.0 * m) * ((dec - x0) / (x1 - x0)) as f32;
        let mut pb = PathBuilder::new();
        pb.move_to(x, m);
        pb.line_to(x, h - m + 6.0);
        pm.stroke_path(
            &pb.finish().unwrap(),
            &grey,
            &stroke,
            Transform::identity(),
            None,
        );
        dec += 1.0;
    }
    let mut dec = y0;
    while dec <= y1 + 1e-9 {
        let y = h - m - (h - 2.0 * m) * ((dec - y0) / (y1 - y0)) as f32;
        let mut pb = PathBuilder::new();
        pb.move_to(m - 6.0, y);
        pb.line_to(w - m, y);
        pm.stroke_path(
            &pb.finish().unwrap(),
            &grey,
            &stroke,
            Transform::identity(),
            None,
        );
        dec += 1.0;
    }
    // axes
    let mut pb = PathBuilder::new();
    pb.move_to(m, m);
    pb.line_to(m, h - m);
    pb.line_to(w - m, h - m);
    pm.stroke_path(
        &pb.finish().unwrap(),
        &black,
        &Stroke {
            width: 2.0,
            ..Stroke::default()
        },
        Transform::identity(),
        None,
    );
    // the 4-ulp target line (dashed look: short segments)
    let y4 = py(4.0);
    let mut x = m;
    while x < w - m {
        let mut pb = PathBuilder::new();
        pb.move_to(x, y4);
        pb.line_to((x + 8.0).min(w - m), y4);
        pm.stroke_path(
            &pb.finish().unwrap(),
            &black,
            &Stroke {
                width: 1.0,
                ..Stroke::default()
            },
            Transform::identity(),
            None,
        );
        x += 16.0;
    }
    // later points smaller, so that coinciding points stay visible
    for (i, &(x, y, c)) in points.iter().enumerate() {
        let radius = 11.0 - 1.5 * i as f32;
        let mut paint = Paint::default();
        paint.set_color_rgba8(c[0], c[1], c[2], 255);
        paint.anti_alias = true;
        let circle = PathBuilder::from_circle(px(x), py(y), radius.max(3.0)).unwrap();
        pm.fill_path(
            &circle,
            &paint,
            tiny_skia::FillRule::Winding,
            Transform::identity(),
            None,
        );
        pm.stroke_path(
            &circle,
            &black,
            &Stroke {
                width: 1.0,
                ..Stroke::default()
            },
            Transform::identity(),
            None,
        );
    }
    pm.save_png(path).unwrap();
}

/// The [`Sun`] prototype against `Prepared::leaving_blocks` on shadow rays from random points
/// of each scene's spheres, towards random light directions and towards directions that graze
/// another sphere: (tests, decided without the fallback, disagreements). Scenes: lit.toml's
/// spheres as they are, moved by (10⁴, 10⁴, −10⁴), scaled by 10⁻⁴ and by 10⁴, and random scenes
/// of 8 spheres (radii 0.05–2 in a box of 10).
fn sun_agreement(rays_per_scene: usize) -> (usize, usize, usize) {
    let mut g = Rng(SEED_SHADOW + 1);
    let moved = |t: Vec3, k: f32| LIT_SPHERES.map(|s| Sphere::new(s.center * k + t, s.radius * k));
    let mut scenes: Vec<Vec<Sphere>> = vec![
        LIT_SPHERES.to_vec(),
        moved(Vec3::new(1e4, 1e4, -1e4), 1.0).to_vec(),
        moved(Vec3::ZERO, 1e-4).to_vec(),
        moved(Vec3::ZERO, 1e4).to_vec(),
    ];
    for _ in 0..4 {
        scenes.push(
            (0..SUN_MAX)
                .map(|_| {
                    let c = [g.range(-5.0, 5.0), g.range(-5.0, 5.0), g.range(-5.0, 5.0)];
                    let c = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
                    Sphere::new(c, g.range(0.05, 2.0) as f32)
                })
                .collect(),
        );
    }
    let f64s = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let unit32 = |v: [f64; 3]| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32).normalized();
    let (mut tests, mut decided, mut wrong) = (0, 0, 0);
    let mut test = |spheres: &[Sphere], sun: &Sun, i: usize, rel: Vec3| {
        let anchor = spheres[i].center;
        let p = sun.project(anchor, rel);
        for (j, s) in spheres.iter().enumerate() {
            if j != i {
                tests += 1;
                if let Some(b) = sun.decide(p, j) {
                    decided += 1;
                    let full = Prepared::leaving_blocks(anchor, rel, s, sun.dir(), f32::INFINITY);
                    wrong += (b != full) as usize;
                }
            }
        }
    };
    for spheres in &scenes {
        let pick = |g: &mut Rng| (g.next() % spheres.len() as u64) as usize;
        // Random points towards random light directions ...
        for _ in 0..rays_per_scene / 32 {
            let Some(l) = unit32(g.dir()) else { continue };
            let sun = Sun::new(spheres, l).unwrap();
            for _ in 0..16 {
                let (i, n) = (pick(&mut g), unit32(g.dir()).unwrap());
                if n.dot(l) > 0.0 {
                    test(spheres, &sun, i, n * spheres[i].radius);
                }
            }
        }
        // ... and towards a point within a relative 10⁻⁴ of a tangent point of another sphere
        // seen from the point: the silhouettes, where a decision is closest to wrong.
        for _ in 0..rays_per_scene / 2 {
            let (i, j) = (pick(&mut g), pick(&mut g));
            let (si, sj) = (spheres[i], spheres[j]);
            let rel = unit32(g.dir()).unwrap() * si.radius;
            let (o, m, r) = (f64s(si.center + rel), f64s(sj.center), sj.radius as f64);
            let f = [o[0] - m[0], o[1] - m[1], o[2] - m[2]];
            let dd = f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
            if i == j || dd <= r * r {
                continue;
            }
            // The tangent points from o: m + (r²/D²) f + (r √(D² − r²)/D) w, w a unit across f.
            let w = g.dir();
            let wf = (w[0] * f[0] + w[1] * f[1] + w[2] * f[2]) / dd;
            let w = [w[0] - wf * f[0], w[1] - wf * f[1], w[2] - wf * f[2]];
            let wn = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            let (a, b) = (r * r / dd, r * (dd - r * r).sqrt() / dd.sqrt() / wn);
            let k = 1.0 + g.range(-1e-4, 1e-4);
            let q: Vec<f64> = (0..3).map(|n| m[n] + (a * f[n] + b * w[n]) * k).collect();
            let Some(l) = unit32([q[0] - o[0], q[1] - o[1], q[2] - o[2]]) else {
                continue;
            };
            if rel.dot(l) > 0.0 {
                test(spheres, &Sun::new(spheres, l).unwrap(), i, rel);
            }
        }
    }
    (tests, decided, wrong)
}

// ---- main ---------------------------------------------------------------------------------------

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    // `--plot PATH`: CI runs the quick report without touching the committed plot.
    let plot_path = match args.iter().position(|a| a == "--plot") {
        None => "docs/speed_vs_error.png",
        Some(k) => args.get(k + 1).map(String::as_str).unwrap_or_else(|| {
            eprintln!("--plot needs a path");
            std::process::exit(2)
        }),
    };
    let runs = if quick { 5 } else { 31 };
    let m4f = M4f::measure();

    // 1. Intersection formulas.
    let cases = hard_rays(if quick { 20_000 } else { 200_000 });
    let (eye, dirs, spheres) = timing_set(if quick { 2_000 } else { 20_000 });
    let items = dirs.len() * spheres.len();
    let prepared: Vec<Prepared> = spheres.iter().map(|s| Prepared::exact(eye, s)).collect();
    let mut fs: Vec<&mut dyn FnMut() -> f32> = vec![];
    let mut f_textbook = || sum_hits(eye, &dirs, &spheres, textbook);
    let mut f_textbook_vsqrt = || sum_hits(eye, &dirs, &spheres, textbook_vsqrt);
    let mut f_geometric = || sum_hits(eye, &dirs, &spheres, geometric);
    let mut f_hb = || sum_hits(eye, &dirs, &spheres, hearn_baker);
    // A closure, not the fn item: the item's `Fn::call` shim was left out of line (the loop then
    // passed every ray through memory), which the other variants, smaller, escape.
    #[allow(clippy::redundant_closure)]
    let mut f_default = || sum_hits(eye, &dirs, &spheres, |o, d, s| default_per_ray(o, d, s));
    let mut f_f64_c_per_ray = || sum_hits(eye, &dirs, &spheres, f64_c_per_ray);
    let mut f_f32_c_per_ray = || sum_hits(eye, &dirs, &spheres, f32_c_per_ray);
    let mut f_frame = || primary_frame(&dirs, &prepared);
    let mut f_frame4 = || primary_frame4(&dirs, &prepared);
    fs.push(&mut f_textbook);
    fs.push(&mut f_geometric);
    fs.push(&mut f_hb);
    fs.push(&mut f_default);
    fs.push(&mut f_frame);
    fs.push(&mut f_f64_c_per_ray);
    fs.push(&mut f_frame4);
    fs.push(&mut f_textbook_vsqrt);
    fs.push(&mut f_f32_c_per_ray);
    let ns = time_all(items, runs, &mut fs);
    // A second timing set, like the shadow rays of an ordinary scene: origins on the spheres of
    // tests/data/lit.toml, directions away from the surface.
    let lit: Box<Desktop> = scene_file::load("tests/data/lit.toml").unwrap();
    let lit_spheres: Vec<Sphere> = lit.scene.spheres().to_vec();
    let mut g2 = Rng(SEED_SHADOW);
    let shadow_rays: Vec<(Vec3, Vec3, usize)> = (0..if quick { 2_000 } else { 20_000 })
        .map(|k| {
            let n = g2.dir();
            shadow_ray(&lit_spheres, k, n, g2.dir())
        })
        .collect();
    // microray's shading: Prepared::leaving_hit (from the hit's centre and offset, the sphere
    // skipped when certainly behind) ...
    let sum_shading = || {
        shadow_loop(&shadow_rays, &lit_spheres, |_, anchor, rel, s, d| {
            let (lo, hi) = (f32::MIN_POSITIVE, f32::INFINITY);
            Prepared::leaving_hit(anchor, rel, s, d, lo, hi).map(|(t, _)| t)
        })
    };
    // ... and as it tests shadow rays: any hit, no root (Prepared::leaving_blocks)
    let sum_blocks = || {
        shadow_loop(&shadow_rays, &lit_spheres, |_, anchor, rel, s, d| {
            Prepared::leaving_blocks(anchor, rel, s, d, f32::INFINITY).then_some(1.0)
        })
    };
    let shadow_items = shadow_rays.len() * (lit_spheres.len() - 1);
    // The per-ray variants from the ray's origin as one point; a macro, not a helper taking the
    // variant, so that each gets a closure of its own and is inlined into its own copy of the
    // loop (`default_per_ray`'s fn item was not: its `Fn::call` shim stayed out of line).
    macro_rules! per_ray {
        ($variant:ident) => {
            &mut || {
                shadow_loop(&shadow_rays, &lit_spheres, |o, _, _, s, d| {
                    $variant(o, d, s)
                })
            }
        };
    }
    let ns2 = time_all(
        shadow_items,
        runs,
        &mut [
            per_ray!(textbook),
            per_ray!(geometric),
            per_ray!(hearn_baker),
            per_ray!(default_per_ray),
            per_ray!(f64_c_per_ray),
            &mut || sum_shading(),
            &mut || sum_blocks(),
            per_ray!(textbook_vsqrt),
            per_ray!(f32_c_per_ray),
        ],
    );
    let frame_errors = errors(&cases, |o, d, s| {
        Prepared::exact(o, s).hit(d, f32::MIN_POSITIVE, f32::INFINITY)
    });
    // The lanes' hits are the scalar ones bit for bit; measured, not assumed.
    let frame4_errors = errors(&cases, |o, d, s| {
        Prepared::exact(o, s).hit4(&[d; 4], f32::MIN_POSITIVE, [f32::INFINITY; 4])[0]
    });
    // name, plot colour and its name, errors, ns/test, numbench key
    type Row = (
        &'static str,
        [u8; 3],
        &'static str,
        Errors,
        f64,
        &'static str,
    );
    let rows: Vec<Row> = vec![
        (
            "textbook quadratic (-b ± √(b²-4ac))/2a",
            [220, 40, 40],
            "red",
            errors(&cases, textbook),
            ns[0],
            "primary_textbook",
        ),
        (
            "geometric t_m ± Δt",
            [240, 150, 30],
            "orange",
            errors(&cases, geometric),
            ns[1],
            "primary_geometric",
        ),
        (
            "stable roots + Hearn-Baker, f32 c",
            [40, 110, 220],
            "blue",
            errors(&cases, hearn_baker),
            ns[2],
            "primary_hearn_baker",
        ),
        (
            "default, per ray (secondary rays)",
            [30, 160, 60],
            "green",
            errors(&cases, default_per_ray),
            ns[3],
            "primary_default_per_ray",
        ),
        (
            "default, per-frame constants (primary)",
            [20, 90, 30],
            "dark green",
            frame_errors,
            ns[4],
            "primary_frame_constants",
        ),
        (
            "alternative: c always in f64, per ray",
            [150, 60, 200],
            "purple",
            errors(&cases, f64_c_per_ray),
            ns[5],
            "primary_f64_c_per_ray",
        ),
        (
            "default, per-frame constants, 4 directions per vector (primary, hosts)",
            [60, 200, 200],
            "teal",
            frame4_errors,
            ns[6],
            "",
        ),
        // On hosts the same instruction as libm's (sqrtss), on the M4F `vsqrt.f32` instead of
        // libm's software routine; the textbook quadratic's errors. Not plotted: on hosts it is
        // the red point.
        (
            "textbook quadratic, microray's sqrt (vsqrt.f32 on M4F)",
            NOT_PLOTTED,
            "—",
            errors(&cases, textbook_vsqrt),
            ns[7],
            "primary_textbook_vsqrt",
        ),
        // What per-ray costs if the compensation cost nothing; its errors are the f32 c's.
        // Not plotted: a bound, not a variant.
        (
            "floor: the default's roots with plain f32 c, never compensated",
            NOT_PLOTTED,
            "—",
            errors(&cases, f32_c_per_ray),
            ns[8],
            "primary_f32_c_per_ray",
        ),
    ];
    println!("## Ray-sphere intersection\n");
    println!("{} hard rays ({} far/small up to distance/radius 1e5, the rest grounds of radius 1e3..1e6 seen from 1 above); ulp statistics on hits that do not graze.\n", cases.len(), cases.iter().filter(|c| !c.ground).count());
    println!("| variant | plot marker | ns/test (median) | × textbook | max ulp, far/small | max ulp, ground | median ulp | ground max rel. error | false hits | misses | Cortex-M4F instructions/test (× textbook with vsqrt) |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (name, _, colour, e, t, key) in &rows {
        println!(
            "| {name} | {colour} | {t:.2} | {:.2} | {:.3} | {:.3} | {:.2} | {:.1e} | {} | {} | {} |",
            t / ns[0],
            e.max_ulp_far,
            e.max_ulp_ground,
            e.median_ulp,
            e.max_rel_ground,
            e.false_hits,
            e.misses,
            m4f.cell_vs(key, "primary_textbook_vsqrt")
        );
    }
    if m4f.0.is_ok() {
        let first = |key: &str, per: usize| m4f.cell(key).parse::<usize>().map_or(0, |n| n / per);
        println!(
            "\nCortex-M4F instructions/test: counted by examples/firmware/numbench.sh in QEMU (mps2-an386, -icount), instructions not cycles (vdiv.f32 and vsqrt.f32 are one instruction of 14 cycles), on the first {} directions of this timing set and the first {} rays of the shadow-like one below, each variant inlined into its own copy of the loop (as here and in a renderer), the empty loop subtracted. The textbook, geometric and Hearn-Baker rows call libm::sqrtf, a software routine on thumbv7em (~50 instructions); the ratios in brackets are to the textbook quadratic with vsqrt.f32, as microray's rows use it, so that they compare formulas.",
            first("primary_tests", spheres.len()),
            first("shadow_tests", lit_spheres.len() - 1)
        );
    }
    println!("\nThe same per-ray variants timed on shadow-like rays of an ordinary scene (origins on the spheres of tests/data/lit.toml, directions away from the surface, the sphere left not tested; per-frame constants do not apply to rays of their own origin):\n");
    println!("| variant | ns/test (median) | × textbook | Cortex-M4F instructions/test (× textbook with vsqrt) |");
    println!("|---|---:|---:|---:|");
    for (k, (name, key)) in [
        ("textbook quadratic", "shadow_textbook"),
        ("geometric t_m ± Δt", "shadow_geometric"),
        ("stable roots + Hearn-Baker, f32 c", "shadow_hearn_baker"),
        ("default, per ray (ray_intersect)", "shadow_default_per_ray"),
        (
            "alternative: c always in f64, per ray",
            "shadow_f64_c_per_ray",
        ),
        (
            "default as mirror rays call it (Prepared::leaving_hit)",
            "shadow_leaving_hit",
        ),
        (
            "default as shadow rays call it (Prepared::leaving_blocks: any hit, no root)",
            "shadow_leaving_blocks",
        ),
        (
            "textbook quadratic, microray's sqrt (vsqrt.f32 on M4F)",
            "shadow_textbook_vsqrt",
        ),
        (
            "floor: the default's roots with plain f32 c, never compensated",
            "shadow_f32_c_per_ray",
        ),
    ]
    .iter()
    .enumerate()
    {
        println!(
            "| {name} | {:.2} | {:.2} | {} |",
            ns2[k],
            ns2[k] / ns2[0],
            m4f.cell_vs(key, "shadow_textbook_vsqrt")
        );
    }
    // How often the per-ray default computes the compensated c (~100 instructions more): the
    // tests ray_intersect and Prepared::leaving_hit make.
    let cancels = |f: Vec3, s: &Sphere| {
        let (ff, rr) = (f.dot(f), s.radius * s.radius);
        let c = ff - rr;
        !(libm::fabsf(c) > (ff + rr) * 0.5 && c.is_finite())
    };
    let behind = |f: Vec3, s: &Sphere, d: Vec3| {
        let (ff, rr) = (f.dot(f), s.radius * s.radius);
        ff - rr > (ff + rr) * (1.0 / 1_048_576.0) && f.dot(d) >= 0.0
    };
    let per_mille = |k: usize, n: usize| 1000.0 * k as f64 / n as f64;
    let primary = per_mille(
        spheres
            .iter()
            .filter(|s| cancels(eye - s.center, s))
            .count()
            * dirs.len(),
        spheres.len() * dirs.len(),
    );
    let (mut n, mut k_new, mut k_shading) = (0, 0, 0);
    for &(o, d, from) in &shadow_rays {
        for (j, s) in lit_spheres.iter().enumerate() {
            if j != from {
                n += 1;
                let f = o - s.center;
                k_new += cancels(f, s) as usize;
                k_shading += (!behind(f, s, d) && cancels(f, s)) as usize;
            }
        }
    }
    println!(
        "\nc compensated (where f32 c cancels), per 1000 tests: primary-like set, per ray at most {primary:.0} (per-frame constants: none per ray); shadow-like set, ray_intersect at most {:.0}, as shading calls it at most {:.0} (clear misses skip it). The purple variant computes c in f64 (software on a Cortex-M) in every test.",
        per_mille(k_new, n),
        per_mille(k_shading, n),
    );
    // The secondary rays that rendering lit.toml (its sun) and mirror.toml (first bounces)
    // casts: the per-ray paths on the rays a renderer asks about.
    let mirror: Box<Desktop> = scene_file::load("tests/data/mirror.toml").unwrap();
    assert_eq!(
        lit_spheres, LIT_SPHERES,
        "variants.rs's copy of tests/data/lit.toml"
    );
    assert_eq!(
        mirror.scene.spheres(),
        LIT_SPHERES,
        "mirror.toml's spheres are lit.toml's"
    );
    let mirrors: Vec<usize> = (0..LIT_SPHERES.len())
        .filter(|&i| mirror.scene.materials()[i].mirror != microray::Color::ZERO)
        .collect();
    assert_eq!(
        mirrors, MIRROR_SPHERES,
        "variants.rs's mirrors of mirror.toml"
    );
    match lit.scene.lights()[1] {
        microray::Light::Directional { direction, .. } => {
            assert_eq!(-direction, lit_sun(), "variants.rs's sun of lit.toml")
        }
        _ => panic!("lit.toml's second light is its sun"),
    }
    println!("\nThe same variants on the secondary rays that rendering tests/data/lit.toml, mirror.toml and glass.toml casts (160×120, one ray a pixel): the directional light's shadow rays from every primary hit that faces it, which shading tests with Prepared::leaving_blocks, the first mirror bounces and the rays refracted into and out of the glass ball, which it tests with Prepared::leaving_hit (the point light's shadow rays are cast from the light with per-frame constants, as primary rays are). Unlike the shadow-like set above, whose directions cover each point's whole hemisphere, these are the rays a render asks about:\n");
    println!("| rays | tests | variant | ns/test (median) | × textbook | Cortex-M4F instructions/test (× textbook with vsqrt) |");
    println!("|---|---:|---|---:|---:|---:|");
    let sun = Sun::new(&LIT_SPHERES, lit_sun()).unwrap();
    for (kind, key) in [(Secondary::Sun, "sun"), (Secondary::Mirror, "mirror")] {
        let mut rays = vec![(Vec3::ZERO, Vec3::ZERO, 0); 19_200];
        let len = recorded_rays(kind, &mut rays);
        rays.truncate(len);
        let tests = rays.len() * (LIT_SPHERES.len() - 1);
        let (lo, hi) = (f32::MIN_POSITIVE, f32::INFINITY);
        let (what, call) = match kind {
            Secondary::Sun => ("lit.toml's sun", "shadow rays: Prepared::leaving_blocks"),
            Secondary::Mirror => (
                "mirror.toml's bounces",
                "mirror rays: Prepared::leaving_hit",
            ),
        };
        // The set's own loops: the textbook quadratic, ray_intersect, what shading calls (the
        // sun's shadow rays' blocks, the bounces' hits) and, for the sun, the prototype.
        let mut f_textbook = || shadow_loop(&rays, &LIT_SPHERES, |o, _, _, s, d| textbook(o, d, s));
        let mut f_default = || {
            shadow_loop(&rays, &LIT_SPHERES, |o, _, _, s, d| {
                default_per_ray(o, d, s)
            })
        };
        let mut f_blocks = || {
            shadow_loop(&rays, &LIT_SPHERES, |_, anchor, rel, s, d| {
                Prepared::leaving_blocks(anchor, rel, s, d, hi).then_some(1.0)
            })
        };
        let mut f_hit = || {
            shadow_loop(&rays, &LIT_SPHERES, |_, anchor, rel, s, d| {
                Prepared::leaving_hit(anchor, rel, s, d, lo, hi).map(|(t, _)| t)
            })
        };
        let mut f_sun = || {
            sun_loop(&rays, &LIT_SPHERES, &sun, |anchor, rel, s, d| {
                Prepared::leaving_blocks(anchor, rel, s, d, hi)
            })
        };
        let mut fs: Vec<&mut dyn FnMut() -> f32> = vec![&mut f_textbook, &mut f_default];
        match kind {
            Secondary::Sun => fs.extend([&mut f_blocks as &mut dyn FnMut() -> f32, &mut f_sun]),
            Secondary::Mirror => fs.push(&mut f_hit),
        }
        let ns3 = time_all(tests, runs, &mut fs);
        let (shading, prototype) = (ns3[2], ns3.get(3).copied().unwrap_or(f64::NAN));
        let call = format!("default as shading calls it ({call})");
        for (name, variant, ns) in [
            ("textbook quadratic", "textbook", ns3[0]),
            (
                "default, per ray (ray_intersect)",
                "default_per_ray",
                ns3[1],
            ),
            (call.as_str(), "shading", shading),
            (
                "prototype: per-frame constants of the light's direction (Sun), the rest by leaving_blocks",
                "frame",
                prototype,
            ),
        ] {
            if ns.is_nan() {
                continue;
            }
            println!(
                "| {what} | {tests} | {name} | {ns:.2} | {:.2} | {} |",
                ns / ns3[0],
                m4f.cell_vs(&format!("{key}_{variant}"), &format!("{key}_textbook_vsqrt"))
            );
        }
        if m4f.0.is_ok() {
            println!(
                "| {what} | | textbook quadratic, microray's sqrt (vsqrt.f32 on M4F) | | | {} |",
                m4f.cell_vs(
                    &format!("{key}_textbook_vsqrt"),
                    &format!("{key}_textbook_vsqrt")
                )
            );
        }
    }
    // The refracted rays of tests/data/glass.toml: host only (the firmware has no glass).
    let glass: Box<Desktop> = scene_file::load("tests/data/glass.toml").unwrap();
    let rays = refracted_rays(&glass);
    let spheres = glass.scene.spheres();
    let tests = rays.len() * (spheres.len() - 1);
    let mut f_textbook = || shadow_loop(&rays, spheres, |o, _, _, s, d| textbook(o, d, s));
    let mut f_default = || shadow_loop(&rays, spheres, |o, _, _, s, d| default_per_ray(o, d, s));
    let mut f_hit = || {
        shadow_loop(&rays, spheres, |_, anchor, rel, s, d| {
            let hi = f32::INFINITY;
            Prepared::leaving_hit(anchor, rel, s, d, f32::MIN_POSITIVE, hi).map(|(t, _)| t)
        })
    };
    let t = time_all(
        tests,
        runs,
        &mut [&mut f_textbook, &mut f_default, &mut f_hit],
    );
    for (name, ns) in [
        ("textbook quadratic", t[0]),
        ("default, per ray (ray_intersect)", t[1]),
        (
            "default as shading calls it (refracted rays: Prepared::leaving_hit)",
            t[2],
        ),
    ] {
        println!(
            "| glass.toml's refracted rays | {tests} | {name} | {ns:.2} | {:.2} | (no glass on the firmware) |",
            ns / t[0]
        );
    }
    let (tests, decided, wrong) = sun_agreement(if quick { 20_000 } else { 200_000 });
    println!(
        "\nThe prototype (`Sun` in examples/common/variants.rs: per frame, every sphere projected across the light's direction; per ray, the origin; per test, a 2D distance, and the full test only where the projections' error bound leaves the answer open) against Prepared::leaving_blocks on {tests} tests from random points of lit.toml's spheres (also moved by 10⁴, scaled by 10⁻⁴ and 10⁴) and of random scenes, towards random light directions and directions that graze another sphere within 10⁻⁴ of its radius: {decided} ({:.1}%) decided without the full test, {wrong} of them answered differently.",
        100.0 * decided as f64 / tests as f64
    );
    assert_eq!(
        wrong, 0,
        "the Sun prototype must give leaving_blocks's answers"
    );
    if m4f.0.is_ok() {
        let first = |key: &str| m4f.cell(key).parse::<usize>().map_or(0, |n| n / 3);
        println!(
            "\nCortex-M4F columns: the first {} and {} rays of each set (RAM), as counted by numbench.",
            first("sun_tests"),
            first("mirror_tests")
        );
    }
    if let Some(dir) = std::path::Path::new(plot_path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).unwrap();
        }
    }
    plot(
        &rows
            .iter()
            .filter(|r| r.1 != NOT_PLOTTED)
            .map(|r| (r.4, r.3.max_ulp, r.1))
            .collect::<Vec<_>>(),
        plot_path,
    );
    println!("\n(plot: {plot_path} — x: ns per test, log; y: max ulp of t, log; dashed: 4 ulp)");

    // 2. Square roots.
    let mut g = Rng(SEED_ARGS);
    let xs: Vec<f32> = (0..if quick { 10_000 } else { 100_000 })
        .map(|_| 10f64.powf(g.range(-8.0, 8.0)) as f32)
        .collect();
    let sqrt_err = |f: &dyn Fn(f32) -> f32| {
        xs.iter()
            .map(|&x| {
                let r = (x as f64).sqrt();
                (f(x) as f64 - r).abs() / common::reference::ulp32(r)
            })
            .fold(0.0, f64::max)
    };
    let mut s_libm = || xs.iter().map(|&x| libm::sqrtf(black_box(x))).sum::<f32>();
    let mut s_n1 = || {
        xs.iter()
            .map(|&x| rsqrt_newton(black_box(x), 1))
            .sum::<f32>()
    };
    let mut s_n2 = || {
        xs.iter()
            .map(|&x| rsqrt_newton(black_box(x), 2))
            .sum::<f32>()
    };
    let sq_ns = time_all(xs.len(), runs, &mut [&mut s_libm, &mut s_n1, &mut s_n2]);
    let t_err =
        |f: fn(f32) -> f32| errors(&cases, move |o, d, s| hearn_baker_with(o, d, s, f)).max_ulp_far;
    println!("\n## Square root\n");
    println!("| sqrt | ns/call (host) | × libm | max ulp | max ulp of t, far/small (stable roots + HB) | Cortex-M4F instructions/test |");
    println!("|---|---:|---:|---:|---:|---|");
    let m4f_sqrt = match &m4f.0 {
        Ok(_) => format!(
            "{} (libm::sqrtf); {} (microray::math::sqrt)",
            m4f.cell("sqrt_libm_sqrtf"),
            m4f.cell("sqrt_math_sqrt")
        ),
        Err(_) => m4f.cell("sqrt_libm_sqrtf"),
    };
    println!("| libm::sqrtf (host; microray uses vsqrt.f32 on M4F, same bits) | {:.2} | 1.00 | {:.2} | {:.3e} | {m4f_sqrt} |", sq_ns[0], sqrt_err(&libm::sqrtf), t_err(libm::sqrtf));
    let newton: [fn(f32) -> f32; 2] = [|x| rsqrt_newton(x, 1), |x| rsqrt_newton(x, 2)];
    for (k, f) in (1..).zip(newton) {
        let steps = if k == 1 {
            "1 Newton step"
        } else {
            "2 Newton steps"
        };
        println!(
            "| bit-trick rsqrt + {steps}, × x | {:.2} | {:.2} | {:.0} | {:.3e} | {} |",
            sq_ns[k],
            sq_ns[k] / sq_ns[0],
            sqrt_err(&f),
            t_err(f),
            m4f.cell(&format!("sqrt_rsqrt_newton{k}"))
        );
    }

    // 3. Specular powers.
    let xs: Vec<f32> = (0..if quick { 10_000 } else { 100_000 })
        .map(|_| g.range(0.5, 1.0) as f32)
        .collect();
    println!("\n## Specular power x^s (x = n·h in [0.5, 1]; error in 8-bit levels at k_s I = 1)\n");
    println!("| s | powf ns | squaring ns | Schlick ns | powf max levels | squaring max levels | Schlick max levels | Cortex-M4F instructions/test: powf / microray::math::spec_pow (this table's squaring) / Schlick |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---|");
    for s in [8u32, 32, 128, 1000, 5000] {
        let sf = s as f32;
        let mut p1 = || {
            xs.iter()
                .map(|&x| libm::powf(black_box(x), sf))
                .sum::<f32>()
        };
        let mut p2 = || {
            xs.iter()
                .map(|&x| pow_squaring(black_box(x), s))
                .sum::<f32>()
        };
        let mut p3 = || {
            xs.iter()
                .map(|&x| pow_schlick(black_box(x), sf))
                .sum::<f32>()
        };
        let t = time_all(xs.len(), runs, &mut [&mut p1, &mut p2, &mut p3]);
        let lv = |f: &dyn Fn(f32) -> f32| {
            xs.iter()
                .map(|&x| 255.0 * (f(x) as f64 - (x as f64).powf(s as f64)).abs())
                .fold(0.0, f64::max)
        };
        let m4f_pow = match &m4f.0 {
            Ok(_) => format!(
                "{} / {} ({}) / {}",
                m4f.cell(&format!("pow_s{s}_powf")),
                m4f.cell(&format!("pow_s{s}_spec_pow")),
                m4f.cell(&format!("pow_s{s}_squaring")),
                m4f.cell(&format!("pow_s{s}_schlick"))
            ),
            Err(_) => m4f.cell("pow_args"),
        };
        println!(
            "| {s} | {:.2} | {:.2} | {:.2} | {:.4} | {:.4} | {:.1} | {m4f_pow} |",
            t[0],
            t[1],
            t[2],
            lv(&|x| libm::powf(x, sf)),
            lv(&|x| pow_squaring(x, s)),
            lv(&|x| pow_schlick(x, sf))
        );
    }

    // 4. Whole images: microray's f32 default against the f64 reference.
    println!("\n## Whole image: f32 against the f64 reference\n");
    println!("Pixels off by more than 1 / more than 8 levels (not excused by the 2-ulp rule) and ns per pixel. The plain renderers differ only in the intersection formula; microray is the library's `Frame`; the f64 column is the test reference.\n");
    println!("| scene | pixels | textbook | geometric | stable + HB, f32 c | stable + HB, f64 c | microray | f64 reference ns/pixel |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let mut names: Vec<String> = std::fs::read_dir("tests/hard")
        .unwrap()
        .filter_map(|e| e.ok()?.path().file_stem()?.to_str().map(String::from))
        .collect();
    names.sort();
    let variants: [Isect; 4] = [textbook, geometric, hearn_baker, f64_c_per_ray];
    let mut fails = [0usize; 5];
    for name in &names {
        let file: Box<Desktop> = scene_file::load(format!("tests/hard/{name}.toml")).unwrap();
        let mut storage = microray::FrameStorage::on_heap();
        let frame = Frame::new(&file.scene, &file.camera, file.options, &mut storage).unwrap();
        let reference = common::reference::Reference::new(&file);
        let (w, h) = (file.camera.width(), file.camera.height());
        let mut buf = vec![embedded_graphics::pixelcolor::Rgb888::new(0, 0, 0); (w * h) as usize];
        let img_runs = if quick { 3 } else { 9 };
        let plains: Vec<Plain> = variants
            .iter()
            .map(|&isect| Plain { file: &file, isect })
            .collect();
        let mut r32 = || {
            frame.render(&mut buf).unwrap();
            0.0
        };
        let mut r64 = || {
            black_box(reference.render());
            0.0
        };
        let mut p0 = || black_box(plains[0].render()).pixels.len() as f32;
        let mut p1 = || black_box(plains[1].render()).pixels.len() as f32;
        let mut p2 = || black_box(plains[2].render()).pixels.len() as f32;
        let mut p3 = || black_box(plains[3].render()).pixels.len() as f32;
        let t = time_all(
            (w * h) as usize,
            img_runs,
            &mut [&mut p0, &mut p1, &mut p2, &mut p3, &mut r32, &mut r64],
        );
        let mut cells = vec![];
        for (k, img) in plains
            .iter()
            .map(|p| p.render())
            .chain(std::iter::once(common::render(&file)))
            .enumerate()
        {
            let a = common::agreement(&file, &img);
            fails[k] += !a.holds() as usize;
            cells.push(format!("{} / {} ({:.0} ns)", a.over1, a.over8, t[k]));
        }
        println!(
            "| {name} | {} | {} | {:.0} |",
            w * h,
            cells.join(" | "),
            t[5]
        );
    }
    println!(
        "| **scenes failing the goal** | | {} | {} | {} | {} | {} | |",
        fails[0], fails[1], fails[2], fails[3], fails[4]
    );
}

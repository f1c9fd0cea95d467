//! An independent double-precision renderer of microray's model, for tests.
//!
//! It reads the parsed scene (whose numbers are f32) and does everything else in f64 with
//! textbook formulas: its own vectors, camera, intersection, shading and encoding. It shares no
//! numerical code with the library, so agreement is evidence and not an echo.
//!
//! The only concession to f64 not being exact: the quadratic's smaller root is computed as
//! `c / q` (otherwise the root near zero of a shadow ray would be f64 noise) and a ray leaving
//! a sphere's surface meets that sphere only at its other root `−2b/a` (the model's "no
//! self-shadow acne").
#![allow(dead_code)]

use microray::scene_file::SceneFile;
use microray::{Encoding, Light};

pub type V = [f64; 3];

pub fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn mul(a: V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub fn had(a: V, b: V) -> V {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}
pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: V, b: V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn norm(a: V) -> V {
    mul(a, 1.0 / dot(a, a).sqrt())
}
fn v(p: microray::Vec3) -> V {
    [p.x as f64, p.y as f64, p.z as f64]
}

pub struct RSphere {
    pub c: V,
    pub r: f64,
    kd: V,
    ks: V,
    s: f64,
    km: V,
    kt: V,
    ior: f64,
}

pub enum RLight {
    Point(V, V),
    Dir(V, V),
}

/// The scene and camera in f64.
pub struct Reference {
    pub spheres: Vec<RSphere>,
    pub lights: Vec<RLight>,
    ambient: V,
    background: V,
    shadows: bool,
    max_depth: u32,
    pub eye: V,
    u: V,
    vv: V,
    w: V,
    pub width: u32,
    pub height: u32,
    fov_a: f64,
    samples: u32,
    srgb: bool,
}

/// The smaller and larger root of `a t² + 2 b t + c = 0`, `None` when it has none.
pub fn roots(o: V, d: V, center: V, r: f64) -> Option<(f64, f64)> {
    let f = sub(o, center);
    let a = dot(d, d);
    let b = dot(f, d);
    let c = dot(f, f) - r * r;
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    if q == 0.0 {
        return Some((0.0, 0.0));
    }
    let (t0, t1) = (c / q, q / a);
    Some((t0.min(t1), t0.max(t1)))
}

/// The near root (t > 0 first) in f64 of an f32 ray and sphere, or None: the ground truth of
/// the ray-level accuracy tests and of the speed-against-error report (Hearn–Baker
/// discriminant, stable roots).
pub fn reference_t(o: microray::Vec3, d: microray::Vec3, s: &microray::Sphere) -> Option<f64> {
    let v = |p: microray::Vec3| [p.x as f64, p.y as f64, p.z as f64];
    reference_t64(v(o), v(d), v(s.center), s.radius as f64)
}

/// [`reference_t`] for inputs already in f64 (an origin that is a sum of f32 vectors, exact in
/// f64 but not in f32).
pub fn reference_t64(o: V, d: V, m: V, r: f64) -> Option<f64> {
    let f = [o[0] - m[0], o[1] - m[1], o[2] - m[2]];
    let (a, b) = (dot(d, d), dot(f, d));
    let c = dot(f, f) - r * r;
    let k = b / a;
    let l = [f[0] - k * d[0], f[1] - k * d[1], f[2] - k * d[2]];
    let disc = a * (r * r - dot(l, l));
    if disc < 0.0 {
        return None;
    }
    let q = -(b + b.signum() * disc.sqrt());
    let (t0, t1) = (c / q, q / a);
    let (t0, t1) = (t0.min(t1), t0.max(t1));
    if t0 > 0.0 {
        Some(t0)
    } else if t1 > 0.0 {
        Some(t1)
    } else {
        None
    }
}

impl Reference {
    pub fn new<const S: usize, const L: usize>(file: &SceneFile<S, L>) -> Self {
        let sc = &file.scene;
        let spheres = sc
            .spheres()
            .iter()
            .zip(sc.materials())
            .map(|(s, m)| RSphere {
                c: v(s.center),
                r: s.radius as f64,
                kd: v(m.diffuse),
                ks: v(m.specular),
                s: m.shininess as f64,
                km: v(m.mirror),
                kt: v(m.refraction),
                ior: m.ior as f64,
            })
            .collect();
        let lights = sc
            .lights()
            .iter()
            .map(|l| match *l {
                Light::Point {
                    position,
                    intensity,
                } => RLight::Point(v(position), v(intensity)),
                Light::Directional {
                    direction,
                    intensity,
                } => RLight::Dir(norm(v(direction)), v(intensity)),
            })
            .collect();
        let view = file.view;
        let eye = v(view.eye);
        let w = norm(sub(v(view.look_at), eye));
        let up = v(view.up);
        let up = mul(up, 1.0 / up[0].abs().max(up[1].abs()).max(up[2].abs()));
        let u = norm(cross(w, up));
        let vv = cross(u, w);
        Reference {
            spheres,
            lights,
            ambient: v(sc.ambient()),
            background: v(sc.background()),
            shadows: sc.shadows(),
            max_depth: sc.max_depth() as u32,
            eye,
            u,
            vv,
            w,
            fov_a: ((view.vfov as f64).to_radians() / 2.0).tan(),
            width: file.camera.width(),
            height: file.camera.height(),
            samples: file.options.samples as u32,
            srgb: file.options.encoding == Encoding::Srgb,
        }
    }

    /// The unit primary direction through image point (x, y).
    pub fn direction(&self, x: f64, y: f64) -> V {
        let (wf, hf) = (self.width as f64, self.height as f64);
        let a = self.fov_a;
        let px = (2.0 * x / wf - 1.0) * a * wf / hf;
        let py = (1.0 - 2.0 * y / hf) * a;
        norm(add(add(self.w, mul(self.u, px)), mul(self.vv, py)))
    }

    /// The closest sphere hit along `o + t d`, t > 0; `from` is the sphere the ray leaves, with
    /// the offset `o − centre` of its start.
    pub fn closest(&self, o: V, d: V, from: Option<(usize, V)>) -> Option<(f64, usize, V)> {
        let mut best: Option<(f64, usize, V)> = None;
        for (i, s) in self.spheres.iter().enumerate() {
            let (t, f) = match from {
                Some((j, f)) if j == i => (-2.0 * dot(f, d) / dot(d, d), f),
                _ => {
                    let f = sub(o, s.c);
                    match roots(o, d, s.c, s.r) {
                        Some((t0, t1)) => (if t0 > 0.0 { t0 } else { t1 }, f),
                        None => continue,
                    }
                }
            };
            if t > 0.0 && best.is_none_or(|b| t < b.0) {
                best = Some((t, i, add(f, mul(d, t))));
            }
        }
        best
    }

    pub fn blocked(&self, p: V, from: usize, off: V, light: &RLight) -> bool {
        let (d, tmax) = match *light {
            RLight::Point(pos, _) => (sub(pos, p), 1.0),
            RLight::Dir(dir, _) => (mul(dir, -1.0), f64::INFINITY),
        };
        self.spheres.iter().enumerate().any(|(i, s)| {
            let t = if i == from {
                -2.0 * dot(off, d) / dot(d, d)
            } else {
                match roots(p, d, s.c, s.r) {
                    Some((t0, t1)) => {
                        if t0 > 0.0 {
                            t0
                        } else {
                            t1
                        }
                    }
                    None => return false,
                }
            };
            t > 0.0 && t < tmax
        })
    }

    /// The linear colour seen from `o` along `d`.
    pub fn trace(&self, o: V, d: V, from: Option<(usize, V)>, depth: u32) -> V {
        let Some((t, i, off)) = self.closest(o, d, from) else {
            return self.background;
        };
        let s = &self.spheres[i];
        let p = add(o, mul(d, t));
        let mut n = mul(off, 1.0 / s.r);
        if dot(d, n) > 0.0 {
            n = mul(n, -1.0);
        }
        let view = mul(norm(d), -1.0);
        let mut col = had(s.kd, self.ambient);
        for light in &self.lights {
            let (l, int) = match *light {
                RLight::Point(pos, int) => (norm(sub(pos, p)), int),
                RLight::Dir(dir, int) => (mul(dir, -1.0), int),
            };
            let nl = dot(n, l);
            if nl <= 0.0 || (self.shadows && self.blocked(p, i, off, light)) {
                continue;
            }
            let h = norm(add(view, l));
            let spec = dot(n, h).max(0.0).powf(s.s);
            col = add(col, had(int, add(mul(s.kd, nl), mul(s.ks, spec))));
        }
        if s.km != [0.0; 3] && depth < self.max_depth {
            let r = sub(d, mul(n, 2.0 * dot(d, n)));
            col = add(col, had(s.km, self.trace(p, r, Some((i, off)), depth + 1)));
        }
        if s.kt != [0.0; 3] && depth < self.max_depth {
            let t = refracted(d, n, dot(off, n) > 0.0, s.ior);
            col = add(col, had(s.kt, self.trace(p, t, Some((i, off)), depth + 1)));
        }
        col
    }

    fn encode(&self, c: f64) -> u8 {
        let c = c.clamp(0.0, 1.0);
        let e = if !self.srgb {
            c
        } else if c <= 0.0031308 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (255.0 * e + 0.5).floor() as u8
    }

    /// Pixel (i, j), every primary direction moved by `k` f32 ulp per component (`k = [0; 3]`:
    /// the pixel itself).
    pub fn pixel(&self, i: u32, j: u32, k: [f64; 3]) -> [u8; 3] {
        let n = self.samples;
        let mut sum = [0.0; 3];
        for sy in 0..n {
            for sx in 0..n {
                let x = i as f64 + (sx as f64 + 0.5) / n as f64;
                let y = j as f64 + (sy as f64 + 0.5) / n as f64;
                let mut d = self.direction(x, y);
                for c in 0..3 {
                    d[c] += k[c] * ulp32(d[c]);
                }
                sum = add(sum, self.trace(self.eye, d, None, 0));
            }
        }
        let c = mul(sum, 1.0 / (n * n) as f64);
        [self.encode(c[0]), self.encode(c[1]), self.encode(c[2])]
    }

    /// Whether pixel (i, j) changes by more than one level when its rays move by 2 f32 ulp of
    /// their direction (per component, all sign patterns): an edge or tangent no f32 renderer
    /// can decide.
    pub fn sensitive(&self, i: u32, j: u32) -> bool {
        let base = self.pixel(i, j, [0.0; 3]);
        let mut ks = vec![];
        for c in 0..3 {
            for s in [-2.0, 2.0] {
                let mut k = [0.0; 3];
                k[c] = s;
                ks.push(k);
            }
        }
        for m in 0..8 {
            ks.push([0, 1, 2].map(|c| if m >> c & 1 == 1 { 2.0 } else { -2.0 }));
        }
        ks.iter().any(|&k| {
            let p = self.pixel(i, j, k);
            (0..3).any(|c| p[c].abs_diff(base[c]) > 1)
        })
    }

    /// The background as a pixel.
    pub fn pixel_background(&self) -> [u8; 3] {
        let b = self.background;
        [self.encode(b[0]), self.encode(b[1]), self.encode(b[2])]
    }

    /// The whole image, row by row.
    pub fn render(&self) -> Vec<[u8; 3]> {
        let mut out = Vec::with_capacity((self.width * self.height) as usize);
        for j in 0..self.height {
            for i in 0..self.width {
                out.push(self.pixel(i, j, [0.0; 3]));
            }
        }
        out
    }
}

/// The refracted direction (unit) of a ray along `d` at a hit with facing normal `n`, entering
/// the sphere or leaving it, or the mirror direction beyond the critical angle: the textbook
/// formula.
pub fn refracted(d: V, n: V, entering: bool, ior: f64) -> V {
    let d = norm(d);
    let eta = if entering { 1.0 / ior } else { ior };
    let cos_i = -dot(d, n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        sub(d, mul(n, 2.0 * dot(d, n)))
    } else {
        add(mul(d, eta), mul(n, eta * cos_i - k.sqrt()))
    }
}

/// The spacing of f32 numbers at `x` (as an f64).
pub fn ulp32(x: f64) -> f64 {
    let x = (x as f32).abs();
    if !x.is_finite() {
        return 0.0;
    }
    let next = f32::from_bits(x.to_bits() + 1);
    (next - x) as f64
}

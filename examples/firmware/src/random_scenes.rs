//! Random scenes from a seed, shared word for word by the `scenes` firmware
//! (`src/bin/scenes.rs`) and the host test (`tests/firmware.rs`, through `#[path = ...]`), with
//! the CRC-32 of each one's frame. Both check every scene against [`EXPECTED`]: if the host and
//! the microcontroller print the same CRCs, they computed the same pixels on every scene.
//!
//! The generator uses integers and exact conversions only (a 64-bit xorshift, 24 random bits
//! times 2⁻²⁴), then the f32 operations `+`, `−` and `×`, which round the same on every IEEE
//! target without fused multiply-add: each board builds the host's scene bit for bit.
//!
//! `no_std`, heap-free; the scenes fit the micro:bit's 16 KiB of RAM.

use microray::{
    Camera, Color, Encoding, Error, Frame, Light, Material, RenderOptions, Scene, Sphere, Vec3,
};

/// Image width of every scene, in pixels.
pub const WIDTH: u32 = 32;
/// Image height of every scene, in pixels.
pub const HEIGHT: u32 = 24;
/// Sphere capacity (the scan rather than sweeps, as on a microcontroller: `Frame::SWEEPS`).
pub const SPHERES: usize = 8;
/// Light capacity.
pub const LIGHTS: usize = 3;
/// Number of scenes.
pub const COUNT: usize = 56;
/// The seed of scene `k` is `SEED + k`.
pub const SEED: u64 = 0x9e37_79b9_7f4a_7c15;

/// A random scene's type.
pub type RandomScene = Scene<SPHERES, LIGHTS>;

/// What a scene stresses; scene `k` is of kind `k % 8`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Unit-sized spheres and lights.
    Ordinary,
    /// The ordinary scene scaled down to 10⁻⁴…10⁻³.
    Tiny,
    /// The ordinary scene scaled up to 10³…10⁵.
    Huge,
    /// The ordinary scene, camera included, moved 10³…3·10⁴ away from the origin.
    Far,
    /// A ground sphere of radius 10³…10⁶ under the spheres, the eye near its horizon.
    Ground,
    /// Lights at grazing angles: a directional light almost parallel to the ground, point lights
    /// just above it.
    Grazing,
    /// Several mirrors, reflections up to depth 6.
    Mirrors,
    /// The spheres seen from 10³…10⁴ away through a field of view a fraction of a degree wide.
    Narrow,
}

const KINDS: [Kind; 8] = [
    Kind::Ordinary,
    Kind::Tiny,
    Kind::Huge,
    Kind::Far,
    Kind::Ground,
    Kind::Grazing,
    Kind::Mirrors,
    Kind::Narrow,
];

/// The kind of scene `k`.
pub const fn kind(k: usize) -> Kind {
    KINDS[k % KINDS.len()]
}

/// xorshift64 (Marsaglia): integers only, the same sequence on every target.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// A generator from `seed` (0 is replaced: xorshift would stay at 0).
    pub const fn new(seed: u64) -> Self {
        Rng(if seed == 0 { 1 } else { seed })
    }

    /// The next 64 random bits.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1): 24 bits, converted exactly.
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// One of `n` choices.
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.next() >> 32) % n as u64) as u32
    }

    /// One of `values`.
    pub fn pick(&mut self, values: &[f32]) -> f32 {
        values[self.below(values.len() as u32) as usize]
    }

    fn vec(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }

    fn color(&mut self, lo: f32, hi: f32) -> Color {
        Color::new(self.range(lo, hi), self.range(lo, hi), self.range(lo, hi))
    }
}

/// Where a unit-sized scene goes: `offset + scale · p` for its points, `scale · r` for radii.
#[derive(Debug, Clone, Copy)]
struct Place {
    scale: f32,
    offset: Vec3,
}

impl Place {
    fn point(self, p: Vec3) -> Vec3 {
        self.offset + p * self.scale
    }
}

/// Builds scene `k` into `scene` (which must be empty) and returns its camera and options.
/// Every scene builds on every target (the host test checks that no value is refused).
pub fn build(k: usize, scene: &mut RandomScene) -> Result<(Camera, RenderOptions), Error> {
    let mut g = Rng::new(SEED.wrapping_add(k as u64));
    let kind = kind(k);
    let place = match kind {
        Kind::Tiny => Place {
            scale: g.pick(&[1e-4, 3e-4, 1e-3]),
            offset: Vec3::ZERO,
        },
        Kind::Huge => Place {
            scale: g.pick(&[1e3, 1e4, 1e5]),
            offset: Vec3::ZERO,
        },
        Kind::Far => {
            let d = g.pick(&[1e3, 1e4, 3e4]);
            let dir = g.vec(Vec3::splat(-1.0), Vec3::splat(1.0));
            Place {
                scale: 1.0,
                offset: dir * d,
            }
        }
        _ => Place {
            scale: 1.0,
            offset: Vec3::ZERO,
        },
    };
    scene.set_ambient(g.color(0.0, 0.2))?;
    scene.set_background(g.color(0.0, 0.4))?;
    scene.set_shadows(g.below(5) != 0);
    scene.set_max_depth(if kind == Kind::Mirrors {
        1 + g.below(6) as u8
    } else {
        g.below(3) as u8
    })?;

    // The ground: huge for `Ground`, always for `Grazing`, none seen from afar, else on a coin.
    let ground = match kind {
        Kind::Ground => Some(g.pick(&[1e3, 1e4, 1e5, 1e6])),
        Kind::Grazing => Some(1e3),
        Kind::Narrow => None,
        _ if g.below(2) == 0 => Some(1e3),
        _ => None,
    };
    if let Some(r) = ground {
        let m = Material {
            diffuse: g.color(0.3, 0.8),
            ..Material::default()
        };
        let c = place.point(Vec3::new(0.0, -r, 0.0));
        scene.add_sphere(Sphere::new(c, r * place.scale), m)?;
    }
    let n = 2 + g.below((SPHERES - 2) as u32) as usize;
    for _ in 0..n {
        let r = g.range(0.15, 1.2);
        let c = g.vec(Vec3::new(-2.5, r - 0.2, -2.5), Vec3::new(2.5, r + 1.5, 2.5));
        let mirror = match kind {
            Kind::Mirrors if g.below(3) != 0 => g.color(0.5, 0.95),
            _ if g.below(6) == 0 => g.color(0.1, 0.6),
            _ => Color::splat(0.0),
        };
        let m = Material {
            diffuse: g.color(0.05, 0.95),
            specular: if g.below(3) == 0 {
                Color::splat(0.0)
            } else {
                g.color(0.1, 0.8)
            },
            shininess: g.pick(&[1.0, 8.0, 32.0, 128.0, 1000.0]),
            mirror,
            ..Material::default()
        };
        // A full scene is not an error here: the capacity bounds `n`.
        if scene.spheres().len() < SPHERES {
            scene.add_sphere(Sphere::new(place.point(c), r * place.scale), m)?;
        }
    }
    for _ in 0..1 + g.below(LIGHTS as u32) {
        let intensity = g.color(0.2, 0.9);
        let light = if g.below(2) == 0 {
            let p = if kind == Kind::Grazing {
                g.vec(Vec3::new(-8.0, 0.02, -8.0), Vec3::new(8.0, 0.3, 8.0))
            } else {
                g.vec(Vec3::new(-6.0, 2.0, -6.0), Vec3::new(6.0, 9.0, 6.0))
            };
            Light::Point {
                position: place.point(p),
                intensity,
            }
        } else {
            let y = if kind == Kind::Grazing {
                g.range(-0.02, -0.001)
            } else {
                g.range(-1.0, -0.2)
            };
            Light::Directional {
                direction: Vec3::new(g.range(-1.0, 1.0), y, g.range(-1.0, 1.0)),
                intensity,
            }
        };
        scene.add_light(light)?;
    }

    let look = g.vec(Vec3::new(-0.5, 0.3, -0.5), Vec3::new(0.5, 1.0, 0.5));
    let (eye, vfov) = match kind {
        Kind::Narrow => {
            let d = g.pick(&[1e3, 3e3, 1e4]);
            let dir = g.vec(Vec3::new(-1.0, 0.1, 0.5), Vec3::new(1.0, 0.6, 1.0));
            // About 5 units of the scene across at distance d: 2·atan(2.5 / d) ≈ 5 / d radians
            // (the eye is 0.5 d to 1.5 d away).
            (look + dir * d, 286.0 / d)
        }
        Kind::Ground => {
            let eye = g.vec(Vec3::new(-6.0, 0.3, 5.0), Vec3::new(6.0, 1.5, 9.0));
            (eye, g.range(30.0, 70.0))
        }
        _ => {
            let eye = g.vec(Vec3::new(-5.0, 1.0, 4.0), Vec3::new(5.0, 4.0, 7.0));
            (eye, g.range(40.0, 75.0))
        }
    };
    let camera = Camera::new(
        place.point(eye),
        place.point(look),
        Vec3::new(0.0, 1.0, 0.0),
        vfov,
        WIDTH,
        HEIGHT,
    )?;
    let options = RenderOptions {
        samples: 1 + ((k / KINDS.len()) % 3) as u8,
        encoding: if g.below(2) == 0 {
            Encoding::Linear
        } else {
            Encoding::Srgb
        },
    };
    Ok((camera, options))
}

/// The CRC-32 of every scene's `Rgb888` frame (`scene::crc_rgb888`: bytes r, g, b per pixel,
/// rows from the top), as the firmware prints them on both boards and the host computes them.
pub const EXPECTED: [u32; COUNT] = [
    0x023a815b, 0xe891da8e, 0xca0ff8f5, 0xdd8f02fb, 0xd55524a0, 0x492fbefe, 0x62d9991a, 0xc97eab16,
    0x6e7fc29f, 0x96188818, 0x0e0c5468, 0x212e4b48, 0xb246b15c, 0xc85c041b, 0xf518e7c4, 0xfd5baf5d,
    0xaaab3b8b, 0xa08b4af7, 0x0b19c65d, 0x4ef8b265, 0xb81fca22, 0x7a9b1bc8, 0xc4be33fb, 0x9afa5f3c,
    0xe73fd1bd, 0x50ddf078, 0x960de5dd, 0x337b3e9f, 0x8ac5015c, 0xb5c0140f, 0x7530c05f, 0xf3ef239f,
    0xabb1e918, 0x2ec7c083, 0xd7868597, 0x4b0cd02a, 0x66e8a07b, 0xdbed4927, 0x4f44ff88, 0x95a214b2,
    0xe8fd2d57, 0x60eeffe0, 0x8d8cf2fb, 0x4c3c1632, 0x47325e69, 0x0b73ba02, 0x2a7b6ab7, 0xccd97830,
    0x7dca26b5, 0xf8db113f, 0x332eeb32, 0xd0748c0c, 0x2a755c0b, 0x9aa1ad15, 0x54769c05, 0xfef91c8c,
];

/// Renders scene `k` in `storage` and returns its CRC-32, or the error of a scene that does
/// not build.
pub fn crc_of(
    k: usize,
    scene: &mut RandomScene,
    storage: &mut microray::FrameStorage<SPHERES, LIGHTS, microray::render::Small>,
) -> Result<u32, Error> {
    let (camera, options) = build(k, scene)?;
    let frame = Frame::new(scene, &camera, options, storage)?;
    Ok(crate::scene::crc_rgb888::<WIDTH, HEIGHT, SPHERES, LIGHTS>(&frame).0)
}

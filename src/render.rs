//! Rendering: per-frame constants, the pixel loop, supersampling and pixel encoding.
//!
//! # How a frame is traced fast
//!
//! [`Frame::new`] computes what all rays of the frame share: for the eye, `o − m` and
//! `|o − m|² − r²` of every sphere ([`Prepared::exact`]); for every point light (when shadows
//! are on) the `c = |o − m|² − r²` of those constants (the rest is rebuilt exactly when used);
//! for every sphere its exact, conservative screen-space box ([`crate::raster`]); and for every
//! light (with shadows) its spheres sorted by a 1-D key, to find shadow candidates by a binary
//! search.
//! [`Frame::render_rows`] then walks each row in spans of [`SPAN`] pixels:
//!
//! 1. the row's spheres are those whose box crosses it, the span's those whose box overlaps
//!    the span, in scene order; a primary ray tests only the span's spheres whose box holds
//!    its pixel;
//! 2. with shadows on, the span's primary hits are traced first, grouped by the sphere hit and
//!    each group bounded by a ball; for each group and light, only the spheres that can meet a
//!    shadow ray from that ball are kept (for a point light: the cone hull of the light and the
//!    ball; for a directional light: the ball swept along the light), found in the light's
//!    sorted band (never a group's own sphere, which shadow rays leave analytically); shadow
//!    rays stop at the first blocker;
//! 3. the pixels are shaded with those lists, from the stored hits and ray directions; every
//!    miss shows the background whatever its ray, so the row shades one miss for all.
//!
//! Every list is a superset of the spheres the full test could report, and the tests
//! themselves are the brute-force ones, in the same order where order matters (the closest
//! hit keeps the last of equal `t`s): the pixels are the brute-force pixels, bit for bit
//! ([`Frame::render_rows_brute`] is kept as the reference). Mirror rays, which leave from
//! anywhere, are traced against every sphere.
//!
//! A scene pays only for what it has: without lights or shadows, step 2 is skipped; no
//! specular or mirror work is done for materials without them.

use embedded_graphics::pixelcolor::Rgb888;

use crate::camera::{sample_offset, Camera};
use crate::error::Error;
use crate::geometry::{hit_point_near, Prepared, Ray};
use crate::math::{powf, Color, Vec3};
use crate::raster::{PixelBox, Screen, ETA};
use crate::scene::{hit_from_offset, make_hit, Hit, Light, Scene};
use crate::shading::{follow, in_shadow_among, shade_lit, T_EPS};

/// How linear colour becomes a byte.
///
/// ```
/// use microray::{render::encode_channel, Encoding};
/// assert_eq!(encode_channel(0.5, Encoding::Linear), 128);
/// assert_eq!(encode_channel(0.5, Encoding::Srgb), 188);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Encoding {
    /// The channel value as it is.
    #[default]
    Linear,
    /// The sRGB transfer curve (`12.92c` below 0.0031308, else `1.055c^(1/2.4) − 0.055`).
    Srgb,
}

/// Per-frame settings that are not part of the scene.
///
/// ```
/// use microray::{Encoding, RenderOptions};
/// let opts = RenderOptions { samples: 3, encoding: Encoding::Srgb };
/// assert_eq!(RenderOptions::default().samples, 1);
/// # let _ = opts;
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RenderOptions {
    /// Samples per pixel along each axis (1..=16): `samples²` rays per pixel.
    pub samples: u8,
    /// How pixels are encoded.
    pub encoding: Encoding,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            samples: 1,
            encoding: Encoding::Linear,
        }
    }
}

/// Clamps a linear channel to [0, 1], encodes it and rounds to a byte (NaN counts as 0).
///
/// ```
/// use microray::{render::encode_channel, Encoding};
/// assert_eq!(encode_channel(2.0, Encoding::Linear), 255);
/// assert_eq!(encode_channel(-1.0, Encoding::Srgb), 0);
/// assert_eq!(encode_channel(f32::NAN, Encoding::Linear), 0);
/// ```
#[inline]
pub fn encode_channel(c: f32, encoding: Encoding) -> u8 {
    let v = match encoding {
        // Not clamped first: 255c + 0.5 is monotone in c, so a c ≥ 1 gives ≥ 255.5 and a
        // c ≤ 0 at most 0.5, which the cast below maps to 255 and 0 as the clamp would.
        Encoding::Linear => 255.0 * c + 0.5,
        Encoding::Srgb => {
            let c = if c > 0.0 {
                if c < 1.0 {
                    c
                } else {
                    1.0
                }
            } else {
                0.0
            };
            255.0 * srgb(c) + 0.5
        }
    };
    // The cast saturates (NaN to 0), which a Cortex-M4F's `vcvt` does by itself, and truncates,
    // which is floor for v ≥ 0; the clamp is one `usat` there.
    (v as i32).clamp(0, 255) as u8
}

/// [`encode_channel`] with [`Encoding::Linear`] of four channel values in vector lanes: `255c +
/// 0.5`, then the saturating cast's cases as selections (NaN and below 0 give 0, 256 and above
/// 255) and a plain truncation of what is left, in `[0, 256)`: the same bytes, as integer lanes.
#[cfg(lanes)]
#[inline(always)]
fn linear_bytes(c: crate::math::lanes::F) -> wide::i32x4 {
    use crate::math::lanes::F;
    use wide::{CmpGe, CmpLt};
    let v = F::splat(255.0) * c + F::splat(0.5);
    let (zero, top, end) = (F::ZERO, F::splat(255.0), F::splat(256.0));
    let outside = v.cmp_ge(end).blend(top, zero);
    let v = (v.cmp_ge(zero) & v.cmp_lt(end)).blend(v, outside);
    v.fast_trunc_int()
}

/// The sRGB transfer curve on [0, 1]. Out of line: one copy for the three channels.
#[inline(never)]
fn srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * powf(c, 1.0 / 2.4) - 0.055
    }
}

/// Pixels per span: the unit for which the renderer gathers candidate spheres.
pub const SPAN: usize = 32;

/// A scene, a camera and options, with everything that all rays of the frame share computed
/// once: `o − m` and `|o − m|² − r²` of every sphere for the eye and for every point light,
/// and every sphere's box on the screen.
///
/// Build it once, then render the whole image, bands of rows, single pixels, or draw onto an
/// embedded-graphics display.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microray::{Camera, Color, Frame, Light, Material, RenderOptions, Scene, Sphere, Vec3};
///
/// let mut scene: Scene<4, 1> = Scene::new();
/// scene.set_ambient(Color::splat(0.1))?;
/// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
/// scene.add_light(Light::Point { position: Vec3::new(3.0, 5.0, 4.0), intensity: Color::ONE })?;
/// let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 32, 24)?;
/// let frame = Frame::new(&scene, &camera, RenderOptions::default())?;
///
/// let mut image = [Rgb888::new(0, 0, 0); 32 * 24];
/// frame.render(&mut image)?;
/// assert_eq!(image[0], Rgb888::new(0, 0, 0)); // the corner sees the black background
/// assert_ne!(image[12 * 32 + 16], Rgb888::new(0, 0, 0)); // the centre sees the sphere
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug)]
pub struct Frame<'a, const S: usize, const L: usize> {
    scene: &'a Scene<S, L>,
    camera: &'a Camera,
    samples: u32,
    encoding: Encoding,
    eye: heapless::Vec<Prepared, S>,
    boxes: heapless::Vec<PixelBox, S>,
    /// Per light, in scene order: for a point light with shadows, `c` of [`Prepared::exact`]
    /// from the light for every sphere (the rest of those constants is rebuilt exactly when
    /// needed); empty for the others.
    lights: [heapless::Vec<f32, S>; L],
    /// Per light, in scene order, when shadows are on and `SWEEPS`: its spheres sorted for
    /// the span culling.
    sweeps: heapless::Vec<Sweep<S>, L>,
    /// Shadows on and at least one light: the only case that casts shadow rays.
    shadow_rays: bool,
    /// Every sphere's index: the candidate list of a shadow ray that must test them all, so
    /// that every shadow ray walks a plain slice.
    all: List<S>,
    /// Per sphere, [`Frame::offset_near`]'s answer, decided once.
    near: heapless::Vec<bool, S>,
}

/// Sphere indices: a row's, a span's or a light's candidates.
type List<const S: usize> = heapless::Vec<u16, S>;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Sphere indices are stored as `u16`, two values kept as markers.
    const FITS: () = assert!(S < REST as usize, "sphere capacity above 65533");

    /// Whether shadow rays find their candidates through sorted sweeps, or test every sphere
    /// against a span's bound: decided by the capacity, at compile time, so that a scene of a
    /// few spheres (a microcontroller's) links none of the sweep code (sorting, `atan2f`),
    /// where a scan of all its spheres per span costs about as much.
    const SWEEPS: bool = S > 8;

    /// Prepares a frame; fails only for invalid options (`samples` outside 1..=16).
    ///
    /// ```
    /// # use microray::{Camera, Error, Frame, RenderOptions, Scene, Vec3};
    /// let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let bad = RenderOptions { samples: 0, ..RenderOptions::default() };
    /// assert_eq!(Frame::new(&scene, &cam, bad).err(), Some(Error::InvalidSamples));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn new(
        scene: &'a Scene<S, L>,
        camera: &'a Camera,
        options: RenderOptions,
    ) -> Result<Self, Error> {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS;
        if !(1..=16).contains(&options.samples) {
            return Err(Error::InvalidSamples);
        }
        let mut frame = Frame {
            scene,
            camera,
            samples: options.samples as u32,
            encoding: options.encoding,
            eye: heapless::Vec::new(),
            boxes: heapless::Vec::new(),
            lights: [const { heapless::Vec::new() }; L],
            sweeps: heapless::Vec::new(),
            shadow_rays: scene.shadows() && !scene.lights().is_empty(),
            all: heapless::Vec::new(),
            near: heapless::Vec::new(),
        };
        frame.prepare();
        Ok(frame)
    }

    /// Fills the per-frame tables where they lie. Built apart and moved in, the per-light
    /// tables were copied whole, capacity included (0.7 MB at `Frame<1024, 32>`): 3.2 MB of
    /// copies and 0.5 MB of zeroing, most of `Frame::new`'s time and serial before a
    /// multi-threaded render. One copy is left, the frame's return by value.
    fn prepare(&mut self) {
        let (scene, camera) = (self.scene, self.camera);
        // Capacity S, at most S spheres (below `REST`, `FITS`), and at most L lights (the
        // scene's capacity): none of the pushes can fail.
        let screen = Screen::new(camera);
        for (s, sphere) in scene.spheres().iter().enumerate() {
            let k = Prepared::exact(camera.eye(), sphere);
            let _ = self.boxes.push(screen.sphere_box(&k));
            let _ = self
                .near
                .push(crate::geometry::offset_is_near(k.f, k.r, scene.near2(s)));
            let _ = self.all.push(s as u16);
            let _ = self.eye.push(k);
        }
        let axes = camera.basis();
        for (light, consts) in scene.lights().iter().zip(&mut self.lights) {
            if let (Light::Point { position, .. }, true) = (light, scene.shadows()) {
                for s in scene.spheres() {
                    let _ = consts.push(Prepared::exact(*position, s).c);
                }
            }
            if scene.shadows() && Self::SWEEPS {
                let _ = self.sweeps.push(Sweep::empty());
                if let Some(sweep) = self.sweeps.last_mut() {
                    sweep.fill(light, scene.spheres(), axes.0, axes.1);
                }
            }
        }
    }

    /// Image width in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// # let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!((frame.width(), frame.height()), (4, 3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn width(&self) -> u32 {
        self.camera.width()
    }

    /// Image height in pixels.
    ///
    /// ```
    /// # use microray::{Camera, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// # let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.height(), 3);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn height(&self) -> u32 {
        self.camera.height()
    }

    /// The screen box of every sphere, in scene order: a primary ray through pixel `(i, j)`
    /// can hit sphere `s` only if `boxes()[s]` contains `(i, j)`.
    ///
    /// ```
    /// # use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<2, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 0.5), Material::default())?;
    /// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, 9.0), 1.0), Material::default())?; // behind
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 64, 64)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// let b = frame.boxes()[0];
    /// assert!(b.contains(32, 32) && !b.contains(0, 0));
    /// assert!(frame.boxes()[1].is_empty());
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn boxes(&self) -> &[PixelBox] {
        &self.boxes
    }

    /// The closest hit of a primary ray (one that starts at the eye), against every sphere.
    #[inline]
    fn primary_hit(&self, ray: &Ray) -> Option<Hit> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for (i, k) in self.eye.iter().enumerate() {
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                tmax = t;
                best = Some((t, i));
            }
        }
        let (t, i) = best?;
        self.eye_hit(ray, t, i)
    }

    /// The closest hit of the primary ray through column `i`, as `(t, sphere)`, against the
    /// spheres of `cands` (in scene order) whose box holds that column (the row is the
    /// caller's). Inlined in [`Frame::gather`]'s pixel loop where spans cannot keep every view
    /// direction (soft-float Arm; elsewhere [`Frame::trace_span`] finds the same hits sphere by
    /// sphere); the other callers share [`Frame::primary_hit_among`].
    #[inline]
    fn primary_among(&self, ray: &Ray, i: u32, cands: &[u16]) -> Option<(f32, usize)> {
        let mut best: Option<(f32, usize)> = None;
        let mut tmax = f32::INFINITY;
        for &s in cands {
            let s = s as usize;
            let (Some(b), Some(k)) = (self.boxes.get(s), self.eye.get(s)) else {
                continue;
            };
            if i < b.i0 as u32 || i > b.i1 as u32 {
                continue;
            }
            if let Some(t) = k.hit(ray.dir, T_EPS, tmax) {
                tmax = t;
                best = Some((t, s));
            }
        }
        best
    }

    /// [`Frame::primary_among`] as a hit record. Out of line: one copy for the callers off
    /// the hot path (several samples per pixel, no shadow rays, single pixels).
    #[inline(never)]
    fn primary_hit_among(&self, ray: &Ray, i: u32, cands: &[u16]) -> Option<Hit> {
        let (t, s) = self.primary_among(ray, i, cands)?;
        self.eye_hit(ray, t, s)
    }

    /// What a primary hit record on sphere `s` takes besides its ray and `t`: the eye's
    /// constants for `s`, the sphere, and whether its offset is `f + t·d` ([`Frame::offset_near`]).
    #[inline(always)]
    fn eye_record(&self, s: usize) -> Option<(&Prepared, &crate::Sphere, bool)> {
        Some((
            self.eye.get(s)?,
            self.scene.spheres().get(s)?,
            self.offset_near(s),
        ))
    }

    /// The hit record of a primary ray at `t` on sphere `s`: a pure function of them.
    #[inline]
    fn eye_hit(&self, ray: &Ray, t: f32, s: usize) -> Option<Hit> {
        let (k, sphere, near) = self.eye_record(s)?;
        Some(make_hit(
            ray,
            t,
            s,
            k.f,
            sphere,
            near,
            ray.origin,
            Vec3::ZERO,
        ))
    }

    /// The hit record of the span's kept primary hit in `slot` along `ray` where spans keep
    /// offsets (`OFFS`, hosts): [`Frame::eye_hit`], with the hit's offset from the centre taken
    /// from the span's bounds where they were built (shadow rays: `culled`), which computed
    /// `hit_point_within` of the same arguments, so the same hit record. One copy of the rest
    /// of `make_hit` for both cases. Its callers test `OFFS` first, so that Cortex-M, where it
    /// is 0, compiles the plain `eye_hit` alone.
    #[inline]
    fn kept_hit(&self, ray: &Ray, t: f32, s: usize, slot: usize, cull: &Cull<S, L>) -> Option<Hit> {
        let (k, sphere, near) = self.eye_record(s)?;
        // Within near2 (`near`) the offset is `f + t·d`, cheaper to redo than to keep
        // (`hit_points_lanes` does not store it there).
        let offset = match cull.hit_o.get(slot) {
            Some(&offset) if cull.culled && !near => offset,
            _ => hit_point_near(ray, t, k.f, sphere, near).1,
        };
        Some(hit_from_offset(
            ray.dir,
            t,
            s,
            sphere,
            offset,
            ray.origin,
            Vec3::ZERO,
        ))
    }

    /// Shades the span's stored primary hits four neighbouring pixels at a time, one lane pass
    /// for each sphere that is not a mirror among the four ([`shade_lit4`](crate::shading)),
    /// into `cull.px`, marking them in `cull.done`: the pixels `next_pixel` would compute one
    /// by one, bit for bit (the hit records built lane by lane as `make_hit` builds them, the
    /// shadow tests the scalar ones, asked for the same lanes and lights). Misses are marked
    /// done too (`px` starts as the background); every other pixel is left to the scalar path.
    #[cfg(lanes)]
    #[inline(never)]
    fn shade_span4(&self, cull: &mut Cull<S, L>) {
        let len = cull.span_len();
        let (mut done, mut px) = (0u32, [cull.miss; SPAN]);
        let mut m = 0;
        while m + 4 <= len {
            // Pixels `k0..k0 + 4`, whose hits are in slots `q..q + 4`.
            let (k0, q) = (m, cull.slot(m));
            m += 4;
            let [dx, dy, dz] = &cull.hit_dc;
            let lanes = |a: &[f32; DPAD]| -> Option<[f32; 4]> { a.get(q..q + 4)?.try_into().ok() };
            let (Some(ss), Some(ts), Some(x), Some(y), Some(z)) = (
                cull.hit_s.get(q..q + 4),
                cull.hit_t.get(q..q + 4),
                lanes(dx),
                lanes(dy),
                lanes(dz),
            ) else {
                break;
            };
            // Misses show the background, which `px` already holds: done, whatever the rest.
            let none = (0..4).fold(0u32, |b, l| b | ((ss[l] == NONE) as u32) << l);
            done |= none << k0;
            let hits = !none & 0b1111;
            if hits == 0b1111 && ss.iter().all(|&x| x == ss[0]) {
                let colour = self.shade4::<true>(cull, q, ss[0] as usize, hits, ts, [x, y, z]);
                keep4(self, &mut px, &mut done, k0, hits, colour);
            } else if hits != 0 {
                self.shade4_mixed(cull, (k0, q), ss, hits, ts, [x, y, z], &mut px, &mut done);
            }
        }
        cull.px = px;
        cull.done = done;
    }

    /// [`Frame::shade_span4`]'s groups of four whose hits are not all on one sphere (an edge):
    /// one lane pass per sphere, each keeping the lanes that hit it. Left to the scalar path,
    /// such a group cost ~4× its lanes per pixel (a scene of 256 small spheres, 8% of its
    /// pixels on edges, rendered 13% faster). Out of line, so that the common group's code
    /// keeps its values in registers (inlined, the target scene took +10 instructions a pixel).
    #[cfg(lanes)]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    fn shade4_mixed(
        &self,
        cull: &Cull<S, L>,
        (k0, q): (usize, usize),
        ss: &[u16],
        hits: u32,
        ts: &[f32],
        xyz: [[f32; 4]; 3],
        px: &mut [Rgb888; SPAN],
        done: &mut u32,
    ) {
        let mut todo = hits;
        while let Some(&s) = ss.get(todo.trailing_zeros() as usize) {
            let active = (0..4).fold(0u32, |b, l| b | ((ss.get(l) == Some(&s)) as u32) << l) & todo;
            todo &= !active;
            let colour = self.shade4::<false>(cull, q, s as usize, active, ts, xyz);
            keep4(self, px, done, k0, active, colour);
        }
    }

    /// The colours of the lanes `active` of the span's four stored hits from slot `q`, all on
    /// sphere `si` (`ts` their t, `dir` their view directions by coordinate), shaded in lanes
    /// as `shade_span4` describes; the other lanes' values are meaningless. `None` where the
    /// scalar path must shade them (a mirror, a case `shade_lit4` leaves). `ALL`: all four lanes
    /// (the common group); a parameter so that the common group and `shade4_mixed` each get a
    /// copy of their own, whose shadow-test closure is inlined (shared, it went out of line:
    /// +5 x86 instructions a pixel).
    #[cfg(lanes)]
    #[inline(always)]
    fn shade4<const ALL: bool>(
        &self,
        cull: &Cull<S, L>,
        q: usize,
        si: usize,
        active: u32,
        ts: &[f32],
        [x, y, z]: [[f32; 4]; 3],
    ) -> Option<crate::math::lanes::V> {
        use crate::math::lanes::{bits, F, V};
        use crate::shading::{in_shadow4, shade_lit4, Hits4};
        use wide::{CmpGt, CmpLe, CmpLt};
        let scene = self.scene;
        let active = if ALL { 0b1111 } else { active };
        let (k, sphere) = (self.eye.get(si)?, scene.spheres().get(si)?);
        if scene.has_mirror(si) && scene.max_depth() > 0 {
            return None;
        }
        let dir = V {
            x: F::from(x),
            y: F::from(y),
            z: F::from(z),
        };
        let t = F::from(<[f32; 4]>::try_from(ts).ok()?);
        let r = sphere.radius;
        // `hit_point_within`'s offset: `f + t·d` within near2 radii, else the one the span's
        // bounds kept, or without them (no shadow rays) `hit_point_far`'s, in lanes here.
        let offset = if self.offset_near(si) {
            V::splat(k.f).add(dir.mul(t))
        } else {
            match cull.hit_o.get(q..q + 4) {
                Some(o) if cull.culled => V::from_lanes([o[0], o[1], o[2], o[3]]),
                _ => crate::geometry::hit_point_far4(dir, t, k.f, sphere)?.1,
            }
        };
        // `hit_from_offset` for rays from the eye (`path` zero).
        let outward = offset.div(F::splat(r));
        let path = V::splat(Vec3::ZERO).add(dir.mul(t));
        let centre = F::splat(r * r).cmp_le(path.dot(path));
        let anchor = V::select(centre, V::splat(sphere.center), V::splat(self.camera.eye()));
        let rel = V::select(centre, offset, path);
        let facing = dir.dot(outward).cmp_gt(F::ZERO);
        let normal = V::select(facing, outward.neg(), outward);
        let h = Hits4 {
            t,
            sphere: si,
            normal,
            offset,
            anchor,
            rel,
            dir,
        };
        let group = if cull.culled { cull.lists(si) } else { None };
        let inside = bits(normal.dot(offset).cmp_lt(F::ZERO));
        let blocked = |i: usize, light: &Light, ask: u32, to: &V| {
            if !scene.shadows() {
                return 0;
            }
            // No candidate: only lanes that see the sphere from inside need the test
            // (`Frame::blocked`'s shortcut, four lanes at a time).
            let cands = self.candidates(group, i);
            let ask = if cands.is_empty() { ask & inside } else { ask };
            if ask == 0 {
                return 0;
            }
            let cs = self.light_consts(i, light);
            let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
            in_shadow4(scene, &h, light, to, ask, consts, cands)
        };
        shade_lit4(scene, &h, active, blocked)
    }

    /// Whether `hit_point_within` takes `f + t·d` for primary hits on sphere `s` (its eye
    /// constants within near2 radii): the same choice for every pixel, which `Frame::new`
    /// makes once per sphere.
    #[inline(always)]
    fn offset_near(&self, s: usize) -> bool {
        self.near.get(s).copied().unwrap_or(false)
    }

    /// The per-light constants of light `i` (empty unless it is a point light with shadows).
    #[inline]
    fn light_consts(&self, i: usize, light: &Light) -> Option<&[f32]> {
        match light {
            Light::Point { .. } => self.lights.get(i).map(|v| &v[..]),
            Light::Directional { .. } => None,
        }
    }

    /// The pixel of [`Frame::shade_from`] of [`Frame::eye_hit`]`(ray, t, s)`, a span's stored
    /// primary hit, with the hit record and the primary hit's shading inlined into the pixel
    /// loop: the record stays in registers instead of going through memory to the out-of-line
    /// `make_hit` and shading closure (M4F: 455.7 → 420.6 instructions a pixel at opt 3). The
    /// same operations, so the same bits. A second copy of the shading (mirror bounces and the
    /// other paths keep theirs): +2.7 KiB at "s", where it saved 34 instructions a pixel, so
    /// not in size builds (`size_opt`, see build.rs), whose flash is budgeted.
    #[cfg(not(any(lanes, size_opt)))]
    #[inline(always)]
    fn shade_stored(&self, ray: &Ray, t: f32, s: usize, lists: Option<Lists<'_, L>>) -> Rgb888 {
        let scene = self.scene;
        let Some((k, sphere, near)) = self.eye_record(s) else {
            return self.encode(scene.background());
        };
        // The values, not `ray`'s memory, which only the bounces need: its origin is the eye.
        let (d, o, f) = (ray.dir, self.camera.eye(), k.f);
        // No path before the eye: −0, whose sum `−0 + t·d` is `t·d` exactly, which the
        // compiler then need not compute (`+0 + x` is `x` only up to the sign of a zero).
        let h = crate::scene::make_hit_inline(
            d.x, d.y, d.z, t, s, f.x, f.y, f.z, sphere, near, o.x, o.y, o.z, -0.0, -0.0, -0.0,
        );
        let colour = crate::shading::shade_lit_inline(scene, &h, d, |i, light, v| {
            self.blocked(&h, lists, i, light, v)
        });
        // Encoded on each path: a colour merged from the bounces' out-of-line return went
        // through memory (M4F: ~12 instructions a pixel).
        if !scene.has_mirrors() {
            return self.encode(colour);
        }
        // A copy, as for `shadow_test`: only the bounces put the record in memory.
        self.encode(crate::shading::follow_mirror(
            scene,
            ray,
            &{ h },
            colour,
            |hit, ray, _| {
                shade_lit(scene, hit, ray.dir, |i, light, v| {
                    self.blocked(hit, None, i, light, v)
                })
            },
        ))
    }

    /// Shades a primary hit (and its mirror bounces): `lists`, when given, holds per light
    /// the spheres that can block shadow rays from this primary hit; mirror hits and missing
    /// `lists` test every sphere.
    #[inline]
    fn shade_from(&self, ray: &Ray, first: Option<Hit>, lists: Option<Lists<'_, L>>) -> Color {
        let scene = self.scene;
        follow(scene, ray, first, |hit, ray, primary| {
            let lists = if primary { lists } else { None };
            shade_lit(scene, hit, ray.dir, |i, light, v| {
                self.blocked(hit, lists, i, light, v)
            })
        })
    }

    /// The spheres that can block light `i` for a hit with the span lists `lists` (a primary
    /// hit's), or every sphere.
    #[inline(always)]
    fn candidates<'c>(&'c self, lists: Option<Lists<'c, L>>, i: usize) -> &'c [u16] {
        // A slice in both cases: one copy of the shadow tests, and a tight loop.
        lists.and_then(|l| l.light(i)).unwrap_or(&self.all)
    }

    /// Whether light `i` is blocked at `hit` (`v` its `to_light` vector), testing the
    /// [`Frame::candidates`] of `lists`: the shadow test of both shading paths.
    #[inline(always)]
    fn blocked(
        &self,
        hit: &Hit,
        lists: Option<Lists<'_, L>>,
        i: usize,
        light: &Light,
        v: Vec3,
    ) -> bool {
        // Span lists exist only with shadow rays (`Cull::culled`): with some, the scene's flag
        // is not read (M4F: 481.6 → 475.3 instructions a pixel).
        if lists.is_none() && !self.scene.shadows() {
            return false;
        }
        // No candidate: only the hit's own sphere could block, and only when it is seen from
        // inside (see `in_shadow_among`). Most span lists are empty: decided from the list's
        // range, before a slice is built.
        if lists.is_some_and(|l| l.is_empty(i)) && !(hit.normal.dot(hit.offset) < 0.0) {
            return false;
        }
        // The slice's own test, which the range's has decided wherever a list exists; left in,
        // as without it the M4F took +6 instructions a pixel (register allocation).
        let cands = self.candidates(lists, i);
        if cands.is_empty() && !(hit.normal.dot(hit.offset) < 0.0) {
            return false;
        }
        // A copy for the out-of-line test: the caller's record, which `shade_stored` keeps
        // in registers, does not escape to memory on the paths that do not get here.
        self.shadow_test(&{ *hit }, cands, i, light, (v.x, v.y, v.z))
    }

    /// [`in_shadow_among`] of light `i` at `hit` over `cands`, with the light's per-frame
    /// constants.
    ///
    /// Out of line on Cortex-M: `blocked` returns before it for most pixels (no candidate), and
    /// inlined into the shading loop its registers made that loop keep more of its values on
    /// the stack (M4F: 587.6 → 581.5 instructions a pixel; "s": 696.6 → 686.3). `v` as three
    /// floats, which go in registers: a `Vec3` went by address, and the shading loop stored it
    /// for every lit light before asking whether the test is needed (M4F: 413.2 → 406.4; "s":
    /// 517.0 → 509.4, 60 bytes smaller).
    #[cfg_attr(lanes, inline(always))]
    #[cfg_attr(not(lanes), inline(never))]
    fn shadow_test(
        &self,
        hit: &Hit,
        cands: &[u16],
        i: usize,
        light: &Light,
        (vx, vy, vz): (f32, f32, f32),
    ) -> bool {
        let v = Vec3::new(vx, vy, vz);
        let cs = self.light_consts(i, light);
        let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
        let cands = cands.iter().map(|&j| j as usize);
        in_shadow_among(self.scene, hit, light, v, consts, cands)
    }

    /// The linear colour seen along a primary ray from the eye, tested against every sphere:
    /// the brute-force reference of the renderer (it takes any ray, so no screen box applies).
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(0.3))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.trace(&cam.ray(2.0, 2.0)), Color::splat(0.3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn trace(&self, ray: &Ray) -> Color {
        self.shade_from(ray, self.primary_hit(ray), None)
    }

    /// The linear colour of pixel `(i, j)`: the average of its `samples²` rays, unclamped.
    /// Primary rays test only the spheres whose screen box holds the pixel; shadow rays test
    /// every sphere (use [`Frame::render_rows`] for whole rows, which culls those too).
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::splat(2.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions { samples: 2, ..Default::default() })?;
    /// assert_eq!(frame.pixel_color(0, 0), Color::splat(2.0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel_color(&self, i: u32, j: u32) -> Color {
        let mut cands: List<S> = heapless::Vec::new();
        for (s, b) in self.boxes.iter().enumerate() {
            if b.contains(i, j) {
                let _ = cands.push(s as u16);
            }
        }
        self.average(i, j, |ray| {
            self.shade_from(ray, self.primary_hit_among(ray, i, &cands), None)
        })
    }

    /// [`Frame::pixel_color`] the brute-force way: every ray against every sphere. The
    /// reference that the accelerated paths must equal bit for bit.
    ///
    /// ```
    /// # use microray::{Camera, Color, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.pixel_color_brute(4, 4), frame.pixel_color(4, 4));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel_color_brute(&self, i: u32, j: u32) -> Color {
        self.average(i, j, |ray| self.trace(ray))
    }

    /// The average over the pixel's `samples²` rays of `f(ray)` (with one sample, `f(ray)`
    /// itself). `f` is called from one place, so it is inlined once.
    #[inline]
    fn average(&self, i: u32, j: u32, mut f: impl FnMut(&Ray) -> Color) -> Color {
        let n = self.samples;
        let mut sum = Color::ZERO;
        for sy in 0..n {
            for sx in 0..n {
                let c = f(&self.camera.primary_ray(i, j, sx, sy, n));
                if n == 1 {
                    return c;
                }
                sum += c;
            }
        }
        sum / (n * n) as f32
    }

    /// A linear colour encoded as a pixel.
    #[inline]
    fn encode(&self, c: Color) -> Rgb888 {
        let e = self.encoding;
        Rgb888::new(
            encode_channel(c.x, e),
            encode_channel(c.y, e),
            encode_channel(c.z, e),
        )
    }

    /// [`Frame::encode`] of four colours in vector lanes (`cfg(lanes)`): `encode_channel`'s
    /// `255c + 0.5` and its saturating cast lane by lane (the cast's cases as selections: NaN
    /// and below 0 to 0, 256 and above to 255), the same bytes. sRGB goes channel by channel
    /// through the scalar curve.
    #[cfg(lanes)]
    #[inline(always)]
    fn encode4(&self, c: &crate::math::lanes::V) -> [Rgb888; 4] {
        if self.encoding != Encoding::Linear {
            return core::array::from_fn(|l| self.encode(c.lane(l)));
        }
        // The three bytes of each pixel in one integer lane: one extraction a pixel, not three.
        let (r, g, b) = (linear_bytes(c.x), linear_bytes(c.y), linear_bytes(c.z));
        let rgb: wide::i32x4 = r | (g << 8_i32) | (b << 16_i32);
        let rgb = rgb.to_array();
        rgb.map(|w| Rgb888::new(w as u8, (w >> 8) as u8, (w >> 16) as u8))
    }

    /// The encoded colour of pixel `(i, j)` (row 0 at the top).
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(1.0, 0.5, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert_eq!(frame.pixel(3, 3), Rgb888::new(255, 128, 0));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn pixel(&self, i: u32, j: u32) -> Rgb888 {
        self.encode(self.pixel_color(i, j))
    }

    /// The pixels of row `j`, left to right, traced span by span with every culling of
    /// [`Frame::render_rows`]; for displays that consume a row as an iterator. Rows past the
    /// image yield nothing.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Color, Frame, RenderOptions, Scene, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(1.0, 0.5, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 4)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// assert!(frame.row(1).all(|p| p == Rgb888::new(255, 128, 0)));
    /// assert_eq!(frame.row(1).count(), 4);
    /// assert_eq!(frame.row(4).count(), 0);
    /// # Ok::<(), microray::Error>(())
    /// ```
    // Out of line: whatever temporary the compiler builds the `Row` in stays in this frame,
    // which is gone before the row is traced (a caller's frame would keep it).
    #[inline(never)]
    pub fn row(&self, j: u32) -> Row<'_, 'a, S, L> {
        // The row's lists are made by its first pixel: the `Row` is built in place, never
        // moved with them filled in (it is large, microcontroller stacks are small).
        Row {
            frame: self,
            j,
            i: 0,
            end: if j < self.height() { self.width() } else { 0 },
            cull: Cull::new(),
        }
    }

    /// Starts row `j`: its spheres are those whose box crosses it, in scene order.
    fn start_row(&self, j: u32, cull: &mut Cull<S, L>) {
        cull.row.clear();
        for (s, b) in self.boxes.iter().enumerate() {
            if b.has_row(j) {
                let _ = cull.row.push(s as u16);
            }
        }
        self.start_miss(cull);
    }

    /// [`Frame::start_row`] for the `n` rows from `j` that a span gathers at once (a tile,
    /// `Cull::rows`): their spheres are those whose box crosses any of them.
    #[cfg(lanes)]
    fn start_rows(&self, j: u32, n: u32, cull: &mut Cull<S, L>) {
        cull.row.clear();
        for (s, b) in self.boxes.iter().enumerate() {
            if (j..j + n).any(|r| b.has_row(r)) {
                let _ = cull.row.push(s as u16);
            }
        }
        cull.rows = n;
        self.start_miss(cull);
    }

    /// The rest of starting rows: no span yet, and the pixel of every ray that misses.
    #[inline(always)]
    fn start_miss(&self, cull: &mut Cull<S, L>) {
        cull.span_end = 0;
        // A miss shows the background, whatever its ray: one pixel for all of them. Shaded
        // here, on the render path's stack, rather than in `Frame::new` (set-up's).
        let nowhere = Ray::new(self.camera.eye(), Vec3::ZERO);
        cull.miss = self.encode(self.shade_from(&nowhere, None, None));
    }

    /// The pixel `(i, j)` of row `j`, pixels taken in order from `i = 0` (which starts the
    /// row with [`Frame::start_row`]).
    #[inline]
    fn next_pixel(&self, j: u32, i: u32, cull: &mut Cull<S, L>) -> Rgb888 {
        if i == 0 {
            self.start_row(j, cull);
        }
        if i >= cull.span_end {
            self.start_span(j, i, cull);
        }
        #[cfg(lanes)]
        {
            // Hosts shade the whole span at its start (`fill_span`).
            let k = (i - cull.span_start) as usize;
            cull.px.get(k).copied().unwrap_or(cull.miss)
        }
        #[cfg(not(lanes))]
        self.span_pixel(j, i, cull)
    }

    /// Starts the span of row `j` at column `i`: its candidates, hits and bounds
    /// ([`Frame::gather`]), and on hosts all its pixels ([`Frame::fill_span`]).
    #[inline(always)]
    fn start_span(&self, j: u32, i: u32, cull: &mut Cull<S, L>) {
        cull.span_start = i;
        cull.span_end = (i + SPAN as u32).min(self.width());
        self.gather(j, cull);
        #[cfg(lanes)]
        self.fill_span(j, cull);
    }

    /// Every pixel of the span just gathered into `cull.px`: groups of four in lanes
    /// (`shade_span4`), the others one by one, so that the pixel loop only reads them.
    #[cfg(lanes)]
    #[inline(never)]
    fn fill_span(&self, j: u32, cull: &mut Cull<S, L>) {
        cull.done = 0;
        if cull.stored {
            self.shade_span4(cull);
        }
        let len = cull.span_len();
        let span = if len >= 32 { u32::MAX } else { (1 << len) - 1 };
        for k in crate::math::lanes::ones(!cull.done & span) {
            let c = self.span_pixel(j, cull.span_start + k as u32, cull);
            if let Some(p) = cull.px.get_mut(k) {
                *p = c;
            }
        }
    }

    /// Pixel `(i, j)` of the span gathered in `cull`, shaded on its own.
    #[inline(always)]
    fn span_pixel(&self, j: u32, i: u32, cull: &Cull<S, L>) -> Rgb888 {
        let c = if cull.stored {
            let k = cull.slot((i - cull.span_start) as usize);
            // A miss: the pixel `start_row` shaded for all of them (gather built no ray).
            let Some((t, s)) = cull.hit(k) else {
                return cull.miss;
            };
            let dir = match cull.dir(k) {
                Some(dir) => dir,
                None => self.camera.primary_ray(i, j, 0, 0, 1).dir,
            };
            let ray = Ray::new(self.camera.eye(), dir);
            // The scalar path's speed builds build the hit record where they shade it; hosts
            // and size builds go on below.
            #[cfg(not(any(lanes, size_opt)))]
            return self.shade_stored(&ray, t, s as usize, cull.lists_at(k));
            // The hit record from (t, sphere): `make_hit` is a pure function of them. Its ray
            // built anew from the values, not read back from `ray`, which shading takes by
            // address: M4F loaded the direction and eye through core registers to copy them.
            #[allow(unreachable_code)]
            let first = if KEEPS_OFFSETS && SPHERE_MAJOR {
                self.kept_hit(&ray, t, s as usize, k, cull)
            } else {
                self.eye_hit(&Ray::new(self.camera.eye(), dir), t, s as usize)
            };
            self.shade_from(&ray, first, cull.lists_at(k))
        } else if KEPT > 1 && cull.kept {
            let k = (i - cull.span_start) as usize;
            // `average`'s sum, in its order, of the samples' kept hits (slot `m·SPAN + k`).
            let n = self.samples;
            let mut sum = Color::ZERO;
            for m in 0..n * n {
                let slot = m as usize * SPAN + k;
                sum += match cull.hit(slot) {
                    Some(h) => self.shade_kept(i, j, slot, h, cull),
                    // What `shade_from` gives a ray that hits nothing.
                    None => self.scene.background(),
                };
            }
            sum / (n * n) as f32
        } else {
            self.average(i, j, |ray| {
                let hit = self.primary_hit_among(ray, i, &cull.span);
                let lists = hit.as_ref().and_then(|h| cull.lists(h.sphere));
                self.shade_from(ray, hit, lists)
            })
        };
        self.encode(c)
    }

    /// The colour of the kept primary hit `(t, sphere)` in `slot` of a supersampled span (see
    /// `KEPT`): the hit record rebuilt from them (`make_hit` is a pure function of them) along
    /// the kept view ray, or the rebuilt one where directions are not kept (the same bits).
    #[inline]
    fn shade_kept(
        &self,
        i: u32,
        j: u32,
        slot: usize,
        (t, s): (f32, u16),
        cull: &Cull<S, L>,
    ) -> Color {
        let ray = match cull.dir(slot) {
            Some(dir) => Ray::new(self.camera.eye(), dir),
            None => {
                let (n, m) = (self.samples, (slot / SPAN) as u32);
                self.camera.primary_ray(i, j, m % n, m / n, n)
            }
        };
        let first = if KEEPS_OFFSETS && SPHERE_MAJOR {
            self.kept_hit(&ray, t, s as usize, slot, cull)
        } else {
            self.eye_hit(&ray, t, s as usize)
        };
        self.shade_from(&ray, first, cull.lists_at(slot))
    }

    /// Renders rows `first_row ..` into `buf`, which holds a whole number of rows; returns how
    /// many rows it rendered. This is how a microcontroller without room for a framebuffer
    /// streams an image, and how the desktop renderer splits a frame between threads.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::{Rgb565, Rgb888};
    /// # use microray::{Camera, Color, Error, Frame, RenderOptions, Scene, Vec3};
    /// # let mut scene: Scene<1, 0> = Scene::new();
    /// # scene.set_background(Color::new(1.0, 0.0, 0.0))?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 6)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// let mut band = [Rgb565::new(0, 0, 0); 2 * 8]; // two rows, straight into a display format
    /// for first in (0..6).step_by(2) {
    ///     assert_eq!(frame.render_rows(first, &mut band)?, 2);
    ///     // ... send `band` to the display ...
    /// }
    /// assert_eq!(band[0], Rgb565::new(31, 0, 0));
    /// assert_eq!(frame.render_rows(5, &mut band), Err(Error::BufferSize)); // only 1 row left
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows<C: From<Rgb888>>(
        &self,
        first_row: u32,
        buf: &mut [C],
    ) -> Result<u32, Error> {
        let rows = self.check_rows(first_row, buf.len())?;
        let w = self.width() as usize;
        // Hosts: tile by tile (`tile_rows`).
        #[cfg(lanes)]
        let _ = self.tile_rows(first_row, rows, |t: TileRow<'_>| {
            for (o, &p) in t.place(buf, first_row, w).iter_mut().zip(t.px) {
                *o = p.into();
            }
            Ok::<(), core::convert::Infallible>(())
        });
        // Cortex-M: row by row, as `Row` does.
        #[cfg(not(lanes))]
        {
            let mut cull = Cull::new();
            for (r, row) in buf.chunks_exact_mut(w).enumerate() {
                let j = first_row + r as u32;
                for (i, px) in row.iter_mut().enumerate() {
                    *px = self.next_pixel(j, i as u32, &mut cull).into();
                }
            }
        }
        Ok(rows)
    }

    /// Rows `first ..first + n` as hosts trace them: span by span, each span shaded whole by
    /// `fill_span`, and with one sample a pixel and shadow rays `KEPT` (8) rows at a time (a
    /// tile), whose hits the sample slots hold: one set of shadow lists for the tile's groups
    /// instead of one per row. A tile's bounds are barely larger than a row's (a span is 32
    /// pixels wide), and the lists were a quarter of a shadowed frame's time. `out` gets each
    /// row of each span of each tile in turn; its first error ends it.
    #[cfg(lanes)]
    pub(crate) fn tile_rows<E>(
        &self,
        first: u32,
        n: u32,
        mut out: impl FnMut(TileRow<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let tile = if self.samples == 1 && self.shadow_rays {
            KEPT as u32
        } else {
            1
        };
        let end = (first + n).min(self.height());
        let mut cull = Cull::new();
        let mut j = first;
        while j < end {
            let rows = tile.min(end - j);
            self.start_rows(j, rows, &mut cull);
            for m in 0..self.width().div_ceil(SPAN as u32) {
                let i = m * SPAN as u32;
                cull.span_start = i;
                cull.span_end = (i + SPAN as u32).min(self.width());
                self.gather(j, &mut cull);
                for r in 0..rows {
                    cull.base = r as usize * SPAN;
                    self.fill_span(j + r, &mut cull);
                    let px = cull.px.get(..cull.span_len()).unwrap_or(&[]);
                    out(TileRow { i, j: j + r, px })?;
                }
            }
            j += rows;
        }
        Ok(())
    }

    /// [`Frame::render_rows`] the brute-force way, every ray against every sphere: the
    /// reference for tests and benchmarks.
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Frame, Material, RenderOptions, Scene, Sphere, Vec3};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// let (mut a, mut b) = ([Rgb888::new(0, 0, 0); 64], [Rgb888::new(0, 0, 0); 64]);
    /// frame.render_rows(0, &mut a)?;
    /// frame.render_rows_brute(0, &mut b)?;
    /// assert_eq!(a, b);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render_rows_brute<C: From<Rgb888>>(
        &self,
        first_row: u32,
        buf: &mut [C],
    ) -> Result<u32, Error> {
        let rows = self.check_rows(first_row, buf.len())?;
        let w = self.width() as usize;
        for (r, row) in buf.chunks_exact_mut(w).enumerate() {
            let j = first_row + r as u32;
            for (i, px) in row.iter_mut().enumerate() {
                *px = self.encode(self.pixel_color_brute(i as u32, j)).into();
            }
        }
        Ok(rows)
    }

    /// How many rows a buffer of `len` pixels holds, if whole rows inside the image.
    fn check_rows(&self, first_row: u32, len: usize) -> Result<u32, Error> {
        let w = self.width() as usize; // ≥ 1 (Camera checks); checked_div links no panic
        let (Some(rows), Some(0)) = (len.checked_div(w), len.checked_rem(w)) else {
            return Err(Error::BufferSize);
        };
        if first_row as usize + rows > self.height() as usize {
            return Err(Error::BufferSize);
        }
        Ok(rows as u32)
    }

    /// Renders the whole image into `buf` (`width × height` pixels, row by row from the top).
    ///
    /// ```
    /// # use embedded_graphics::pixelcolor::Rgb888;
    /// # use microray::{Camera, Error, Frame, RenderOptions, Scene, Vec3};
    /// # let scene: Scene<1, 0> = Scene::new();
    /// let cam = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 4, 3)?;
    /// let frame = Frame::new(&scene, &cam, RenderOptions::default())?;
    /// let mut too_small = [Rgb888::new(0, 0, 0); 4 * 2];
    /// assert_eq!(frame.render(&mut too_small), Err(Error::BufferSize));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn render<C: From<Rgb888>>(&self, buf: &mut [C]) -> Result<(), Error> {
        if buf.len() != self.width() as usize * self.height() as usize {
            return Err(Error::BufferSize);
        }
        self.render_rows(0, buf).map(|_| ())
    }

    /// The closest primary hits of the span's pixels `i0..i1` for one sample (`ox`, row
    /// coordinate `y`) into the slots `base..`: view directions in `hit_d`, `(t, sphere)` in
    /// `hit_t`/`hit_s` (`NONE`: a miss). Sphere by sphere in scene order, each over the columns of
    /// its box: every pixel sees its candidates in the order and with the `tmax` of
    /// [`Frame::primary_among`], so the hits are its hits, bit for bit, while a sphere's
    /// constants and box stay in registers across its columns.
    #[inline]
    fn trace_span(
        &self,
        i0: u32,
        i1: u32,
        ox: f32,
        (row, y): (u32, f32),
        base: usize,
        cull: &mut Cull<S, L>,
    ) {
        // Hosts with f32 vector registers: `LANES` columns at a time, and with shadow rays the
        // hit points for the span's bounds too.
        #[cfg(lanes)]
        {
            const PAD: usize = SPAN + crate::geometry::LANES - 1;
            let len = (i1 - i0) as usize;
            let [dx, dy, dz] = &mut cull.hit_dc;
            fn lanes<const N: usize>(a: &mut [f32; DPAD], base: usize) -> Option<&mut [f32; N]> {
                a.get_mut(base..base + N)?.try_into().ok()
            }
            let (Some(ts), Some(ss), Some(ps), Some(os)) = (
                cull.hit_t.get_mut(base..base + len),
                cull.hit_s.get_mut(base..base + len),
                cull.hit_p.get_mut(base..base + len),
                cull.hit_o.get_mut(base..base + len),
            ) else {
                return;
            };
            let (Some(dx), Some(dy), Some(dz)) = (
                lanes::<PAD>(dx, base),
                lanes::<PAD>(dy, base),
                lanes::<PAD>(dz, base),
            ) else {
                return;
            };
            let points = self.shadow_rays.then_some((ps, os));
            self.trace_lanes(
                [dx, dy, dz],
                ts,
                ss,
                points,
                &cull.span,
                (i0, i1, ox, y, row),
            );
        }
        #[cfg(not(lanes))]
        {
            // One row at a time on Cortex-M: the row's spheres are the span's.
            let _ = row;
            self.trace_scalar(i0, i1, ox, y, base, cull);
        }
    }

    /// `trace_span` one column at a time.
    #[cfg(not(lanes))]
    #[inline(always)]
    fn trace_scalar(&self, i0: u32, i1: u32, ox: f32, y: f32, base: usize, cull: &mut Cull<S, L>) {
        let len = (i1 - i0) as usize;
        let (Some(dirs), Some(ts), Some(ss)) = (
            cull.hit_d.get_mut(base..base + len),
            cull.hit_t.get_mut(base..base + len),
            cull.hit_s.get_mut(base..base + len),
        ) else {
            return;
        };
        let row = self.camera.row(y);
        // The column `i as f32`, counted in f32: exact below 2²⁴ (image sizes are u16).
        let mut column = i0 as f32;
        for ((d, t), s) in dirs.iter_mut().zip(ts.iter_mut()).zip(ss.iter_mut()) {
            // `primary_ray(i, j, sx, sy, n)`, the same bits.
            *d = row.ray(column + ox).dir;
            // No limit yet, finite for `hit_outside` (any root is finite).
            *t = f32::MAX;
            *s = NONE;
            column += 1.0;
        }
        for &sphere in &cull.span {
            let (Some(b), Some(k)) = (
                self.boxes.get(sphere as usize),
                self.eye.get(sphere as usize),
            ) else {
                continue;
            };
            // The box's columns within the span (the span list holds only boxes that meet it).
            let lo = (b.i0 as u32).max(i0) - i0;
            let hi = (b.i1 as u32 + 1).min(i1).saturating_sub(i0);
            let (Some(dirs), Some(ts), Some(ss)) = (
                dirs.get(lo as usize..hi as usize),
                ts.get_mut(lo as usize..hi as usize),
                ss.get_mut(lo as usize..hi as usize),
            ) else {
                continue;
            };
            // The eye outside the sphere, as for most: decided once per box, not per ray.
            let outside = k.outside();
            for ((d, t), s) in dirs.iter().zip(ts.iter_mut()).zip(ss.iter_mut()) {
                let hit = if outside {
                    k.hit_outside(*d, T_EPS, *t)
                } else {
                    k.hit(*d, T_EPS, *t)
                };
                if let Some(hit) = hit {
                    *t = hit;
                    *s = sphere;
                }
            }
        }
    }

    /// `trace_span` `LANES` columns at a time: the view directions
    /// ([`Camera::directions4`]) and the sphere loop ([`Prepared::hit_lanes`]), the same
    /// operations and tests in the same order, so the same directions and hits. The directions
    /// go to the span's arrays by coordinate (`Cull::hit_dc`), padded to whole lanes: their
    /// lanes past the span hold whatever they held, which only lanes that are not the span's
    /// read.
    #[cfg(lanes)]
    #[inline(always)]
    fn trace_lanes<const PAD: usize>(
        &self,
        [dx, dy, dz]: [&mut [f32; PAD]; 3],
        ts: &mut [f32],
        ss: &mut [u16],
        points: Option<(&mut [Vec3], &mut [Vec3])>,
        span: &[u16],
        (i0, i1, ox, y, row): (u32, u32, f32, f32, u32),
    ) {
        use crate::geometry::LANES;
        use crate::math::{finite, lanes::F};
        let (mut t, mut sp) = ([f32::INFINITY; PAD], [NONE; PAD]);
        let len = ts.len().min(SPAN);
        let lane = F::from(core::array::from_fn(|l| l as f32));
        for m in (0..len).step_by(LANES) {
            // `primary_ray(i, j, sx, sy, n)`: pixel column i at `i + ox`. Columns (below
            // `MAX_SIZE` + `LANES`) are exact in f32, so the lanes' `(i0 + m) + l` is each
            // column converted, in one conversion instead of four.
            let x = F::splat((i0 + m as u32) as f32) + lane;
            let x = (x + F::splat(ox)).to_array();
            let [x, y, z] = self.camera.directions4(x, y);
            let lanes = m..m + LANES;
            if let (Some(a), Some(b), Some(c)) = (
                dx.get_mut(lanes.clone()),
                dy.get_mut(lanes.clone()),
                dz.get_mut(lanes),
            ) {
                a.copy_from_slice(&x);
                b.copy_from_slice(&y);
                c.copy_from_slice(&z);
            }
        }
        for &sphere in span {
            let (Some(b), Some(k)) = (
                self.boxes.get(sphere as usize),
                self.eye.get(sphere as usize),
            ) else {
                continue;
            };
            // A tile's span lists the spheres of all its rows; the box holds every hit.
            if !b.has_row(row) {
                continue;
            }
            let lo = ((b.i0 as u32).max(i0) - i0) as usize;
            let hi = ((b.i1 as u32 + 1).min(i1).saturating_sub(i0) as usize).min(SPAN);
            if !finite(k.c) {
                // Overflowing constants: the scalar path, whose scaled roots handle them.
                for m in lo..hi {
                    let d = Vec3::new(dx[m], dy[m], dz[m]);
                    if let Some(hit) = k.hit(d, T_EPS, t[m]) {
                        (t[m], sp[m]) = (hit, sphere);
                    }
                }
                continue;
            }
            let hb = k.hearn_baker();
            let mut m = lo;
            while m < hi {
                let lanes = |a: &[f32; PAD]| -> [f32; LANES] {
                    core::array::from_fn(|l| a.get(m + l).copied().unwrap_or(0.0))
                };
                let (x, y, z, tm) = (lanes(dx), lanes(dy), lanes(dz), lanes(&t));
                let h = k.hit_lanes(hb, x, y, z, T_EPS, tm);
                // Lanes past the box's last column are not its to change.
                let valid = if hi - m >= LANES {
                    (1 << LANES) - 1
                } else {
                    (1u32 << (hi - m)) - 1
                };
                let (hit, redo) = (h.hit & valid, h.redo & valid);
                for l in 0..LANES {
                    if hit & (1 << l) != 0 {
                        if let (Some(tt), Some(ss)) = (t.get_mut(m + l), sp.get_mut(m + l)) {
                            (*tt, *ss) = (h.t[l], sphere);
                        }
                    }
                }
                if redo != 0 {
                    for l in 0..LANES {
                        if redo & (1 << l) != 0 {
                            let q = m + l;
                            let d = Vec3::new(dx[q], dy[q], dz[q]);
                            if let Some(hit) = k.hit(d, T_EPS, t[q]) {
                                (t[q], sp[q]) = (hit, sphere);
                            }
                        }
                    }
                }
                m += LANES;
            }
        }
        for (k, (tt, s)) in ts.iter_mut().zip(ss.iter_mut()).enumerate().take(SPAN) {
            (*tt, *s) = (t[k], sp[k]);
        }
        if let Some((ps, os)) = points {
            self.hit_points_lanes(ps, os, (dx, dy, dz), &t, &sp);
        }
    }

    /// `hit_point_within` of every hit of a span (its point and offset, as `make_hit` and the
    /// span's bounds compute them) into `ps` and `os`: four at a time where four neighbouring
    /// columns hit one sphere on `f + t·d`'s side of `near2` (the same operations lane by lane,
    /// so the same bits; the offset, `f + t·d`, is not stored there), else one by one.
    #[cfg(lanes)]
    #[inline(always)]
    fn hit_points_lanes<const PAD: usize>(
        &self,
        ps: &mut [Vec3],
        os: &mut [Vec3],
        (dx, dy, dz): (&[f32; PAD], &[f32; PAD], &[f32; PAD]),
        t: &[f32; PAD],
        sp: &[u16; PAD],
    ) {
        use crate::geometry::{hit_point_far4, LANES};
        use wide::f32x4 as F;
        let eye = self.camera.eye();
        let spheres = self.scene.spheres();
        let one = |m: usize, ps: &mut [Vec3], os: &mut [Vec3]| {
            let s = sp[m] as usize;
            if let (Some(k), Some(sphere), Some(p), Some(o)) = (
                self.eye.get(s),
                spheres.get(s),
                ps.get_mut(m),
                os.get_mut(m),
            ) {
                let ray = Ray::new(eye, Vec3::new(dx[m], dy[m], dz[m]));
                (*p, *o) = hit_point_near(&ray, t[m], k.f, sphere, self.offset_near(s));
            }
        };
        let len = ps.len().min(os.len());
        let mut m = 0;
        while m < len {
            let s = sp[m];
            let whole = m + LANES <= len && sp[m..m + LANES].iter().all(|&x| x == s);
            let near = whole && self.offset_near(s as usize);
            // Four hits on one sphere beyond `near2`: `hit_point_far` lane by lane.
            if whole && !near {
                if let (Some(k), Some(sphere)) = (self.eye.get(s as usize), spheres.get(s as usize))
                {
                    let lanes = |a: &[f32; PAD]| {
                        F::from(core::array::from_fn::<f32, LANES, _>(|l| a[m + l]))
                    };
                    let d = crate::math::lanes::V {
                        x: lanes(dx),
                        y: lanes(dy),
                        z: lanes(dz),
                    };
                    if let Some((p, o)) = hit_point_far4(d, lanes(t), k.f, sphere) {
                        for l in 0..LANES {
                            if let (Some(pp), Some(oo)) = (ps.get_mut(m + l), os.get_mut(m + l)) {
                                (*pp, *oo) = (p.lane(l), o.lane(l));
                            }
                        }
                        m += LANES;
                        continue;
                    }
                }
            }
            if !near {
                let end = if whole { m + LANES } else { m + 1 };
                for (q, &sq) in sp.iter().enumerate().take(end.min(len)).skip(m) {
                    if sq != NONE {
                        one(q, ps, os);
                    }
                }
                m = end;
                continue;
            }
            let lanes =
                |a: &[f32; PAD]| F::from(core::array::from_fn::<f32, LANES, _>(|l| a[m + l]));
            let (x, y, z, tt) = (lanes(dx), lanes(dy), lanes(dz), lanes(t));
            // `ray.at(t)` = eye + d·t and `f + d·t`, coordinate by coordinate.
            let (px, py, pz) = (
                F::splat(eye.x) + x * tt,
                F::splat(eye.y) + y * tt,
                F::splat(eye.z) + z * tt,
            );
            // The offsets, `f + t·d`, are left out: shading redoes them where it needs them
            // (`kept_hit`, `shade4`), which costs less than storing them by point.
            let (px, py, pz) = (px.to_array(), py.to_array(), pz.to_array());
            for l in 0..LANES {
                if let Some(p) = ps.get_mut(m + l) {
                    *p = Vec3::new(px[l], py[l], pz[l]);
                }
            }
            m += LANES;
        }
    }

    /// Joins the span's hits in `slots` (column `i0` first, sample offset `ox`, all along
    /// `row`) to their groups' bounds run by run, where the span keeps no hit points
    /// (Cortex-M): a run of hits on one sphere as the box of the row's ray fan over the run's
    /// columns and range of `t` (`RowRays::fan_box`, the range found in one tight loop), or for
    /// a sphere beyond near2 as the sphere's box (`hit_point_far` puts those points on the
    /// sphere, not at `eye + t·d`, which is off where a grazing ray's `t` is ill-conditioned).
    /// No point and box a pixel: on the M4F they had cost ~60 instructions a hit (the frame
    /// went from 516.2 to 490.0), on the M0 ~540 (15 005 to 14 659).
    #[inline(always)]
    fn bound_runs(
        &self,
        row: &crate::camera::RowRays,
        (i0, ox): (u32, f32),
        slots: core::ops::Range<usize>,
        cull: &mut Cull<S, L>,
        bounds: &mut Bounds,
    ) {
        let mut slot = slots.start;
        while slot < slots.end {
            let Some((t, s)) = cull.hit(slot) else {
                slot += 1;
                continue;
            };
            // The run's least and greatest `t` by their bits: a hit's `t` is positive (at least
            // `T_EPS`), where the bits order as the values do (M4F: integer compares, no
            // moves to and from the FPU's flags).
            let (mut t0, mut t1, mut next) = (t.to_bits(), t.to_bits(), slot + 1);
            if let (Some(ss), Some(ts)) = (cull.hit_s.get(..slots.end), cull.hit_t.get(..slots.end))
            {
                while let (Some(&s2), Some(&t)) = (ss.get(next), ts.get(next)) {
                    if s2 != s {
                        break;
                    }
                    let t = t.to_bits();
                    if t < t0 {
                        t0 = t;
                    }
                    if t > t1 {
                        t1 = t;
                    }
                    next += 1;
                }
            }
            let (t0, t1) = (f32::from_bits(t0), f32::from_bits(t1));
            let s = s as usize;
            let join = if self.offset_near(s) {
                // `column` is monotonic: the run's ends have its least and greatest.
                let x = |k: usize| (i0 + (k - slots.start) as u32) as f32 + ox;
                let columns = (row.column(x(slot)), row.column(x(next - 1)));
                Some(row.fan_box((t0, t1), columns))
            } else {
                self.scene.spheres().get(s).map(|sp| {
                    let r = Vec3::splat(sp.radius);
                    (sp.center - r, sp.center + r)
                })
            };
            if let Some(join) = join {
                let g = bounds.join::<false>(s, join);
                cull.set_group(slot..next, g);
            }
            slot = next;
        }
    }

    /// Gathers the span `[span_start, span_end)` of row `j`: its spheres from the row's, then
    /// (with shadow rays, or one sample a pixel) its primary hits, and with shadow rays the
    /// ball bounding their points and each light's possible blockers.
    #[inline(never)]
    fn gather(&self, j: u32, cull: &mut Cull<S, L>) {
        let (i0, i1) = (cull.span_start, cull.span_end);
        cull.span.clear();
        for &s in &cull.row {
            if let Some(b) = self.boxes.get(s as usize) {
                if (b.i0 as u32) < i1 && b.i1 as u32 >= i0 {
                    let _ = cull.span.push(s);
                }
            }
        }
        cull.culled = false;
        cull.stored = false;
        cull.kept = false;
        // No group until this span's: `lists` finds none where the span builds no lists.
        cull.groups = [NONE; GROUPS];
        // Without shadow rays the span needs no bounds, but with one sample a pixel its hits
        // are still traced here, in one tight loop over the span, and kept for shading.
        let kept = (self.samples * self.samples) as usize <= KEPT;
        if !self.shadow_rays && !kept {
            return;
        }
        // The span's primary hits (kept for shading when one sample per pixel), grouped by
        // the sphere hit (a sphere and the wall behind it make poor company in one bound),
        // and the box of each group's points.
        let mut bounds = Bounds::new();
        // Slots whose hit joins no group (a miss, or no point) get no lists: every sphere.
        cull.hit_g.fill(NO_GROUP);
        if self.samples == 1 && cull.span.is_empty() {
            // No sphere's box meets the span (the sky above the scene): every ray misses, and
            // none needs building.
            cull.hit_s.fill(NONE);
            cull.stored = true;
        } else {
            // Every sample's hit joins the bounds; the hits are also kept for shading where
            // there is room (`KEPT`), the samples outermost so that their offsets (the divides
            // of `Camera::primary_ray`) are hoisted.
            let n = self.samples;
            // Rows of a tile (hosts, one sample a pixel), or the samples of one row.
            for rs in 0..cull.rows() * n {
                // (Several rows come with one sample a pixel only; Cortex-M has one row.)
                let (r, sy) = if cull.rows() == 1 { (0, rs) } else { (rs, 0) };
                let y = (j + r) as f32 + sample_offset(sy, n);
                for sx in 0..n {
                    let ox = sample_offset(sx, n);
                    // The sample's slots (see `KEPT`), or the row's.
                    let base = if KEPT > 1 {
                        (r * n * n + sy * n + sx) as usize * SPAN
                    } else {
                        0
                    };
                    if SPHERE_MAJOR {
                        // Scratch slots where this sample's hits are not kept.
                        let base = if kept { base } else { 0 };
                        self.trace_span(i0, i1, ox, (j + r, y), base, cull);
                        if self.shadow_rays && KEEPS_OFFSETS {
                            // The points `trace_span` computed with its hits (`cfg(lanes)`), four
                            // at a time where four neighbours hit one sphere: their box, in
                            // registers, joins the group once.
                            let end = base + (i1 - i0) as usize;
                            let mut slot = base;
                            while slot < end {
                                let four = (slot + 4 <= end)
                                    .then(|| {
                                        let s = cull.hit_s.get(slot..slot + 4)?;
                                        let p = cull.hit_p.get(slot..slot + 4)?;
                                        let same = s[0] != NONE && s.iter().all(|&x| x == s[0]);
                                        same.then(|| (s[0], box4(p)))
                                    })
                                    .flatten();
                                if let Some((s, b)) = four {
                                    cull.set_group(
                                        slot..slot + 4,
                                        bounds.join::<true>(s as usize, b),
                                    );
                                    slot += 4;
                                    continue;
                                }
                                if let (Some((_, s)), Some(&p)) =
                                    (cull.hit(slot), cull.hit_p.get(slot))
                                {
                                    cull.set_group(
                                        slot..slot + 1,
                                        bounds.join::<true>(s as usize, (p, p)),
                                    );
                                }
                                slot += 1;
                            }
                        } else if self.shadow_rays {
                            let row = self.camera.row(y);
                            let slots = base..base + (i1 - i0) as usize;
                            self.bound_runs(&row, (i0, ox), slots, cull, &mut bounds);
                        }
                        continue;
                    }
                    // Pixel by pixel (soft-float Arm, see `SPHERE_MAJOR`).
                    let row = self.camera.row(y);
                    for (k, i) in (i0..i1).enumerate() {
                        let slot = base + k;
                        // `primary_ray(i, j, sx, sy, n)`, the same bits.
                        let ray = row.ray(i as f32 + ox);
                        let h = self.primary_among(&ray, i, &cull.span);
                        if h.is_some() {
                            // Only a hit is shaded with its ray.
                            cull.set_dir(slot, ray.dir);
                        }
                        let (t, s) = (cull.hit_t.get_mut(slot), cull.hit_s.get_mut(slot));
                        if let (Some(t), Some(s)) = (t, s) {
                            (*t, *s) = h.map_or((0.0, NONE), |(t, s)| (t, s as u16));
                        }
                    }
                    if self.shadow_rays {
                        let slots = base..base + (i1 - i0) as usize;
                        self.bound_runs(&row, (i0, ox), slots, cull, &mut bounds);
                    }
                }
            }
            cull.stored = n == 1;
            cull.kept = kept && n > 1;
        }
        if !self.shadow_rays {
            return;
        }
        cull.culled = true;
        cull.pool.clear();
        for g in 0..GROUPS {
            let (Some(slot), Some(ranges)) = (cull.groups.get_mut(g), cull.ranges.get_mut(g))
            else {
                continue;
            };
            let Some(group) = bounds.groups.get(g) else {
                *slot = NONE;
                continue;
            };
            *slot = group.sphere;
            let (lo, hi) = (group.lo, group.hi);
            let q = (lo + hi) * 0.5;
            let half = (hi - lo) * 0.5;
            // Rounding of q and of the length: a relative pad far above it. Shadow rays leave
            // from the hit's `anchor + rel`, not from these points: the two differ by the f32
            // error of the hit offset, ~4ε of the distance from the eye (f32 offsets are kept
            // out to 2048 radii, `scene::near2`), which 2⁻²⁰ of that distance covers. It covers
            // as well the few ε by which a ray fan's box (`bound_runs`) and the rounded points
            // `eye + t·d` it stands for may differ (`camera::fan_tests` checks 2⁻²²).
            let reach = (q - self.camera.eye()).length() + half.length();
            let rho = half.length() * (1.0 + 1e-5)
                + 1e-5 * q.max_abs()
                + reach * (1.0 / 1_048_576.0)
                + f32::MIN_POSITIVE;
            let bounded = rho.is_finite() && q.is_finite();
            // The scene's lights only: the ranges of light slots past them are never asked.
            for (li, (range, light)) in ranges.iter_mut().zip(self.scene.lights()).enumerate() {
                *range = ALL;
                if !bounded {
                    continue;
                }
                let start = cull.pool.len() as u16;
                let spheres = self.scene.spheres();
                let mut full = false;
                // Hosts collect the candidates first and weigh them four at a time.
                #[cfg(lanes)]
                let mut found: List<S> = heapless::Vec::new();
                let mut consider = |s: u16| {
                    // Not a group's own sphere: the shadow test skips the hit's sphere among
                    // its candidates (it finds the ray's exit from it analytically), so listing
                    // it would only cost a skip per pixel. `REST` is no sphere index (`FITS`).
                    if s == group.sphere {
                        return;
                    }
                    #[cfg(lanes)]
                    if found.push(s).is_err() {
                        full = true;
                    }
                    #[cfg(not(lanes))]
                    if let Some(sphere) = spheres.get(s as usize) {
                        if may_block(light, sphere.center, sphere.radius, q, rho)
                            && cull.pool.push(s).is_err()
                        {
                            full = true;
                        }
                    }
                };
                let band = match self.sweeps.get(li) {
                    Some(w) if Self::SWEEPS => w.band(light, q, rho),
                    _ => None,
                };
                match band {
                    // Only the spheres whose key is near the span's, and the wide ones.
                    Some((sweep, key, band, slack, key2)) => {
                        for &s in &sweep.wide {
                            consider(s);
                        }
                        sweep.scan(key, band, slack, key2, &mut consider);
                    }
                    None => {
                        for s in 0..spheres.len() {
                            consider(s as u16);
                        }
                    }
                }
                #[cfg(lanes)]
                for c in found.chunks(4) {
                    let ids: [u16; 4] = core::array::from_fn(|l| c.get(l).copied().unwrap_or(NONE));
                    let sph = ids.map(|i| spheres.get(i as usize).copied());
                    let m = sph.map(|s| s.map_or(Vec3::ZERO, |s| s.center));
                    let r = sph.map(|s| s.map_or(0.0, |s| s.radius));
                    let pass = may_block4(light, m, r, q, rho);
                    for (l, &i) in ids.iter().enumerate() {
                        if pass & (1 << l) != 0 && sph[l].is_some() && cull.pool.push(i).is_err() {
                            full = true;
                        }
                    }
                }
                if full {
                    // Out of room: this light tests every sphere for this group.
                    cull.pool.truncate(start as usize);
                } else {
                    *range = (start, cull.pool.len() as u16);
                }
            }
        }
    }
}

/// Stores the encoded `colour` of the lanes `active` of the group at `k0` into `px`, marking
/// them done; nothing when the lanes could not shade them (`None`: the scalar path will).
#[cfg(lanes)]
#[inline(always)]
fn keep4<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    px: &mut [Rgb888; SPAN],
    done: &mut u32,
    k0: usize,
    active: u32,
    colour: Option<crate::math::lanes::V>,
) {
    let Some(colour) = colour else { return };
    for (l, &c) in frame.encode4(&colour).iter().enumerate() {
        if active & (1 << l) != 0 {
            if let Some(p) = px.get_mut(k0 + l) {
                *p = c;
                *done |= 1 << (k0 + l);
            }
        }
    }
}

/// The box of four points (a coordinate that is NaN skipped, as `Frame::gather`'s bounds skip
/// it): selections in registers, one group update for four neighbouring hits instead of four.
#[inline(always)]
fn box4(p: &[Vec3]) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for q in p {
        for (k, v) in [q.x, q.y, q.z].into_iter().enumerate() {
            if let (Some(l), Some(h)) = (lo.get_mut(k), hi.get_mut(k)) {
                *l = if v < *l { v } else { *l };
                *h = if v > *h { v } else { *h };
            }
        }
    }
    (Vec3::from(lo), Vec3::from(hi))
}

/// Hit groups per span: hits on up to `GROUPS − 1` spheres get their own bound, the rest share
/// the last.
const GROUPS: usize = 4;
/// An unused group.
const NONE: u16 = u16::MAX;
/// A slot's hit in no group (`Cull::hit_g`).
const NO_GROUP: u8 = u8::MAX;
/// The group of every other sphere.
const REST: u16 = u16::MAX - 1;
/// Span pixels whose view ray direction is kept for shading: all, which spares building it again
/// per hit, except on soft-float Arm (Cortex-M0), whose deeper render stack has no room for the
/// 12 bytes a pixel (it rebuilds the ray instead: since the directions stay unnormalised, a
/// few soft-float products and sums, no square root or divide).
const DIRS: usize = if cfg!(no_dirs) { 0 } else { SPAN * KEPT };
/// Primary hits a span keeps per column for shading: the samples of a supersampled pixel, so
/// that it is not traced twice (once for the span's bounds, once to shade; up to 2×2), or with
/// one sample the rows of a tile (`Frame::render_rows`: 8 rows measured 1.045× faster than 4 on
/// the target scene, 16 no faster than 8). One on Arm, whose render stack (2 KiB on the
/// firmware) has no room for 54 more bytes a pixel; one wherever there are no lanes, so that a
/// host built without them (`MICRORAY_HOST_AS`, see build.rs) takes Cortex-M's path.
const KEPT: usize = if cfg!(lanes) { 8 } else { 1 };
/// `DIRS` and the lanes read past the last slot (`Cull::hit_dc`).
#[cfg(lanes)]
const DPAD: usize = DIRS + crate::geometry::LANES - 1;
/// Whether a span traces its primary rays sphere by sphere (`Frame::trace_span`), which needs
/// room for every pixel's view direction; on soft-float Arm, with none, pixel by pixel.
const SPHERE_MAJOR: bool = DIRS == SPAN * KEPT;
/// Kept hits whose offset from the centre the span keeps from its bounds for shading, which
/// spares `make_hit` computing it again: all on hosts with f32 vectors (`cfg(lanes)`), none on
/// Cortex-M, whose render stack has no room for 12 more bytes a pixel.
const OFFS: usize = if KEEPS_OFFSETS { SPAN * KEPT } else { 0 };
/// Whether spans keep hit offsets (`OFFS` not zero), a flag so that Cortex-M builds, where
/// `OFFS` is 0, test no comparison that is always false (clippy's `absurd_extreme_comparisons`).
const KEEPS_OFFSETS: bool = cfg!(lanes);
// `Cull::done` has a bit per span pixel.
const _: () = assert!(SPAN <= 32);
/// A light's pool range when it must test every sphere (empty as `a..b`: `a > b`).
const ALL: (u16, u16) = (u16::MAX, 0);

/// The bound of one group's hit points.
#[derive(Debug, Clone, Copy)]
struct Group {
    sphere: u16,
    lo: Vec3,
    hi: Vec3,
}

impl Group {
    /// Grows the box to hold `[lo, hi]`. Comparisons, not `f32::min`/`max` (calls to
    /// `fminf`/`fmaxf` without an FPU instruction for them); a NaN coordinate is skipped as
    /// `min`/`max` skip it.
    #[inline(always)]
    fn add_box(&mut self, p_lo: Vec3, p_hi: Vec3) {
        let widen = |l: &mut f32, h: &mut f32, a: f32, b: f32| {
            if a < *l {
                *l = a;
            }
            if b > *h {
                *h = b;
            }
        };
        let (lo, hi) = (&mut self.lo, &mut self.hi);
        widen(&mut lo.x, &mut hi.x, p_lo.x, p_hi.x);
        widen(&mut lo.y, &mut hi.y, p_lo.y, p_hi.y);
        widen(&mut lo.z, &mut hi.z, p_lo.z, p_hi.z);
    }
}

/// A span's hit groups while [`Frame::gather`] collects their bounds.
#[derive(Debug, Clone)]
struct Bounds {
    /// The groups in the order they were made, each with its sphere's hits; the last of
    /// `GROUPS` takes every other sphere (`REST`). A list, not an array of empty groups:
    /// each span starts with none, and an array's boxes were copied in for every span
    /// (M4F: ~4 instructions a pixel).
    groups: heapless::Vec<Group, GROUPS>,
    /// The group of the previous hit's sphere: a sphere keeps its group once it has one, and
    /// neighbouring pixels mostly hit the same sphere.
    last: (usize, usize),
}

impl Bounds {
    #[inline(always)]
    fn new() -> Self {
        Bounds {
            groups: heapless::Vec::new(),
            last: (usize::MAX, 0),
        }
    }

    /// The box `(lo, hi)` (a point, or several points' box) joins sphere `sphere`'s group,
    /// which it returns. `LAST`: look at the previous join's sphere first (for pixels one by
    /// one; runs of one sphere, `Frame::bound_runs`, follow each other's sphere only after
    /// another sphere's run).
    #[inline(always)]
    fn join<const LAST: bool>(&mut self, sphere: usize, (lo, hi): (Vec3, Vec3)) -> u8 {
        let g = if LAST && sphere == self.last.0 {
            self.last.1
        } else {
            // The sphere's group, or else a new one, or the last, which takes every other
            // sphere (`REST`).
            let groups = &self.groups;
            let open = groups.len().min(GROUPS - 1);
            let g = (0..open)
                .find(|&k| groups.get(k).is_some_and(|gr| gr.sphere as usize == sphere))
                .unwrap_or(open);
            if LAST {
                self.last = (sphere, g);
            }
            g
        };
        match self.groups.get_mut(g) {
            Some(gr) => gr.add_box(lo, hi),
            // A new group (`g` is the number of groups, below `GROUPS`), whose box is the
            // first. A NaN coordinate stays in it, where `add_box` skips one: the group's
            // lists are then every sphere's (`gather`: not `bounded`), which holds.
            None => {
                let sphere = if g + 1 < GROUPS { sphere as u16 } else { REST };
                let _ = self.groups.push(Group { sphere, lo, hi });
            }
        }
        g as u8
    }
}

/// Angular margin of the sweep keys of point lights (radians): far above the rounding of
/// `atan2f` and of the unit directions' components.
const ANGLE_MARGIN: f32 = 1e-4;

/// One light's spheres sorted by a key, so that a span finds its possible shadow blockers by a
/// search in a bucket instead of testing every sphere, and filtered by a second key (`axis2`):
/// for a point light, the component along an axis across the light of the unit direction from
/// the light to the sphere, with the half-angle of the sphere's (padded) cone as half-width;
/// for a directional light, the position along an axis across the light, with the padded
/// radius as half-width. A sphere can block a shadow ray from a span only if its key interval
/// meets the span's (two unit directions at an angle θ differ by at most θ in any component; a
/// distance is at least the difference of its projections), so the band is a superset of
/// [`may_block`]'s answers, which then decides.
/// Spheres much wider than the rest (a ground, a wall) would widen every band: they are kept
/// apart and always tested.
#[derive(Debug)]
struct Sweep<const S: usize> {
    /// The wide spheres.
    wide: List<S>,
    /// The rest sorted by key, by field: hosts weigh four entries at a time (`Frame::gather`).
    key: heapless::Vec<f32, S>,
    /// Each one's half-width of its padded cone (angle) or radius (length) along the key.
    half: heapless::Vec<f32, S>,
    /// Each one's coordinate along `axis2`.
    key2: heapless::Vec<f32, S>,
    sphere: List<S>,
    /// The largest half-width of the sorted ones.
    hw_max: f32,
    /// Where a scan starts: `start[b]` counts the sorted entries whose [`Sweep::bucket`] is
    /// below `b` (one more than the buckets, the last the number of entries), so that a
    /// search for a key needs only its bucket's few entries. The binary search over all of
    /// them, a chain of dependent loads, was a third of the scan's time at 256 spheres.
    start: List<S>,
    /// The smallest key, and buckets per unit of key (zero: one bucket).
    k_lo: f32,
    per_key: f32,
    /// The key axis (unit, across the light: a point light's mean direction to the spheres).
    axis: Vec3,
    /// A second axis (unit, across the light and `axis`), whose coordinates are each entry's
    /// `key2`: a sphere must be near the span in both keys, a tube along the light instead of
    /// a slab.
    axis2: Vec3,
}

/// One sphere in a [`Sweep`], while it is built.
#[derive(Debug, Clone, Copy)]
struct Entry {
    /// Its position along the sweep's axis (of its unit direction, for a point light).
    key: f32,
    /// The half-width of its padded cone (angle) or radius (length) along the key.
    half: f32,
    sphere: u16,
    /// Its coordinate along `Sweep::axis2`.
    key2: f32,
}

impl Entry {
    fn new(key: f32, half: f32, sphere: usize, key2: f32) -> Self {
        Entry {
            key,
            half,
            sphere: sphere as u16,
            key2,
        }
    }
}

impl<const S: usize> Sweep<S> {
    const fn empty() -> Self {
        Sweep {
            wide: heapless::Vec::new(),
            key: heapless::Vec::new(),
            half: heapless::Vec::new(),
            key2: heapless::Vec::new(),
            sphere: heapless::Vec::new(),
            hw_max: 0.0,
            start: heapless::Vec::new(),
            k_lo: 0.0,
            per_key: 0.0,
            axis: Vec3::ZERO,
            axis2: Vec3::ZERO,
        }
    }

    /// The bucket of a key: a non-decreasing function of it (a subtraction, a product by a
    /// constant ≥ 0 and a saturating conversion, each monotonic in IEEE arithmetic), so that
    /// the entries before `start[bucket(x)]` have keys below `x` and those from
    /// `start[bucket(x) + 1]` keys above it.
    #[inline(always)]
    fn bucket(&self, key: f32) -> usize {
        let x = (key - self.k_lo) * self.per_key;
        let last = self.start.len().saturating_sub(2);
        // `!(x >= 0)` also takes a NaN (x = 0·∞) to the first bucket.
        if !(x >= 0.0) {
            0
        } else {
            (x as usize).min(last)
        }
    }

    /// Sorts `spheres` for `light` into this sweep, which must be empty.
    fn fill(&mut self, light: &Light, spheres: &[crate::Sphere], u: Vec3, v: Vec3) {
        // Keys across the light's direction (a point light's: the mean direction from it to
        // the spheres, else the view's), where they spread the spheres the most: a point
        // light's are the components of the unit direction to each sphere, which two
        // directions at an angle θ differ in by at most 2 sin(θ/2) ≤ θ, so angular
        // half-widths bound them (an angle from one axis took an `atan2f` per span).
        let along = match *light {
            Light::Point { position, .. } => spheres
                .iter()
                .filter_map(|s| (s.center - position).normalized())
                .fold(Vec3::ZERO, |sum, d| sum + d)
                .normalized()
                .or_else(|| u.cross(v).normalized()),
            Light::Directional { direction, .. } => Some(direction),
        };
        let axis = along.and_then(|c| {
            // The camera's right (or up) vector without its component along `c`.
            let across = |a: Vec3| a - c * a.dot(c);
            let a = across(u);
            let a = if a.dot(a) > 0.01 { a } else { across(v) };
            a.normalized()
        });
        let (Some(along), Some(axis)) = (along, axis) else {
            return;
        };
        self.axis = axis;
        // The third coordinate, which the keys leave out, is then along the light, where a
        // scene's spheres seldom lie on both sides of a point light.
        self.axis2 = along.cross(axis).normalized().unwrap_or(Vec3::ZERO);
        let axis2 = self.axis2;
        let mut all: heapless::Vec<Entry, S> = heapless::Vec::new();
        for (s, sphere) in spheres.iter().enumerate() {
            let (m, r) = (sphere.center, sphere.radius);
            let l1 = |w: Vec3| libm::fabsf(w.x) + libm::fabsf(w.y) + libm::fabsf(w.z);
            let e = match *light {
                Light::Point { position, .. } => {
                    // The same padded radius as `may_block`.
                    let w = m - position;
                    let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(w) + r);
                    let ww = w.dot(w);
                    if !(ww > big * big * 1.01) {
                        // The light inside or near: wide.
                        Entry::new(0.0, f32::INFINITY, s, 0.0)
                    } else {
                        let hw = libm::atan2f(big, libm::sqrtf(ww - big * big));
                        let len = libm::sqrtf(ww);
                        Entry::new(axis.dot(w) / len, hw, s, axis2.dot(w) / len)
                    }
                }
                Light::Directional { .. } => {
                    // `may_block` pads with 2η|m − q|₁ ≤ 2η(|m|₁ + |q|₁); the |q|₁ part and
                    // the rounding of keys (1e-5 of |m|₁, |q|₁) are added per span.
                    let big = r * (1.0 + 2e-4) + 2.0 * ETA * (l1(m) + r) + 1e-5 * l1(m);
                    Entry::new(axis.dot(m), big, s, axis2.dot(m))
                }
            };
            let _ = all.push(e);
        }
        // "Wide": more than 8 times the median half-width.
        let mut hws: heapless::Vec<f32, S> = all.iter().map(|e| e.half).collect();
        hws.sort_unstable_by(|a, b| a.total_cmp(b));
        let median = hws.get(hws.len() / 2).copied().unwrap_or(0.0);
        let is_wide =
            |e: &Entry| !(e.half <= 8.0 * median && e.key.is_finite() && e.key2.is_finite());
        for e in all.iter().filter(|e| is_wide(e)) {
            let _ = self.wide.push(e.sphere);
        }
        all.retain(|e| !is_wide(e));
        all.sort_unstable_by(|a, b| a.key.total_cmp(&b.key));
        // At most S entries in all: none of the pushes can fail.
        for e in &all {
            let _ = self.key.push(e.key);
            let _ = self.half.push(e.half);
            let _ = self.key2.push(e.key2);
            let _ = self.sphere.push(e.sphere);
            self.hw_max = self.hw_max.max(e.half);
        }
        self.index();
    }

    /// The index of the first key ≥ `x` (`key.partition_point(|&k| k < x)`), searched in
    /// `x`'s bucket only.
    #[cfg(test)]
    fn first(&self, x: f32) -> usize {
        self.first_in(self.bucket(x), x)
    }

    /// [`Sweep::first`] of `x` in its bucket `b`.
    #[inline(always)]
    fn first_in(&self, b: usize, x: f32) -> usize {
        let (lo, hi) = (self.start.get(b), self.start.get(b + 1));
        let (lo, hi) = (
            lo.map_or(0, |&i| i as usize),
            hi.map_or(self.key.len(), |&i| i as usize),
        );
        lo + self
            .key
            .get(lo..hi)
            .map_or(0, |keys| keys.partition_point(|&k| k < x))
    }

    /// An index at or before [`Sweep::first`]`(x)`, and at most 8 entries before it: its
    /// bucket's start where the bucket is that small (a search there cost more, in
    /// mispredicted branches, than scanning its keys in lanes: 2% of the 256-sphere frame).
    #[inline(always)]
    fn near_first(&self, x: f32) -> usize {
        let b = self.bucket(x);
        match (self.start.get(b), self.start.get(b + 1)) {
            (Some(&lo), Some(&hi)) if hi - lo <= 8 => lo as usize,
            _ => self.first_in(b, x),
        }
    }

    /// Builds `start` for the sorted keys: about four entries a bucket, evenly spaced in key.
    fn index(&mut self) {
        self.start.clear();
        let n = self.key.len();
        let buckets = (n / 4).max(1);
        if let (Some(&lo), Some(&hi)) = (self.key.first(), self.key.last()) {
            let per_key = buckets as f32 / (hi - lo);
            self.k_lo = lo;
            self.per_key = if per_key.is_finite() { per_key } else { 0.0 };
        }
        // At most S / 4 + 1 ≤ S values, or two for no entry: only a sweep of capacity 1
        // (never built, `SWEEPS`) could lack room, and `first` then searches all keys.
        for _ in 0..=buckets {
            let _ = self.start.push(0);
        }
        let mut i = 0;
        for b in 0..=buckets {
            while self.key.get(i).is_some_and(|&k| self.bucket(k) < b) {
                i += 1;
            }
            if let Some(first) = self.start.get_mut(b) {
                *first = i as u16;
            }
        }
    }

    /// Calls `consider` with the sorted spheres, in their order, whose `|key_j − key| ≤
    /// half_j + slack` and `|key2_j − key2| ≤ half_j + slack` among those with `key_j` within
    /// `band` of `key` (see [`Sweep::band`]), and a few before them that pass the same test
    /// only by rounding (a candidate more, which the shadow test decides).
    #[inline(always)]
    fn scan(&self, key: f32, band: f32, slack: f32, key2: f32, consider: &mut impl FnMut(u16)) {
        let (hi, n) = (key + band, self.key.len());
        // Within a few entries of the first key ≥ key − band: the keys before that are more
        // than `band` from `key` but for rounding, and the filter below decides them.
        let mut i = self.near_first(key - band);
        // Hosts: four entries at a time, the same comparisons lane by lane; the keys are sorted,
        // so the entries within the band are a prefix of the four.
        #[cfg(lanes)]
        {
            use crate::math::lanes::{bits, ones, F};
            use wide::CmpLe;
            fn from(v: &[f32], i: usize) -> &[f32] {
                v.get(i..).unwrap_or(&[])
            }
            let (ks, hs, k2s) = (from(&self.key, i), from(&self.half, i), from(&self.key2, i));
            let ss = self.sphere.get(i..).unwrap_or(&[]);
            let quads = ks.chunks_exact(4).zip(hs.chunks_exact(4));
            for ((k, h), (k2, s)) in quads.zip(k2s.chunks_exact(4).zip(ss.chunks_exact(4))) {
                let four = |c: &[f32]| <[f32; 4]>::try_from(c).ok().map(F::from);
                let (Some(k), Some(h), Some(k2)) = (four(k), four(h), four(k2)) else {
                    break;
                };
                let near = h + F::splat(slack);
                let within = k.cmp_le(F::splat(hi));
                let keep = within
                    & (k - F::splat(key)).abs().cmp_le(near)
                    & (k2 - F::splat(key2)).abs().cmp_le(near);
                for l in ones(bits(keep)) {
                    if let Some(&s) = s.get(l) {
                        consider(s);
                    }
                }
                if bits(within) != 0b1111 {
                    return;
                }
                i += 4;
            }
        }
        while i < n {
            let (Some(&k), Some(&h), Some(&k2), Some(&s)) = (
                self.key.get(i),
                self.half.get(i),
                self.key2.get(i),
                self.sphere.get(i),
            ) else {
                return;
            };
            if k > hi {
                return;
            }
            // `&`, not `&&`: one branch on the outcome rather than two.
            let near = h + slack;
            if (libm::fabsf(k - key) <= near) & (libm::fabsf(k2 - key2) <= near) {
                consider(s);
            }
            i += 1;
        }
    }

    /// For shadow rays from the ball `(q, rho)`: `(self, key, band, slack, key2)` where the
    /// spheres to consider have `|key_j − key| ≤ half-width_j + slack` (so `key_j` within
    /// `band`) and, along `axis2`, `|key2_j − key2| ≤ half-width_j + slack`; or `None` when the
    /// sweep does not apply (no axis, or the light inside the ball).
    fn band(&self, light: &Light, q: Vec3, rho: f32) -> Option<(&Self, f32, f32, f32, f32)> {
        if self.axis == Vec3::ZERO {
            return None;
        }
        let l1 = libm::fabsf(q.x) + libm::fabsf(q.y) + libm::fabsf(q.z);
        let (key, slack, key2) = match *light {
            Light::Point { position, .. } => {
                let v = q - position;
                let vv = v.dot(v);
                if !(vv > rho * rho * 1.01) {
                    return None;
                }
                let len = libm::sqrtf(vv);
                let (key, key2) = (self.axis.dot(v) / len, self.axis2.dot(v) / len);
                // The ball's half-angle seen from the light is atan of this, and atan x ≤ x:
                // a wider band, never a narrower one, without an `atan2f` per span.
                let tan_theta = rho / libm::sqrtf(vv - rho * rho);
                (key, tan_theta + ANGLE_MARGIN, key2)
            }
            // The same bound holds along any unit axis across a directional light.
            Light::Directional { .. } => (
                self.axis.dot(q),
                rho + 2.0 * ETA * (l1 + rho) + rho + 1e-5 * l1,
                self.axis2.dot(q),
            ),
        };
        if !(key.is_finite() && slack.is_finite() && key2.is_finite()) {
            return None;
        }
        Some((self, key, self.hw_max + slack, slack, key2))
    }
}

/// [`may_block`] of four spheres (centres `m`, radii `r`) at once in vector lanes (`cfg(lanes)`):
/// the same operations lane by lane, so the same answers, as bits `0..4`.
#[cfg(lanes)]
#[inline(always)]
fn may_block4(light: &Light, m: [Vec3; 4], r: [f32; 4], q: Vec3, rho: f32) -> u32 {
    use wide::{f32x4 as F, CmpGt, CmpLt};
    let v = F::splat;
    let (mx, my, mz) = (
        F::from(m.map(|c| c.x)),
        F::from(m.map(|c| c.y)),
        F::from(m.map(|c| c.z)),
    );
    let r = F::from(r);
    let (rho_v, eta2) = (v(rho), v(2.0 * ETA));
    let not_above = |g: F, tol: F| !(g.cmp_gt(tol)).move_mask() as u32 & 0b1111;
    match *light {
        Light::Point { position, .. } => {
            let (wx, wy, wz) = (mx - v(position.x), my - v(position.y), mz - v(position.z));
            let qv = q - position;
            let big = r * v(1.0 + 2e-4) + eta2 * (wx.abs() + wy.abs() + wz.abs() + r);
            let (ww, vv) = (wx * wx + wy * wy + wz * wz, v(qv.dot(qv)));
            let wv = wx * v(qv.x) + wy * v(qv.y) + wz * v(qv.z);
            let a = vv - v(rho * rho);
            let b = wv + big * rho_v;
            let g0 = ww - big * big;
            let g1 = a - v(2.0) * b + g0;
            let gmin = g0.cmp_lt(g1).blend(g0, g1);
            let inner = a.cmp_gt(F::ZERO) & b.cmp_gt(F::ZERO) & b.cmp_lt(a);
            let gv = g0 - b * (b / a);
            let gmin = (inner & gv.cmp_lt(gmin)).blend(gv, gmin);
            let tol = v(1e-5) * (ww + vv + big * big + v(rho * rho));
            not_above(gmin, tol)
        }
        Light::Directional { direction, .. } => {
            let l = -direction;
            let (wx, wy, wz) = (mx - v(q.x), my - v(q.y), mz - v(q.z));
            let s = wx * v(l.x) + wy * v(l.y) + wz * v(l.z);
            let ahead = s.cmp_gt(F::ZERO);
            let (ex, ey, ez) = (
                ahead.blend(wx - v(l.x) * s, wx),
                ahead.blend(wy - v(l.y) * s, wy),
                ahead.blend(wz - v(l.z) * s, wz),
            );
            let big =
                r * v(1.0 + 2e-4) + eta2 * (wx.abs() + wy.abs() + wz.abs() + rho_v + r) + rho_v;
            let d2 = ex * ex + ey * ey + ez * ez;
            let tol = v(1e-5) * (wx * wx + wy * wy + wz * wz + big * big);
            not_above(d2 - big * big, tol)
        }
    }
}

/// Whether a sphere (centre `m`, radius `r`) can block a shadow ray towards `light` from some
/// point of the ball `(q, rho)`: a conservative test, padded well beyond the rounding of the
/// shadow test itself and of this one.
/// Hosts weigh candidates four at a time with [`may_block4`]; this stays the Arm path and the
/// reference the lanes are tested against.
#[cfg_attr(lanes, allow(dead_code))]
#[inline]
fn may_block(light: &Light, m: Vec3, r: f32, q: Vec3, rho: f32) -> bool {
    match *light {
        Light::Point { position, .. } => {
            // Shadow rays run from the light to points of the ball: the segments fill the
            // cone hull of the light and the ball, whose section at λ ∈ [0, 1] along
            // v = q − light is the ball (light + λ v, λ ρ). The sphere misses it iff
            // g(λ) = |w − λ v|² − (R + λ ρ)² > 0 on [0, 1], w = m − light.
            let w = m - position;
            let v = q - position;
            // |x| + |y| + |z| ≥ |w|: a wider pad without a square root.
            let big = r * (1.0 + 2e-4)
                + 2.0 * ETA * (libm::fabsf(w.x) + libm::fabsf(w.y) + libm::fabsf(w.z) + r);
            let (ww, vv, wv) = (w.dot(w), v.dot(v), w.dot(v));
            let a = vv - rho * rho;
            let b = wv + big * rho;
            let g0 = ww - big * big;
            let g1 = a - 2.0 * b + g0;
            let mut gmin = if g0 < g1 { g0 } else { g1 };
            if a > 0.0 && b > 0.0 && b < a {
                let gv = g0 - b * (b / a);
                if gv < gmin {
                    gmin = gv;
                }
            }
            let tol = 1e-5 * (ww + vv + big * big + rho * rho);
            !(gmin > tol)
        }
        Light::Directional { direction, .. } => {
            // Shadow rays leave points of the ball along l = −direction: the sphere misses
            // them iff it stays farther than R + ρ from the half-line q + t l, t ≥ 0.
            let l = -direction;
            let w = m - q;
            let s = w.dot(l);
            let e = if s > 0.0 { w - l * s } else { w };
            let big = r * (1.0 + 2e-4)
                + 2.0 * ETA * (libm::fabsf(w.x) + libm::fabsf(w.y) + libm::fabsf(w.z) + rho + r)
                + rho;
            let d2 = e.dot(e);
            let tol = 1e-5 * (w.dot(w) + big * big);
            !(d2 - big * big > tol)
        }
    }
}

/// The candidate lists of the span being traced: the row's spheres, the span's, and for each
/// light the spheres that can block its shadow rays from the span's primary hits (all kept in
/// one pool of `S` indices; a light that does not fit tests every sphere).
///
/// On Cortex-M `repr(C)`, the per-slot arrays first: a new row's zeros (`Cull::new`) are then
/// written straight into the `Row` that `Frame::row` returns; in the compiler's own layout it
/// built them in a temporary and copied 576 bytes a row (M4F: 397.6 → 395.1 instructions a
/// pixel). Hosts keep the compiler's layout (x86: +0.14% instructions a pixel in `repr(C)`).
#[derive(Debug)]
#[cfg_attr(not(lanes), repr(C))]
struct Cull<const S: usize, const L: usize> {
    hit_t: [f32; SPAN * KEPT],
    #[cfg(not(lanes))]
    hit_d: [Vec3; DIRS],
    hit_s: [u16; SPAN * KEPT],
    /// Where `culled`, the hit group of each slot's hit (`NO_GROUP`: none), whose shadow lists
    /// shading takes without searching the groups for the hit's sphere.
    hit_g: [u8; SPAN * KEPT],
    row: List<S>,
    span: List<S>,
    pool: List<S>,
    /// The sphere of each hit group (`NONE`: unused, `REST`: every other sphere).
    groups: [u16; GROUPS],
    /// Per group and light, its slice `a..b` of `pool`; [`ALL`] (`a > b`): test every sphere.
    ranges: [[(u16, u16); L]; GROUPS],
    span_start: u32,
    span_end: u32,
    /// Shadow lists are valid for this span.
    culled: bool,
    /// `hit_t`, `hit_s` hold the span's primary hits (one sample per pixel) as `t` and sphere
    /// (`NONE`: no hit), and `hit_d` (see [`DIRS`]) the direction of each hit's view ray: 6 or
    /// 18 bytes a pixel, for microcontroller stacks.
    stored: bool,
    /// The same for every sample of a supersampled span, sample `m` of pixel `k` in slot
    /// `m·SPAN + k` (see [`KEPT`]). Apart from `stored` so that a pixel of one sample tests one
    /// flag, not also the sample count (one flag for both: +0.5% x86 instructions a pixel).
    kept: bool,
    /// On hosts, the directions by coordinate (x, y, z), padded to whole lanes past the last
    /// slot: traced and shaded four columns at a time, a lane group is one load per
    /// coordinate (`Vec3`s would be transposed both ways).
    #[cfg(lanes)]
    hit_dc: [[f32; DPAD]; 3],
    /// Where `culled`, each kept hit's point and offset from its sphere's centre, which the
    /// span's bounds take and shading reuses (see [`OFFS`]); the offset only for spheres
    /// beyond near2 (`Frame::offset_near`), whose offsets cost more than `f + t·d`.
    hit_p: [Vec3; OFFS],
    hit_o: [Vec3; OFFS],
    /// On hosts with f32 vectors (`cfg(lanes)`), the span's pixels that `Frame::shade_span4`
    /// shaded four at a time or found to be misses (bit `k` for pixel `k`), and all the span's
    /// pixels once `Frame::fill_span` has shaded the rest.
    #[cfg(lanes)]
    done: u32,
    #[cfg(lanes)]
    px: [Rgb888; SPAN],
    /// The pixel of every primary ray that hits nothing.
    miss: Rgb888,
    /// On hosts, the rows a span gathers at once (`Frame::render_rows` with one sample a
    /// pixel and shadow rays: up to `KEPT`), row `r`'s hits in slots `r·SPAN + k`, and the
    /// first slot of the row being shaded.
    #[cfg(lanes)]
    rows: u32,
    #[cfg(lanes)]
    base: usize,
}

impl<const S: usize, const L: usize> Cull<S, L> {
    fn new() -> Self {
        Cull {
            row: heapless::Vec::new(),
            span: heapless::Vec::new(),
            pool: heapless::Vec::new(),
            // Zeros, which the compiler writes in place (one `memset`), wherever `gather` writes
            // the field before it is read: the groups, their ranges and the slots.
            groups: [0; GROUPS],
            ranges: [[(0, 0); L]; GROUPS],
            span_start: 0,
            span_end: 0,
            culled: false,
            stored: false,
            kept: false,
            hit_t: [0.0; SPAN * KEPT],
            hit_s: [0; SPAN * KEPT],
            hit_g: [0; SPAN * KEPT],
            #[cfg(not(lanes))]
            hit_d: [Vec3::ZERO; DIRS],
            #[cfg(lanes)]
            hit_dc: [[0.0; DPAD]; 3],
            hit_p: [Vec3::ZERO; OFFS],
            hit_o: [Vec3::ZERO; OFFS],
            #[cfg(lanes)]
            done: 0,
            #[cfg(lanes)]
            px: [Rgb888::new(0, 0, 0); SPAN],
            miss: Rgb888::new(0, 0, 0),
            #[cfg(lanes)]
            rows: 1,
            #[cfg(lanes)]
            base: 0,
        }
    }

    /// The rows the span gathers at once (1 on Cortex-M).
    #[inline(always)]
    fn rows(&self) -> u32 {
        #[cfg(lanes)]
        return self.rows;
        #[cfg(not(lanes))]
        1
    }

    /// The slot of pixel `k` of the row being shaded.
    #[inline(always)]
    fn slot(&self, k: usize) -> usize {
        #[cfg(lanes)]
        return self.base + k;
        #[cfg(not(lanes))]
        k
    }

    /// The stored primary hit of the span's pixel `k`, as `(t, sphere)`.
    #[inline]
    fn hit(&self, k: usize) -> Option<(f32, u16)> {
        match (self.hit_t.get(k), self.hit_s.get(k)) {
            (Some(&t), Some(&s)) if s != NONE => Some((t, s)),
            _ => None,
        }
    }

    /// Pixels in the current span (the lane paths').
    #[cfg(lanes)]
    #[inline(always)]
    fn span_len(&self) -> usize {
        ((self.span_end - self.span_start) as usize).min(SPAN)
    }

    /// The view direction kept in slot `k` (none where `DIRS` keeps none).
    #[inline(always)]
    fn dir(&self, k: usize) -> Option<Vec3> {
        #[cfg(lanes)]
        {
            let [x, y, z] = &self.hit_dc;
            Some(Vec3::new(*x.get(k)?, *y.get(k)?, *z.get(k)?))
        }
        #[cfg(not(lanes))]
        self.hit_d.get(k).copied()
    }

    /// Keeps `d` as the view direction of slot `k`, where there is room.
    #[inline(always)]
    fn set_dir(&mut self, k: usize, d: Vec3) {
        #[cfg(lanes)]
        for (a, v) in self.hit_dc.iter_mut().zip([d.x, d.y, d.z]) {
            if let Some(a) = a.get_mut(k) {
                *a = v;
            }
        }
        #[cfg(not(lanes))]
        if let Some(a) = self.hit_d.get_mut(k) {
            *a = d;
        }
    }

    /// Records that the hits in `slots` joined group `g` (see `hit_g`).
    #[inline(always)]
    fn set_group(&mut self, slots: core::ops::Range<usize>, g: u8) {
        if let Some(gs) = self.hit_g.get_mut(slots) {
            gs.fill(g);
        }
    }

    /// The shadow lists of the primary hit in `slot` (see `hit_g`), when the span has them.
    #[inline(always)]
    fn lists_at(&self, slot: usize) -> Option<Lists<'_, L>> {
        if !self.culled {
            return None;
        }
        Some(Lists {
            ranges: self.ranges.get(*self.hit_g.get(slot)? as usize)?,
            pool: &self.pool,
        })
    }

    /// The shadow lists of a primary hit on `sphere`: its group's pool range per light; none
    /// where the span built no lists (`gather`, which every span's pixels come after, clears
    /// the groups first and names them only with shadow rays).
    #[inline]
    fn lists(&self, sphere: usize) -> Option<Lists<'_, L>> {
        let mut g = None;
        for (k, &s) in self.groups.iter().enumerate() {
            if s as usize == sphere && s < REST {
                g = Some(k);
                break;
            }
            if s == REST {
                g = Some(k);
            }
        }
        Some(Lists {
            ranges: self.ranges.get(g?)?,
            pool: &self.pool,
        })
    }
}

/// The shadow lists of one primary hit (see [`Cull::lists`]).
#[derive(Debug, Clone, Copy)]
struct Lists<'c, const L: usize> {
    ranges: &'c [(u16, u16); L],
    pool: &'c [u16],
}

impl<'c, const L: usize> Lists<'c, L> {
    /// Whether light `i` has no candidate blocker (its list is empty, not "every sphere").
    #[inline(always)]
    fn is_empty(self, i: usize) -> bool {
        self.ranges.get(i).is_some_and(|&(a, b)| a == b)
    }

    /// The candidate blockers of light `i`, or `None` when it must test every sphere.
    #[inline]
    fn light(self, i: usize) -> Option<&'c [u16]> {
        let (a, b) = self.ranges.get(i).copied()?;
        // The common case, no candidate, without the slice's bounds checks.
        if a == b {
            return Some(&[]);
        }
        // `ALL` has a > b: no slice.
        self.pool.get(a as usize..b as usize)
    }
}

/// One row of one span of a tile (see [`Frame::tile_rows`]): the pixels `(i.., j)`.
#[cfg(lanes)]
pub(crate) struct TileRow<'p> {
    pub(crate) i: u32,
    pub(crate) j: u32,
    pub(crate) px: &'p [Rgb888],
}

#[cfg(lanes)]
impl TileRow<'_> {
    /// Where these pixels go in `buf`, whole rows of `w` pixels from row `first_row`: the rest
    /// of `buf` from pixel `(i, j)` (empty past its end).
    #[inline(always)]
    pub(crate) fn place<'b, C>(&self, buf: &'b mut [C], first_row: u32, w: usize) -> &'b mut [C] {
        let at = (self.j - first_row) as usize * w + self.i as usize;
        buf.get_mut(at..).unwrap_or(&mut [])
    }
}

/// The pixels of one row, traced span by span (see [`Frame::row`]).
#[derive(Debug)]
pub struct Row<'f, 'a, const S: usize, const L: usize> {
    frame: &'f Frame<'a, S, L>,
    j: u32,
    i: u32,
    end: u32,
    cull: Cull<S, L>,
}

impl<const S: usize, const L: usize> Iterator for Row<'_, '_, S, L> {
    type Item = Rgb888;

    // Out of line: the row's whole pixel pipeline, which displays reach through adapters
    // (`by_ref`, `map`); one copy of it, whatever wraps the row.
    #[inline(never)]
    fn next(&mut self) -> Option<Rgb888> {
        if self.i >= self.end {
            return None;
        }
        let px = self.frame.next_pixel(self.j, self.i, &mut self.cull);
        self.i += 1;
        Some(px)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = (self.end - self.i) as usize;
        (n, Some(n))
    }
}

#[cfg(all(test, lanes))]
mod lane_tests {
    use super::*;

    /// `may_block4` answers as `may_block` does, lane by lane, for both kinds of light, on
    /// spheres and balls of every size and distance, near the edge of the test especially.
    #[test]
    fn lane_blockers_are_may_block() {
        let mut g = crate::math::TestRng(0x9e37_79b9_7f4a_7c15);
        let (mut yes, mut no) = (0, 0);
        for case in 0..50_000 {
            let scale = [1e-3f32, 1.0, 1e3][case % 3];
            let (q, rho) = (g.vec(8.0 * scale), g.unit() * scale);
            let light = if case % 2 == 0 {
                Light::Point {
                    position: g.vec(8.0 * scale),
                    intensity: Color::ONE,
                }
            } else {
                let d = g.vec(1.0).normalized().unwrap_or(Vec3::new(0.0, -1.0, 0.0));
                Light::Directional {
                    direction: d,
                    intensity: Color::ONE,
                }
            };
            let r: [f32; 4] = core::array::from_fn(|_| g.unit() * scale);
            // Half the spheres anywhere, half about as far from the shadow rays' axis as the
            // test's edge, where it decides by a hair.
            let far_end = match light {
                Light::Point { position, .. } => position,
                Light::Directional { direction, .. } => q - direction * (8.0 * scale),
            };
            let m: [Vec3; 4] = core::array::from_fn(|l| {
                if l % 2 == 0 {
                    return g.vec(8.0 * scale);
                }
                let u = g.unit();
                let axis = q + (far_end - q) * u;
                let side = g.vec(1.0).normalized().unwrap_or(Vec3::new(1.0, 0.0, 0.0));
                if l == 1 {
                    return axis + side * ((r[l] + rho * u) * (0.9 + 0.2 * g.unit()));
                }
                // Within half the test's pad either side of its edge: the cone's radius there
                // (ρ at the ball, 0 at a point light; ρ all along a directional light's sweep)
                // plus r and the pad's estimate, 2·10⁻⁴ r + 2 ETA |w|₁.
                let (w, reach) = match light {
                    Light::Point { position, .. } => (axis - position, rho * (1.0 - u)),
                    Light::Directional { .. } => (axis - q, rho),
                };
                let l1 = w.x.abs() + w.y.abs() + w.z.abs();
                let pad = 2e-4 * r[l] + 2.0 * ETA * (l1 + r[l] + reach);
                axis + side * (r[l] + reach + pad * (0.5 + g.unit()))
            });
            let lanes = may_block4(&light, m, r, q, rho);
            for l in 0..4 {
                let scalar = may_block(&light, m[l], r[l], q, rho);
                assert_eq!(
                    lanes & (1 << l) != 0,
                    scalar,
                    "{light:?} {:?} {} {q:?} {rho}",
                    m[l],
                    r[l]
                );
                if scalar {
                    yes += 1
                } else {
                    no += 1
                }
            }
        }
        assert!(yes > 10_000 && no > 10_000, "{yes} {no}");
    }

    /// `linear_bytes` is `encode_channel(_, Linear)` on every kind of value: the byte range and
    /// its edges, just below and above 0 and 1, values that round to 256, huge, infinite, NaN,
    /// negative zero and subnormals.
    #[test]
    fn lane_bytes_are_encode_channel() {
        let mut xs = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MAX,
            f32::MIN,
            1e-45,
            -1e-45,
            0.5 / 255.0,
            255.5 / 255.0,
            1.0 + f32::EPSILON,
            1.0 - f32::EPSILON,
            -0.5 / 255.0,
            3e9,
        ]
        .to_vec();
        for k in 0..=65_536u32 {
            let x = k as f32 / 65_536.0 * 1.1 - 0.05;
            xs.extend([
                x,
                f32::from_bits(x.to_bits() + 1),
                f32::from_bits(x.to_bits() ^ 1),
            ]);
        }
        for c in xs.chunks(4) {
            let mut a = [0.0f32; 4];
            a[..c.len()].copy_from_slice(c);
            let lanes = linear_bytes(crate::math::lanes::F::from(a)).to_array();
            for (l, &x) in a.iter().enumerate() {
                let byte = i32::from(encode_channel(x, Encoding::Linear));
                assert_eq!(lanes[l], byte, "{x:e}");
            }
        }
    }
}

#[cfg(test)]
mod sweep_tests {
    use super::*;

    /// `Sweep::first` is the binary search over all keys, and `near_first` at most 8 entries
    /// before it, for keys spread evenly, clustered, repeated, uneven, a single one, none, and
    /// for queries inside, below, above and between them, at their exact values and one ulp
    /// off; and a bucket holds a few keys when they are spread.
    #[test]
    fn bucketed_search_is_the_binary_search() {
        let mut g = crate::math::TestRng(0x5eed_5eed_5eed);
        let (mut in_bucket, mut queries) = (0usize, 0usize);
        for case in 0..400 {
            let n = [0, 1, 2, 5, 64, 256][case % 6];
            let mut keys: heapless::Vec<f32, 256> = (0..n)
                .map(|_| match case % 4 {
                    0 => g.unit() * 3.0 - 1.5,             // spread
                    1 => 0.5 + g.unit() * 1e-6,            // clustered in a few ulp
                    2 => (g.unit() * 8.0) as u32 as f32,   // repeated values
                    _ => libm::powf(10.0, g.unit() * 8.0), // uneven
                })
                .collect();
            keys.sort_unstable_by(|a, b| a.total_cmp(b));
            let mut w: Sweep<256> = Sweep::empty();
            for &k in &keys {
                let _ = w.key.push(k);
            }
            w.index();
            assert_eq!(w.start.len(), (n / 4).max(1) + 1);
            let probes = keys.iter().flat_map(|&k| {
                [
                    k,
                    f32::from_bits(k.to_bits() + 1),
                    f32::from_bits(k.to_bits() - 1),
                ]
            });
            let others = [-1e30, -2.0, 0.0, 0.5, 2.0, 1e9, 1e30, f32::MIN, f32::MAX];
            for x in probes.chain(others) {
                let exact = keys.partition_point(|&k| k < x);
                assert_eq!(w.first(x), exact, "case {case}: key {x}");
                let near = w.near_first(x);
                assert!(
                    near <= exact && exact - near <= 8,
                    "case {case}: key {x} at {near}"
                );
                if case % 4 == 0 {
                    let b = w.bucket(x);
                    in_bucket += (w.start[b + 1] - w.start[b]) as usize;
                    queries += 1;
                }
            }
        }
        // Spread keys, about four a bucket: a search of two or three steps, not eight.
        assert!(
            in_bucket < 8 * queries,
            "{in_bucket} keys in {queries} queries' buckets"
        );
    }
}

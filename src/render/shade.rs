//! Shading a span's pixels from their stored hits: the shadow tests with the span's candidate
//! lists, and four neighbouring pixels of one sphere at once on targets with lanes.

use super::*;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
    /// Shades the span's stored primary hits four neighbouring pixels at a time, one lane pass
    /// for each sphere that is not a mirror among the four ([`shade_lit4`](crate::shading)),
    /// into `cull.px`, marking them in `cull.done`: the pixels `next_pixel` would compute one
    /// by one, bit for bit (the hit records built lane by lane as `make_hit` builds them, the
    /// shadow tests the scalar ones, asked for the same lanes and lights). Misses are marked
    /// done too (`px` starts as the background); every other pixel is left to the scalar path.
    #[cfg(lanes)]
    #[inline(never)]
    pub(super) fn shade_span4(&self, cull: &mut Cull<S, L>) {
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
    /// one lane pass per sphere, each keeping the lanes that hit it, rather than leaving such a
    /// group to the scalar path pixel by pixel (scenes of many small spheres have many edges).
    /// Out of line, so that the common group's code keeps its values in registers.
    #[cfg(lanes)]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)]
    pub(super) fn shade4_mixed(
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
    /// copy of their own, whose shadow-test closure is inlined (shared, it goes out of line).
    #[cfg(lanes)]
    #[inline(always)]
    pub(super) fn shade4<const ALL: bool>(
        &self,
        cull: &Cull<S, L>,
        q: usize,
        si: usize,
        active: u32,
        ts: &[f32],
        [x, y, z]: [[f32; 4]; 3],
    ) -> Option<crate::simd::V> {
        use crate::shading::{in_shadow4, shade_lit4, Hits4};
        use crate::simd::{bits, F, V};
        use wide::{CmpGt, CmpLe, CmpLt};
        let scene = self.scene;
        let active = if ALL { 0b1111 } else { active };
        let (k, sphere) = (self.tables.eye.get(si)?, scene.spheres().get(si)?);
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
    pub(super) fn offset_near(&self, s: usize) -> bool {
        self.tables.near.get(s).copied().unwrap_or(false)
    }

    /// The per-light constants of light `i` (empty unless it is a point light with shadows).
    #[inline]
    pub(super) fn light_consts(&self, i: usize, light: &Light) -> Option<&[f32]> {
        // Kept for the lights whose shadow rays share an origin.
        light
            .origin()
            .and(self.tables.lights.get(i))
            .map(|v| &v[..])
    }

    /// The pixel of [`Frame::shade_from`] of [`Frame::eye_hit`]`(ray, t, s)`, a span's stored
    /// primary hit, with the hit record and the primary hit's shading inlined into the pixel
    /// loop (where [`INLINE_SHADING`]): the record stays in registers instead of going through
    /// memory to the out-of-line `make_hit` and shading closure. The same functions
    /// (`make_hit_inline`, `shade_lit_inline`), so the same bits; a second inlined copy of
    /// their code, which the size builds have no flash for. M4F at opt 3: 398.0 instructions a
    /// pixel with it, 428.7 without (`examples/firmware/run.sh m4f`); CI renders the host's
    /// scenes through this path too (`MICRORAY_HOST_AS=m4f`).
    #[inline(always)]
    pub(super) fn shade_stored(
        &self,
        ray: &Ray,
        t: f32,
        s: usize,
        lists: Option<Lists<'_, L>>,
    ) -> Rgb888 {
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
        // Encoded on each path: a colour merged from the bounces' out-of-line return would go
        // through memory.
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
    pub(super) fn shade_from(
        &self,
        ray: &Ray,
        first: Option<Hit>,
        lists: Option<Lists<'_, L>>,
    ) -> Color {
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
    pub(super) fn candidates<'c>(&'c self, lists: Option<Lists<'c, L>>, i: usize) -> &'c [u16] {
        // A slice in both cases: one copy of the shadow tests, and a tight loop.
        lists.and_then(|l| l.light(i)).unwrap_or(&self.tables.all)
    }

    /// Whether light `i` is blocked at `hit` (`v` its `to_light` vector), testing the
    /// [`Frame::candidates`] of `lists`: the shadow test of both shading paths.
    #[inline(always)]
    pub(super) fn blocked(
        &self,
        hit: &Hit,
        lists: Option<Lists<'_, L>>,
        i: usize,
        light: &Light,
        v: Vec3,
    ) -> bool {
        // Span lists exist only with shadow rays (`Cull::culled`): with some, the scene's flag
        // is not read.
        if lists.is_none() && !self.scene.shadows() {
            return false;
        }
        // No candidate: only the hit's own sphere could block, and only when it is seen from
        // inside (see `in_shadow_among`). Most span lists are empty: decided from the list's
        // range, before a slice is built.
        if lists.is_some_and(|l| l.is_empty(i)) && !(hit.normal.dot(hit.offset) < 0.0) {
            return false;
        }
        // The slice's own test, which the range's has decided wherever a list exists; left in
        // for the register allocation of the Cortex-M shading loop.
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
    /// inlined into the shading loop its registers would make that loop keep more of its values
    /// on the stack. `v` as three floats, which go in registers: a `Vec3` goes by address, and
    /// the shading loop would store it for every lit light before asking whether the test is
    /// needed.
    #[cfg_attr(lanes, inline(always))]
    #[cfg_attr(not(lanes), inline(never))]
    pub(super) fn shadow_test(
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

    /// The colour of the kept primary hit `(t, sphere)` in `slot` of a supersampled span (see
    /// `KEPT`): the hit record rebuilt from them (`make_hit` is a pure function of them) along
    /// the kept view ray, or the rebuilt one where directions are not kept (the same bits).
    #[inline]
    pub(super) fn shade_kept(
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
}

/// Stores the encoded `colour` of the lanes `active` of the group at `k0` into `px`, marking
/// them done; nothing when the lanes could not shade them (`None`: the scalar path will).
#[cfg(lanes)]
#[inline(always)]
pub(super) fn keep4<const S: usize, const L: usize>(
    frame: &Frame<'_, S, L>,
    px: &mut [Rgb888; SPAN],
    done: &mut u32,
    k0: usize,
    active: u32,
    colour: Option<crate::simd::V>,
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

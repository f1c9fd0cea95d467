//! Shading a span's pixels from their stored hits, with the shadow tests over the span's
//! candidate lists (four pixels at a time on hosts: `lanes/shade.rs`).

use super::*;
use crate::shading::EverySphere;

/// The most spheres a secondary hit's shadow ray keeps from a light's sweep
/// (`Frame::swept_blockers`); with more, it walks the hierarchy.
const SHORT: usize = 16;

impl<'a, const S: usize, const L: usize> Frame<'a, S, L> {
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
    /// their code, which size builds leave out for flash unless feature `inline-shading` keeps
    /// it (its cost in instructions: `INLINE_SHADING`); CI renders the host's scenes through
    /// this path too (`MICRORAY_HOST_AS=m4f`).
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
        if !scene.has_secondary() {
            return self.encode(colour);
        }
        // A copy, as for `shadow_test`: only the bounces put the record in memory.
        self.encode(self.follow_secondary(ray, &{ h }, colour))
    }

    /// The shading of a secondary hit, whose shadow rays test the spheres the frame's
    /// hierarchy names ([`Bvh`]) where `CULL`, else every sphere: one closure for each, and so
    /// one copy of each out-of-line walk of secondary rays, which `shade_stored` and
    /// `shade_from` share.
    #[inline(always)]
    fn bounce<const CULL: bool>(&self) -> impl FnMut(&Hit, &Ray, bool) -> Color + '_ {
        let scene = self.scene;
        move |hit, ray, _| {
            if !CULL {
                return self.shade_hit(hit, ray.dir, None);
            }
            shade_lit(scene, hit, ray.dir, |i, light, v| {
                self.blocked_culled(hit, i, light, v)
            })
        }
    }

    /// The hierarchy that culls the frame's secondary rays, if it has one; a constant `None`
    /// at a capacity of 8 or less, which then links neither the hierarchy's walks nor their
    /// shading.
    #[inline(always)]
    pub(super) fn culled(&self) -> Option<&'a Bvh<S>> {
        if Self::SWEEPS {
            self.tables.bvh
        } else {
            None
        }
    }

    /// The shading of a hit that is not a span's stored one: `shade_from`'s primary hit (with
    /// its lists) and the secondary hits of the walk without a hierarchy (with none). Out of
    /// line: one copy for both beside `shade_stored`'s inlined one, where each caller inlined
    /// its own (M4F: 1 KiB of flash).
    #[inline(never)]
    fn shade_hit(&self, hit: &Hit, dir: Vec3, lists: Option<Lists<'_, L>>) -> Color {
        shade_lit(self.scene, hit, dir, |i, light, v| {
            self.blocked(hit, lists, i, light, v)
        })
    }

    /// Walks the secondary rays of the primary hit `h` along `ray`, whose local colour is
    /// `colour`: through the frame's hierarchy where it has one, else testing every sphere; the
    /// same hits either way.
    #[inline(always)]
    fn follow_secondary(&self, ray: &Ray, h: &Hit, colour: Color) -> Color {
        if let Some(bvh) = self.culled() {
            return self.follow_culled(bvh, ray, h, colour);
        }
        let local = self.bounce::<false>();
        crate::shading::follow_secondary(self.scene, ray, h, colour, local, EverySphere)
    }

    /// [`Frame::follow_secondary`] through the hierarchy. Out of line: the pixel loops inline
    /// the other walk's call, and a second beside it cost the mirror and glass scenes 3–6 %
    /// of their frame time (a larger loop, and the shadow test no longer inlined).
    #[inline(never)]
    pub(super) fn follow_culled(
        &self,
        bvh: &'a Bvh<S>,
        ray: &Ray,
        h: &Hit,
        colour: Color,
    ) -> Color {
        let (local, find) = (self.bounce::<true>(), Culled(bvh));
        crate::shading::follow_secondary(self.scene, ray, h, colour, local, find)
    }

    /// Whether light `i` is blocked at a secondary hit, among the spheres the light's sweep
    /// names (`swept_blockers`), or where they are many, the hierarchy.
    #[inline(never)]
    fn blocked_culled(&self, hit: &Hit, i: usize, light: &Light, v: Vec3) -> bool {
        if !self.scene.shadows() {
            return false;
        }
        let cs = self.light_consts(i, light);
        let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
        if let Some(list) = self.swept_blockers(hit, i, light) {
            let cands = list.iter().map(|s| s.index());
            return in_shadow_among(self.scene, hit, light, v, consts, cands);
        }
        match self.culled() {
            Some(bvh) => {
                let cands = bvh.shadow_candidates(hit, light, v);
                in_shadow_among(self.scene, hit, light, v, consts, cands)
            }
            // Never: only a frame with a hierarchy walks its secondary rays here.
            None => {
                let every = 0..self.scene.spheres().len();
                in_shadow_among(self.scene, hit, light, v, consts, every)
            }
        }
    }

    /// The spheres that can block light `i` at the secondary hit `hit`, as light `i`'s sweep
    /// names them for a ball about the hit point (the span's search, `Frame::gather`, for one
    /// point); `None` where the light has no sweep or it names more than `SHORT`. The ball's
    /// radius, 10⁻⁵ of the point's largest coordinate, covers far more than the rounding of
    /// `anchor + rel`, whose exact sum the shadow rays leave from. Unlike a span's list, which
    /// many rays share, this one is not filtered by [`LightKind::may_block`]: for one ray the
    /// filter costs more than the shadow test's own early outs for the spheres it drops.
    #[inline(always)]
    fn swept_blockers(&self, hit: &Hit, i: usize, light: &Light) -> Option<List<SHORT>> {
        if !Self::SWEEPS {
            return None;
        }
        let q = hit.point();
        let rho = 1e-5 * q.max_abs() + f32::MIN_POSITIVE;
        if !(rho.is_finite() && q.is_finite()) {
            return None;
        }
        let (sweep, band) = self.tables.sweeps.get(i)?.band(light, q, rho)?;
        let (mut list, mut full) = (List::<SHORT>::new(), false);
        let mut consider = |s: SphereId| full |= list.push(s).is_err();
        sweep.each::<false>(band, &mut consider);
        (!full).then_some(list)
    }

    /// Shades a primary hit (and its secondary rays): `lists`, when given, holds per light
    /// the spheres that can block shadow rays from this primary hit; secondary hits and missing
    /// `lists` test every sphere, or those the frame's hierarchy names.
    ///
    /// Out of line in Cortex-M speed builds, where [`INLINE_SHADING`]: the pixel loop shades
    /// its stored hits itself and calls this for the few others; inlined there it would only
    /// lengthen that loop. Size builds leave the choice to the compiler, with feature
    /// `inline-shading` too (68 bytes less and 1.5 instructions a pixel fewer on the M4F).
    #[cfg_attr(any(lanes, size_opt), inline)]
    #[cfg_attr(not(any(lanes, size_opt)), inline(never))]
    pub(super) fn shade_from(
        &self,
        ray: &Ray,
        first: Option<Hit>,
        lists: Option<Lists<'_, L>>,
    ) -> Color {
        let scene = self.scene;
        if INLINE_SHADING {
            // `shade_stored` walks secondary rays with `bounce` too: one walk for both.
            let Some(h) = first else {
                return scene.background();
            };
            let colour = self.shade_hit(&h, ray.dir, lists);
            return self.follow_secondary(ray, &h, colour);
        }
        // Without a hierarchy, primary and secondary hits share one out-of-line copy of the
        // shading: the walk's only caller.
        let local = |hit: &Hit, ray: &Ray, primary: bool| {
            let lists = if primary { lists } else { None };
            shade_lit(scene, hit, ray.dir, |i, light, v| {
                self.blocked(hit, lists, i, light, v)
            })
        };
        // `follow`, with the walk through the hierarchy where the frame has one.
        let Some(h) = first else {
            return scene.background();
        };
        let colour = local(&h, ray, true);
        if let Some(bvh) = self.culled() {
            return self.follow_culled(bvh, ray, &h, colour);
        }
        // Hosts: the walk the lanes' mirrors share (`follow4`). Cortex-M size builds keep the
        // one copy of the shading that the walk and the primary hit share here.
        #[cfg(lanes)]
        return self.follow_every(ray, &h, colour);
        #[cfg(not(lanes))]
        crate::shading::follow_secondary(scene, ray, &h, colour, local, EverySphere)
    }

    /// The walk of secondary rays testing every sphere, from the primary hit `h` of local
    /// colour `colour`, for `shade_from` and the lanes' mirrors (`follow4`). Out of line: one
    /// copy of the walk for both, each inlining its own had the glass scenes take 13–20 %
    /// longer (LLVM then kept the walk's steps out of line).
    #[cfg(lanes)]
    #[inline(never)]
    pub(super) fn follow_every(&self, ray: &Ray, h: &Hit, colour: Color) -> Color {
        let local = self.lit_every();
        crate::shading::follow_secondary(self.scene, ray, h, colour, local, EverySphere)
    }

    /// [`Frame::follow_every`] on from `h`, the hit of a mirror ray `ray` of depth `depth`
    /// and weight `weight` (the lanes' `mirror4` found and shaded it; `colour` includes it):
    /// the same walk, one copy.
    #[cfg(lanes)]
    #[inline(never)]
    pub(super) fn follow_on(
        &self,
        ray: &Ray,
        h: &Hit,
        colour: Color,
        (weight, depth): (Color, u8),
    ) -> Color {
        let local = self.lit_every();
        crate::shading::walk_on(
            self.scene,
            (ray, h),
            (colour, weight, depth),
            local,
            EverySphere,
        )
    }

    /// The shading of a secondary hit whose shadow rays test every sphere.
    #[cfg(lanes)]
    #[inline(always)]
    fn lit_every(&self) -> impl FnMut(&Hit, &Ray, bool) -> Color + '_ {
        |hit: &Hit, ray: &Ray, _primary: bool| {
            shade_lit(self.scene, hit, ray.dir, |i, light, v| {
                self.blocked(hit, None, i, light, v)
            })
        }
    }

    /// [`Frame::shade_from`] with every secondary ray, and the shadow rays of every hit,
    /// tested against every sphere: the brute-force reference where the frame has a hierarchy
    /// (without one, `shade_from` is that already). Its shadow test goes over a range, not the
    /// frame's list of every sphere: the same tests, in a copy of their own, which leaves the
    /// pixel loops' copy as it was.
    #[inline(never)]
    pub(super) fn shade_brute(&self, ray: &Ray, first: Option<Hit>) -> Color {
        let scene = self.scene;
        let local = |hit: &Hit, ray: &Ray, _| {
            shade_lit(scene, hit, ray.dir, |i, light, v| {
                if !scene.shadows() {
                    return false;
                }
                let cs = self.light_consts(i, light);
                let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
                in_shadow_among(scene, hit, light, v, consts, 0..scene.spheres().len())
            })
        };
        follow(scene, ray, first, local, EverySphere)
    }

    /// The spheres that can block light `i` for a hit with the span lists `lists` (a primary
    /// hit's), or every sphere.
    #[inline(always)]
    pub(super) fn candidates<'c>(
        &'c self,
        lists: Option<Lists<'c, L>>,
        i: usize,
    ) -> &'c [SphereId] {
        // A slice in both cases: one copy of the shadow tests, and a tight loop.
        lists.and_then(|l| l.light(i)).unwrap_or(self.tables.all)
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
        if lists.is_some_and(|l| l.is_empty(i)) && !hit.from_inside() {
            return false;
        }
        // The slice's own test, which the range's has decided wherever a list exists; left in
        // for the register allocation of the Cortex-M shading loop.
        let cands = self.candidates(lists, i);
        if cands.is_empty() && !hit.from_inside() {
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
        cands: &[SphereId],
        i: usize,
        light: &Light,
        (vx, vy, vz): (f32, f32, f32),
    ) -> bool {
        let v = Vec3::new(vx, vy, vz);
        let cs = self.light_consts(i, light);
        let consts = |j: usize| cs.and_then(|c| c.get(j)).copied();
        let cands = cands.iter().map(|&j| j.index());
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
        (t, s): (f32, SphereId),
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
            self.kept_hit(&ray, t, s.index(), slot, cull)
        } else {
            self.eye_hit(&ray, t, s.index())
        };
        self.shade_from(&ray, first, cull.lists_at(slot))
    }
}

/// Secondary rays through the frame's hierarchy ([`Bvh::find_from`]).
#[derive(Clone, Copy)]
struct Culled<'a, const S: usize>(&'a Bvh<S>);

impl<const S: usize, const L: usize> crate::shading::FindFrom<S, L> for Culled<'_, S> {
    #[inline(always)]
    fn find(self, scene: &Scene<S, L>, ray: &Ray, from: &Hit) -> Option<Hit> {
        self.0.find_from(scene, ray, from)
    }
}

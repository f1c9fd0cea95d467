//! The build-time constants of the render path, in one place: what a span keeps per pixel
//! depends on whether the target has vector lanes (`cfg(lanes)`) and room for view directions
//! (`cfg(no_dirs)`), and size builds (`cfg(size_opt)`) leave out code for flash; build.rs sets
//! all three (ARCHITECTURE.md has the table of variants). Which render path runs is chosen in
//! `render/mod.rs` (`lanes/` or `scalar.rs`).

use super::*;

/// Span pixels whose view ray direction is kept for shading: all, which spares building it again
/// per hit, except on soft-float Arm (Cortex-M0), whose deeper render stack has no room for the
/// 12 bytes a pixel (it rebuilds the ray instead: since the directions stay unnormalised, a
/// few soft-float products and sums, no square root or divide).
pub(super) const DIRS: usize = if cfg!(no_dirs) { 0 } else { SPAN * KEPT };
/// Primary hits a span keeps per column for shading: the samples of a supersampled pixel, so
/// that it is not traced twice (once for the span's bounds, once to shade; up to 2×2), or with
/// one sample the rows of a tile (`Frame::tile_rows`). One on Arm, whose render stack (2 KiB
/// on the firmware) has no room for 54 more bytes a pixel; one wherever there are no lanes, so
/// that a host built without them (`MICRORAY_HOST_AS`, see build.rs) takes Cortex-M's path.
pub(super) const KEPT: usize = if cfg!(lanes) { 8 } else { 1 };
/// `DIRS` and the lanes read past the last slot (`Cull::hit_dc`).
#[cfg(lanes)]
pub(super) const DPAD: usize = DIRS + crate::geometry::LANES - 1;
/// Whether a span traces its primary rays sphere by sphere (`Frame::trace_span`), which needs
/// room for every pixel's view direction; on soft-float Arm, with none, pixel by pixel.
pub(super) const SPHERE_MAJOR: bool = DIRS == SPAN * KEPT;
/// Kept hits whose offset from the centre the span keeps from its bounds for shading, which
/// spares `make_hit` computing it again: all on hosts with f32 vectors (`cfg(lanes)`), none on
/// Cortex-M, whose render stack has no room for 12 more bytes a pixel.
pub(super) const OFFS: usize = if KEEPS_OFFSETS { SPAN * KEPT } else { 0 };
/// Whether spans keep hit offsets (`OFFS` not zero), a flag so that Cortex-M builds, where
/// `OFFS` is 0, test no comparison that is always false (clippy's `absurd_extreme_comparisons`).
pub(super) const KEEPS_OFFSETS: bool = cfg!(lanes);
/// Whether the scalar render path shades each stored primary hit inline in the pixel loop
/// (`Frame::shade_stored`): the speed builds of Cortex-M, and size builds (`cfg(size_opt)`)
/// with feature `inline-shading`; other size builds leave the second copy out for flash. Not
/// on hosts, whose lanes shade spans. With it the M4F's size build takes 477.1 instructions a
/// pixel instead of 529.5, in 1 932 more bytes (docs/firmware.md has every build).
pub(super) const INLINE_SHADING: bool =
    !cfg!(lanes) && (!cfg!(size_opt) || cfg!(feature = "inline-shading"));
/// Whether scalar primary rays take the shorter test for an eye outside the sphere
/// ([`Prepared::hit_outside`], the same answers as [`Prepared::hit`]): all but size builds
/// (`cfg(size_opt)`) without feature `outside-test`, which leave the second test out for
/// flash. With it the M4F's size build takes 496.8 instructions a pixel instead of 529.5, in
/// 572 more bytes; the M0, which traces a span pixel by pixel, never takes it.
#[cfg(not(lanes))]
pub(super) const OUTSIDE_TEST: bool = !cfg!(size_opt) || cfg!(feature = "outside-test");
// `Cull::done` has a bit per span pixel.
const _: () = assert!(SPAN <= 32);

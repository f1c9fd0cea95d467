//! Camera animation, for firmware as for the desktop: a [`View`] (a camera without its image
//! size) turned about the point it looks at ([`View::orbit`], [`Orbit`]), or interpolated
//! between [`Keyframes`]. Everything is `no_std`, heap-free and computed in f32 with `libm`,
//! so every target gets the same views, and so the same pixels.
//!
//! ```
//! use microray::animation::{Orbit, View};
//! use microray::Vec3;
//!
//! let view = View { eye: Vec3::new(0.0, 1.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
//! let orbit = Orbit { view, degrees: 360.0 };
//! // Frame 9 of 36 is a quarter turn: the eye on the +x side, at the same height and distance.
//! let eye = orbit.view(9, 36).eye;
//! assert!((eye.x - 5.0).abs() < 1e-5 && (eye.y - 1.0).abs() < 1e-6 && eye.z.abs() < 1e-5);
//! let camera = orbit.view(9, 36).camera(320, 240)?;
//! # let _ = camera;
//! # Ok::<(), microray::Error>(())
//! ```

use crate::camera::Camera;
use crate::error::Error;
use crate::math::{finite, Vec3};

/// Where a camera is and where it looks, without an image size: what an animation moves.
///
/// ```
/// use microray::{animation::View, Vec3};
/// let view = View { eye: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
/// assert_eq!(view.camera(64, 48)?.width(), 64);
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct View {
    /// The eye point.
    pub eye: Vec3,
    /// The point looked at.
    pub look_at: Vec3,
    /// The up direction.
    pub up: Vec3,
    /// Full vertical field of view in degrees.
    pub vfov: f32,
}

impl View {
    /// The camera for a `width` × `height` image ([`Camera::new`], and its errors).
    ///
    /// ```
    /// # use microray::{animation::View, Error, Vec3};
    /// let view = View { eye: Vec3::ZERO, look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
    /// assert_eq!(view.camera(8, 8).err(), Some(Error::EyeAtLookAt));
    /// ```
    pub fn camera(&self, width: u32, height: u32) -> Result<Camera, Error> {
        Camera::new(self.eye, self.look_at, self.up, self.vfov, width, height)
    }

    /// The view with the eye turned by `degrees` about the axis through `look_at` along `up`
    /// (counter-clockwise seen from above); `look_at`, `up` and `vfov` stay. A zero or
    /// non-finite `up` or angle leaves the view as it is.
    ///
    /// ```
    /// # use microray::{animation::View, Vec3};
    /// let view = View { eye: Vec3::new(0.0, 2.0, 4.0), look_at: Vec3::new(0.0, 2.0, 0.0), up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
    /// let eye = view.orbit(180.0).eye;
    /// assert!(eye.x.abs() < 1e-5 && eye.y == 2.0 && (eye.z + 4.0).abs() < 1e-5);
    /// assert_eq!(view.orbit(0.0), view);
    /// ```
    pub fn orbit(&self, degrees: f32) -> View {
        View {
            eye: self.look_at + rotate(self.eye - self.look_at, self.up, degrees),
            ..*self
        }
    }

    /// The view with the eye raised by `degrees` (lowered if negative) about the camera's
    /// right axis through `look_at`; `up` stays. So a tilt to straight above or below makes a
    /// view whose [`View::camera`] fails (`UpParallelToView`), and one past it a view from the
    /// other side, upside down: a caller that steers by tilts should stop short of the pole.
    ///
    /// ```
    /// # use microray::{animation::View, Vec3};
    /// let view = View { eye: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
    /// let eye = view.tilt(90.0).eye;
    /// assert!((eye.y - 5.0).abs() < 1e-5 && eye.z.abs() < 1e-5);
    /// assert!(view.tilt(90.0).camera(8, 8).is_err()); // looking straight down along `up`
    /// ```
    pub fn tilt(&self, degrees: f32) -> View {
        let back = self.eye - self.look_at;
        // Right-handed: turning `back` about `back × up` by a positive angle lifts it.
        let axis = back.cross(self.up);
        View {
            eye: self.look_at + rotate(back, axis, degrees),
            ..*self
        }
    }

    /// The view `s` of the way from `self` to `to` (0 gives `self`, 1 gives `to`): each of eye,
    /// look-at point, up and field of view as `a + (b − a)·s`.
    ///
    /// ```
    /// # use microray::{animation::View, Vec3};
    /// let a = View { eye: Vec3::new(0.0, 0.0, 4.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 40.0 };
    /// let b = View { eye: Vec3::new(0.0, 0.0, 8.0), vfov: 60.0, ..a };
    /// assert_eq!(a.lerp(&b, 0.5).eye, Vec3::new(0.0, 0.0, 6.0));
    /// assert_eq!(a.lerp(&b, 0.5).vfov, 50.0);
    /// assert_eq!(a.lerp(&b, 1.0), b);
    /// ```
    pub fn lerp(&self, to: &View, s: f32) -> View {
        let mix = |a: f32, b: f32| if s == 1.0 { b } else { a + (b - a) * s };
        let mix3 = |a: Vec3, b: Vec3| Vec3::new(mix(a.x, b.x), mix(a.y, b.y), mix(a.z, b.z));
        View {
            eye: mix3(self.eye, to.eye),
            look_at: mix3(self.look_at, to.look_at),
            up: mix3(self.up, to.up),
            vfov: mix(self.vfov, to.vfov),
        }
    }
}

/// `v` turned by `degrees` about `axis` (Rodrigues' formula: `v cos θ + (k × v) sin θ +
/// k (k·v)(1 − cos θ)` with `k` the unit axis). `v` unchanged for a zero or non-finite axis
/// or angle, and exactly unchanged for 0°.
fn rotate(v: Vec3, axis: Vec3, degrees: f32) -> Vec3 {
    let Some(k) = axis.normalized() else {
        return v;
    };
    if !finite(degrees) || degrees == 0.0 {
        return v;
    }
    let theta = degrees * (core::f32::consts::PI / 180.0);
    let (s, c) = (libm::sinf(theta), libm::cosf(theta));
    v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c))
}

/// A turn about the look-at point spread over the frames of a loop: frame `k` of `n` is the
/// view turned by `degrees · k / n`, so that a full turn's frame `n` would be frame 0 again.
///
/// ```
/// use microray::{animation::{Orbit, View}, Vec3};
/// let view = View { eye: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
/// let orbit = Orbit { view, degrees: 90.0 };
/// assert_eq!(orbit.view(0, 10), view);
/// assert_eq!(orbit.view(5, 10), view.orbit(45.0));
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Orbit {
    /// The view of frame 0.
    pub view: View,
    /// The turn over the whole loop, in degrees.
    pub degrees: f32,
}

impl Orbit {
    /// The view of frame `k` of `n` (`n` = 0 counts as 1).
    pub fn view(&self, k: u32, n: u32) -> View {
        self.view.orbit(self.degrees * k as f32 / n.max(1) as f32)
    }
}

/// A view at a time `at` in [0, 1] of an animation.
///
/// ```
/// use microray::{animation::{Keyframe, View}, Vec3};
/// let view = View { eye: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
/// let key = Keyframe { at: 0.5, view };
/// # let _ = key;
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Keyframe {
    /// When, from 0 (the first frame) to 1 (the last).
    pub at: f32,
    /// The view then.
    pub view: View,
}

/// Up to `N` keyframes, their times increasing from 0 to 1, and the views between them
/// interpolated linearly ([`View::lerp`]). Frame `k` of `n` stands at time `k / (n − 1)`: the
/// first frame shows the first key, the last frame the last one.
///
/// ```
/// use microray::{animation::{Keyframe, Keyframes, View}, Error, Vec3};
/// let a = View { eye: Vec3::new(0.0, 0.0, 4.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
/// let b = View { eye: Vec3::new(4.0, 0.0, 0.0), ..a };
/// let mut keys: Keyframes<4> = Keyframes::new();
/// keys.push(Keyframe { at: 0.0, view: a })?;
/// assert_eq!(keys.view(0, 2), Err(Error::TooFewKeyframes)); // one key is no animation
/// keys.push(Keyframe { at: 1.0, view: b })?;
/// assert_eq!(keys.view(2, 5)?.eye, Vec3::new(2.0, 0.0, 2.0)); // halfway
/// assert_eq!(keys.view(4, 5)?, b);
/// assert_eq!(keys.push(Keyframe { at: 0.5, view: a }), Err(Error::InvalidKeyframe)); // not after 1.0
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Keyframes<const N: usize> {
    keys: heapless::Vec<Keyframe, N>,
}

impl<const N: usize> Default for Keyframes<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Keyframes<N> {
    /// No keyframes.
    pub const fn new() -> Self {
        Keyframes {
            keys: heapless::Vec::new(),
        }
    }

    /// Adds a keyframe after the others. `InvalidKeyframe` for a time that is not in [0, 1],
    /// not after the last key's, or a first key not at 0; `NotFinite` for a view with a NaN or
    /// infinite component (`InvalidFov` for its field of view); `TooManyKeyframes` past `N`.
    /// A rejected key leaves the keyframes as they were.
    ///
    /// ```
    /// # use microray::{animation::{Keyframe, Keyframes, View}, Error, Vec3};
    /// # let view = View { eye: Vec3::new(0.0, 0.0, 5.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 45.0 };
    /// let mut keys: Keyframes<2> = Keyframes::new();
    /// assert_eq!(keys.push(Keyframe { at: 0.3, view }), Err(Error::InvalidKeyframe)); // must start at 0
    /// assert_eq!(keys.push(Keyframe { at: f32::NAN, view }), Err(Error::InvalidKeyframe));
    /// let nan = View { eye: Vec3::new(f32::NAN, 0.0, 0.0), ..view };
    /// assert_eq!(keys.push(Keyframe { at: 0.0, view: nan }), Err(Error::NotFinite));
    /// ```
    pub fn push(&mut self, key: Keyframe) -> Result<(), Error> {
        let after = match self.keys.last() {
            Some(last) => key.at > last.at,
            None => key.at == 0.0,
        };
        if !(after && key.at <= 1.0) {
            return Err(Error::InvalidKeyframe);
        }
        let v = key.view;
        if !(v.eye.is_finite() && v.look_at.is_finite() && v.up.is_finite()) {
            return Err(Error::NotFinite);
        }
        if !(v.vfov > 0.0 && v.vfov < 180.0) {
            return Err(Error::InvalidFov);
        }
        self.keys.push(key).map_err(|_| Error::TooManyKeyframes)
    }

    /// The keyframes, in order.
    ///
    /// ```
    /// # use microray::animation::Keyframes;
    /// assert!(Keyframes::<3>::new().keys().is_empty());
    /// ```
    pub fn keys(&self) -> &[Keyframe] {
        &self.keys
    }

    /// The view at time `t` in [0, 1] (clamped): the keys' views interpolated linearly, the
    /// last key's from its time on. `TooFewKeyframes` with fewer than two keys; a key after 0
    /// is reached only if the last key is at 1, which [`Keyframes::push`] does not require.
    ///
    /// ```
    /// # use microray::{animation::{Keyframe, Keyframes, View}, Vec3};
    /// # let a = View { eye: Vec3::new(0.0, 0.0, 4.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 40.0 };
    /// let b = View { vfov: 60.0, ..a };
    /// let mut keys: Keyframes<2> = Keyframes::new();
    /// keys.push(Keyframe { at: 0.0, view: a })?;
    /// keys.push(Keyframe { at: 0.5, view: b })?;
    /// assert_eq!(keys.at(0.25)?.vfov, 50.0);
    /// assert_eq!(keys.at(0.9)?, b); // after the last key
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn at(&self, t: f32) -> Result<View, Error> {
        let (Some(first), Some(last)) = (self.keys.first(), self.keys.last()) else {
            return Err(Error::TooFewKeyframes);
        };
        if self.keys.len() < 2 {
            return Err(Error::TooFewKeyframes);
        }
        // NaN goes to the start.
        let t = if t > 0.0 { t.min(1.0) } else { 0.0 };
        if t >= last.at {
            return Ok(last.view);
        }
        let mut prev = first;
        for key in self.keys.iter().skip(1) {
            if t < key.at {
                // key.at > prev.at (push checks), so no division by zero.
                let s = (t - prev.at) / (key.at - prev.at);
                return Ok(prev.view.lerp(&key.view, s));
            }
            prev = key;
        }
        Ok(last.view)
    }

    /// The view of frame `k` of `n`: time `k / (n − 1)`, a single frame at time 0.
    ///
    /// ```
    /// # use microray::{animation::{Keyframe, Keyframes, View}, Vec3};
    /// # let a = View { eye: Vec3::new(0.0, 0.0, 4.0), look_at: Vec3::ZERO, up: Vec3::new(0.0, 1.0, 0.0), vfov: 40.0 };
    /// # let b = View { vfov: 60.0, ..a };
    /// # let mut keys: Keyframes<2> = Keyframes::new();
    /// # keys.push(Keyframe { at: 0.0, view: a })?;
    /// # keys.push(Keyframe { at: 1.0, view: b })?;
    /// assert_eq!(keys.view(0, 1)?, a);
    /// assert_eq!(keys.view(3, 4)?, b);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn view(&self, k: u32, n: u32) -> Result<View, Error> {
        let t = if n > 1 {
            k as f32 / (n - 1) as f32
        } else {
            0.0
        };
        self.at(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> View {
        View {
            eye: Vec3::new(1.0, 2.0, 5.0),
            look_at: Vec3::new(0.5, 1.0, -1.0),
            up: Vec3::new(0.0, 1.0, 0.0),
            vfov: 45.0,
        }
    }

    #[test]
    fn an_orbit_keeps_the_distance_and_the_height() {
        let v = view();
        let d0 = (v.eye - v.look_at).length();
        for k in 0..36 {
            let w = v.orbit(10.0 * k as f32);
            assert!(((w.eye - w.look_at).length() - d0).abs() < 1e-5 * d0);
            assert!(
                (w.eye.y - v.eye.y).abs() < 1e-5,
                "turning about up keeps the height"
            );
            assert_eq!((w.look_at, w.up, w.vfov), (v.look_at, v.up, v.vfov));
        }
        // Counter-clockwise seen from above: +z turns towards +x.
        let w = View {
            eye: Vec3::new(0.0, 0.0, 1.0),
            look_at: Vec3::ZERO,
            ..v
        }
        .orbit(90.0);
        assert!(
            (w.eye.x - 1.0).abs() < 1e-6 && w.eye.z.abs() < 1e-6,
            "{:?}",
            w.eye
        );
    }

    #[test]
    fn degenerate_turns_change_nothing() {
        let v = view();
        assert_eq!(v.orbit(f32::NAN), v);
        assert_eq!(
            View {
                up: Vec3::ZERO,
                ..v
            }
            .orbit(30.0)
            .eye,
            v.eye
        );
        assert_eq!(
            View {
                eye: v.look_at,
                ..v
            }
            .tilt(30.0)
            .eye,
            v.look_at
        );
    }

    #[test]
    fn keyframes_pass_through_their_views() {
        let a = view();
        let b = View {
            eye: Vec3::new(-3.0, 4.0, 2.0),
            vfov: 70.0,
            ..a
        };
        let c = View {
            look_at: Vec3::ZERO,
            ..b
        };
        let mut keys: Keyframes<3> = Keyframes::new();
        for (at, v) in [(0.0, a), (0.25, b), (1.0, c)] {
            keys.push(Keyframe { at, view: v }).unwrap();
        }
        assert_eq!(keys.at(0.0), Ok(a));
        assert_eq!(keys.at(0.25), Ok(b));
        assert_eq!(keys.at(1.0), Ok(c));
        assert_eq!(keys.at(-1.0), Ok(a));
        assert_eq!(keys.at(f32::NAN), Ok(a));
        // Between b and c: halfway in time is halfway along.
        let mid = keys.at(0.625).unwrap();
        assert_eq!(mid.look_at, b.look_at * 0.5);
        assert_eq!(
            keys.push(Keyframe { at: 1.0, view: a }),
            Err(Error::InvalidKeyframe)
        );
        let mut full: Keyframes<1> = Keyframes::new();
        full.push(Keyframe { at: 0.0, view: a }).unwrap();
        // Capacity is checked after the key itself.
        assert_eq!(
            full.push(Keyframe { at: 0.5, view: a }),
            Err(Error::TooManyKeyframes)
        );
    }
}

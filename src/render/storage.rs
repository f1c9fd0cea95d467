//! The per-frame tables, in storage the caller provides: what every ray of a frame reads, sized
//! by the scene's capacity, so that a frame itself stays small and is never moved with them.

use super::*;

/// The tables a [`Frame`] computes once and its rays share: per sphere the eye's constants
/// ([`Prepared::exact`]), its screen box and whether its hit offsets are rebuilt exactly; per
/// light with shadows the light's `c` of every sphere and (above 8 spheres) the sorted sweep of
/// its shadow candidates; and (above 16 spheres, for scenes with mirrors or glass) the
/// hierarchy that culls secondary rays.
///
/// Its size grows with the capacity `S × L` of the scene (about 0.78 MB at `Scene<1024, 32>`, a
/// few hundred bytes at `Scene<8, 2>`), so the caller chooses where it lives: on the heap on a
/// desktop (`Box::new(FrameStorage::new())`), in a `static` or on the stack of a
/// microcontroller. A [`Frame`] borrows it for its lifetime; building another frame in the same
/// storage overwrites it, so one storage serves every frame of an animation.
///
/// ```
/// use embedded_graphics::pixelcolor::Rgb888;
/// use microray::{Camera, Frame, FrameStorage, RenderOptions, Scene, Vec3};
///
/// let scene: Scene<1024, 32> = Scene::new();
/// let camera = Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 45.0, 8, 8)?;
/// let mut storage = Box::new(FrameStorage::new()); // large: on the heap
/// let frame = Frame::new(&scene, &camera, RenderOptions::default(), &mut storage)?;
/// let mut row = [Rgb888::new(0, 0, 0); 8];
/// frame.render_rows(0, &mut row)?;
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug)]
pub struct FrameStorage<const S: usize, const L: usize> {
    pub(super) eye: heapless::Vec<Prepared, S>,
    pub(super) boxes: heapless::Vec<PixelBox, S>,
    /// Per light, in scene order: for a point light with shadows, `c` of [`Prepared::exact`]
    /// from the light for every sphere (the rest of those constants is rebuilt exactly when
    /// needed); empty for the others.
    pub(super) lights: [heapless::Vec<f32, S>; L],
    /// Per light, in scene order, when shadows are on and `SWEEPS`: its spheres sorted for
    /// the span culling.
    pub(super) sweeps: heapless::Vec<Sweep<S>, L>,
    /// Every sphere's index: the candidate list of a shadow ray that must test them all, so
    /// that every shadow ray walks a plain slice.
    pub(super) all: List<S>,
    /// Per sphere, [`Frame::offset_near`]'s answer, decided once.
    pub(super) near: heapless::Vec<bool, S>,
    /// The hierarchy that culls secondary rays, where the scene has them and `SWEEPS`.
    pub(super) bvh: Bvh<S>,
}

impl<const S: usize, const L: usize> FrameStorage<S, L> {
    /// Empty storage; [`Frame::new`] fills it. A `const fn`, so it can initialise a `static`,
    /// and it writes nothing but lengths, so a large one costs nothing until it is filled.
    ///
    /// ```
    /// use microray::FrameStorage;
    /// let storage: FrameStorage<8, 2> = FrameStorage::new();
    /// # let _ = storage;
    /// ```
    pub const fn new() -> Self {
        // A copy of a constant, not a struct built from field temporaries: an unoptimised
        // build would put those on the stack beside the result (~2.3 MB at `<1024, 32>`,
        // more than a thread's default stack, in `Box::new(FrameStorage::new())`).
        Self::EMPTY
    }

    const EMPTY: Self = FrameStorage {
        eye: heapless::Vec::new(),
        boxes: heapless::Vec::new(),
        lights: [const { heapless::Vec::new() }; L],
        sweeps: heapless::Vec::new(),
        all: heapless::Vec::new(),
        near: heapless::Vec::new(),
        bvh: Bvh::EMPTY,
    };

    /// Fills the tables for `scene` seen by `camera`, in place: nothing of capacity size is
    /// built elsewhere and moved in.
    pub(super) fn fill(&mut self, scene: &Scene<S, L>, camera: &Camera, sweeps: bool) {
        self.eye.clear();
        self.boxes.clear();
        self.sweeps.clear();
        self.all.clear();
        self.near.clear();
        // Capacity S, at most S spheres (below `SphereId::REST`, `Frame::FITS`), and at most L
        // lights (the scene's capacity): none of the pushes can fail.
        let screen = Screen::new(camera);
        for (s, sphere) in scene.spheres().iter().enumerate() {
            let k = Prepared::exact(camera.eye(), sphere);
            let _ = self.boxes.push(screen.sphere_box(&k));
            let _ = self
                .near
                .push(crate::geometry::offset_is_near(k.f, k.r, scene.near2(s)));
            let _ = self.all.push(SphereId::new(s));
            let _ = self.eye.push(k);
        }
        // A constant test: a capacity of 8 or less links none of the hierarchy, whose storage
        // then stays empty.
        if Frame::<'_, S, L>::SWEEPS {
            let secondary = scene.has_secondary().then_some(scene.spheres());
            self.bvh.fill(secondary.unwrap_or(&[]));
        }
        let axes = camera.basis();
        for consts in &mut self.lights {
            consts.clear();
        }
        for (light, consts) in scene.lights().iter().zip(&mut self.lights) {
            if let (Some(origin), true) = (light.origin(), scene.shadows()) {
                for s in scene.spheres() {
                    let _ = consts.push(Prepared::exact(origin, s).c);
                }
            }
            if scene.shadows() && sweeps {
                let _ = self.sweeps.push(Sweep::empty());
                if let Some(sweep) = self.sweeps.last_mut() {
                    sweep.fill(light, scene.spheres(), axes.0, axes.1);
                }
            }
        }
    }
}

impl<const S: usize, const L: usize> Default for FrameStorage<S, L> {
    fn default() -> Self {
        Self::new()
    }
}

//! The per-frame tables, in storage the caller provides: what every ray of a frame reads, sized
//! by the scene's capacity, so that a frame itself stays small and is never moved with them.

use super::*;

/// The tables a [`Frame`] computes once and its rays share: per sphere the eye's constants
/// ([`Prepared::exact`]), its screen box and whether its hit offsets are rebuilt exactly; per
/// light with shadows the light's `c` of every sphere and (above 8 spheres) the sorted sweep of
/// its shadow candidates; and (above 48 spheres, for scenes with mirrors or glass) the
/// hierarchy that culls secondary rays.
///
/// Its size grows with the capacity `S × L` of the scene (about 0.97 MB at `Scene<1024, 32>`,
/// 15.4 MB at `Scene<16384, 32>`, a few hundred bytes at `Scene<8, 2>`), so the caller chooses
/// where it lives: on the heap on a desktop ([`FrameStorage::on_heap`], each table boxed on
/// its own; `Box::new(FrameStorage::new())` only where an unoptimised build may hold the
/// whole storage on the stack first), in a `static` or on the stack of a microcontroller
/// ([`FrameStorage::new`], the [`Inline`] layout; at a capacity of 8 spheres or less
/// [`FrameStorage::small`], the [`Small`] layout, without the tables only larger capacities
/// use). A [`Frame`] borrows it for its lifetime;
/// building another frame in the same storage overwrites it, so one storage serves every frame
/// of an animation.
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
pub struct FrameStorage<const S: usize, const L: usize, P: Place = Inline> {
    pub(super) eye: P::Slot<heapless::Vec<Prepared, S>>,
    pub(super) boxes: P::Slot<heapless::Vec<PixelBox, S>>,
    /// Per light, in scene order: for a point light with shadows, `c` of [`Prepared::exact`]
    /// from the light for every sphere (the rest of those constants is rebuilt exactly when
    /// needed); empty for the others.
    pub(super) lights: P::Slot<[heapless::Vec<f32, S>; L]>,
    /// Per light, in scene order, when shadows are on and `SWEEPS`: its spheres sorted for
    /// the span culling, in the first `swept` slots (kept, and cleared in place, from frame to
    /// frame: no sweep is built elsewhere and moved in).
    pub(super) sweeps: P::Culling<[Sweep<S>; L]>,
    pub(super) swept: usize,
    /// Where a sweep is sorted before it is split into its fields (`Sweep::fill`): one for
    /// all the lights, so that no capacity-sized list is built on the stack.
    pub(super) entries: P::Culling<heapless::Vec<Entry, S>>,
    /// The room of a sweep's radix sort (hosts): as many entries again.
    #[cfg(lanes)]
    pub(super) sort_room: P::Culling<SortRoom<S>>,
    /// Every sphere's index: the candidate list of a shadow ray that must test them all, so
    /// that every shadow ray walks a plain slice.
    pub(super) all: P::Slot<List<S>>,
    /// Per sphere, [`Frame::offset_near`]'s answer, decided once.
    pub(super) near: P::Slot<heapless::Vec<bool, S>>,
    /// Per sphere, the order of a deep pile of spheres (hosts: `lanes::pile_key`).
    #[cfg(lanes)]
    pub(super) pile: P::Slot<heapless::Vec<f32, S>>,
    /// The rows of each block of the boxes (hosts: `lanes::index_boxes`).
    #[cfg(lanes)]
    pub(super) box_rows: P::Slot<heapless::Vec<PixelBox, { super::lanes::BOX_BLOCKS }>>,
    /// The hierarchy that culls secondary rays, where the scene has them and `SWEEPS`.
    pub(super) bvh: P::Culling<Bvh<S>>,
}

impl<const S: usize, const L: usize, P: Place> core::fmt::Debug for FrameStorage<S, L, P> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("FrameStorage")
            .field("eye", &*self.eye)
            .field("boxes", &*self.boxes)
            .field("lights", &*self.lights)
            .field("sweeps", &self.built_sweeps())
            .field("all", &*self.all)
            .field("near", &*self.near)
            .field("bvh", &self.bvh.get())
            .finish()
    }
}

/// Where a [`FrameStorage`]'s tables live: [`Inline`] in the storage itself (no heap: on the
/// stack, in a `static` or in a `Box` of the whole), [`Small`] likewise but without the tables
/// that only capacities above 8 spheres use, or [`Heap`] (feature `std`) each table in a box
/// of its own.
pub trait Place: sealed::Sealed {
    /// A table of type `T`, as the storage holds it.
    type Slot<T>: core::ops::DerefMut<Target = T>;
    /// A table that only capacities above 8 spheres use (the lights' sweeps, the hierarchy):
    /// a [`Place::Slot`], or nothing at all ([`Absent`], in [`Small`]).
    type Culling<T>: sealed::Maybe<T>;
}

mod sealed {
    pub trait Sealed {}

    /// A table the storage may not hold ([`super::Place::Culling`]).
    pub trait Maybe<T> {
        fn get(&self) -> Option<&T>;
        fn get_mut(&mut self) -> Option<&mut T>;
    }
}

use sealed::Maybe;

/// A table that a [`Small`] storage does not hold: nothing, not even room for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Absent<T>(core::marker::PhantomData<T>);

impl<T> Maybe<T> for Absent<T> {
    fn get(&self) -> Option<&T> {
        None
    }
    fn get_mut(&mut self) -> Option<&mut T> {
        None
    }
}

/// A [`FrameStorage`] that holds its tables itself: [`FrameStorage::new`], a `const fn`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Inline;

/// A table held inline, in a [`FrameStorage<S, L, Inline>`](FrameStorage) (see [`Place`]).
#[derive(Debug)]
pub struct InlineSlot<T>(T);

impl<T> core::ops::Deref for InlineSlot<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<T> core::ops::DerefMut for InlineSlot<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.0
    }
}

impl<T> Maybe<T> for InlineSlot<T> {
    fn get(&self) -> Option<&T> {
        Some(&self.0)
    }
    fn get_mut(&mut self) -> Option<&mut T> {
        Some(&mut self.0)
    }
}

impl sealed::Sealed for Inline {}
impl Place for Inline {
    type Slot<T> = InlineSlot<T>;
    type Culling<T> = InlineSlot<T>;
}

/// A [`FrameStorage`] of at most 8 spheres that holds its tables itself, as [`Inline`] does,
/// but for those that only larger capacities use: a frame of 8 spheres or less sorts no
/// sweeps and builds no hierarchy (`Frame`'s culling is decided by the capacity, at compile
/// time), so it renders the same pixels from less memory ([`FrameStorage::small`]): on a
/// Cortex-M, a quarter of [`Inline`]'s at `<5, 2>`. The layout for a microcontroller.
///
/// ```
/// use microray::render::{FrameStorage, Small};
///
/// static STORAGE: FrameStorage<5, 2, Small> = FrameStorage::small();
/// assert!(size_of_val(&STORAGE) < size_of::<FrameStorage<5, 2>>());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Small;

impl sealed::Sealed for Small {}
impl Place for Small {
    type Slot<T> = InlineSlot<T>;
    type Culling<T> = Absent<T>;
}

/// A [`FrameStorage`] whose tables are each boxed on the heap ([`FrameStorage::on_heap`];
/// feature `std`): built without a storage-sized value on the stack, however large the
/// capacity and whether or not the build is optimised.
#[cfg(feature = "std")]
#[cfg_attr(docsrs, doc(cfg(feature = "std")))]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Heap;

#[cfg(feature = "std")]
impl sealed::Sealed for Heap {}
#[cfg(feature = "std")]
impl Place for Heap {
    type Slot<T> = std::boxed::Box<T>;
    type Culling<T> = std::boxed::Box<T>;
}

#[cfg(feature = "std")]
impl<T> Maybe<T> for std::boxed::Box<T> {
    fn get(&self) -> Option<&T> {
        Some(self)
    }
    fn get_mut(&mut self) -> Option<&mut T> {
        Some(self)
    }
}

impl<const S: usize, const L: usize> FrameStorage<S, L, Inline> {
    /// Empty storage; [`Frame::new`] fills it. A `const fn`, so it can initialise a `static`,
    /// and it writes nothing but lengths, so a large one costs nothing until it is filled.
    ///
    /// An unoptimised build may still build it on the stack before moving it into a `Box`
    /// (`Box::new(FrameStorage::new())`): at a large capacity take
    /// [`FrameStorage::on_heap`] instead.
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
        eye: InlineSlot(heapless::Vec::new()),
        boxes: InlineSlot(heapless::Vec::new()),
        lights: InlineSlot([const { heapless::Vec::new() }; L]),
        sweeps: InlineSlot([const { Sweep::empty() }; L]),
        swept: 0,
        entries: InlineSlot(heapless::Vec::new()),
        #[cfg(lanes)]
        sort_room: InlineSlot(heapless::Vec::new()),
        all: InlineSlot(heapless::Vec::new()),
        near: InlineSlot(heapless::Vec::new()),
        #[cfg(lanes)]
        pile: InlineSlot(heapless::Vec::new()),
        #[cfg(lanes)]
        box_rows: InlineSlot(heapless::Vec::new()),
        bvh: InlineSlot(Bvh::EMPTY),
    };
}

impl<const S: usize, const L: usize> FrameStorage<S, L, Small> {
    /// Empty storage for at most 8 spheres, without the tables only larger capacities use
    /// ([`Small`]); [`Frame::new`] fills it. A `const fn`, for a `static`. A capacity above 8
    /// does not compile.
    ///
    /// ```
    /// use microray::render::{FrameStorage, Small};
    /// let storage: FrameStorage<8, 2, Small> = FrameStorage::small();
    /// # let _ = storage;
    /// ```
    ///
    /// ```compile_fail
    /// use microray::render::{FrameStorage, Small};
    /// let storage: FrameStorage<9, 2, Small> = FrameStorage::small();
    /// ```
    pub const fn small() -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS_SMALL;
        Self::EMPTY_SMALL
    }

    /// A capacity that never sorts sweeps or builds a hierarchy (`Frame::SWEEPS`).
    const FITS_SMALL: () = assert!(S <= 8, "a Small storage holds at most 8 spheres");

    const EMPTY_SMALL: Self = FrameStorage {
        eye: InlineSlot(heapless::Vec::new()),
        boxes: InlineSlot(heapless::Vec::new()),
        lights: InlineSlot([const { heapless::Vec::new() }; L]),
        sweeps: Absent(core::marker::PhantomData),
        swept: 0,
        entries: Absent(core::marker::PhantomData),
        #[cfg(lanes)]
        sort_room: Absent(core::marker::PhantomData),
        all: InlineSlot(heapless::Vec::new()),
        near: InlineSlot(heapless::Vec::new()),
        #[cfg(lanes)]
        pile: InlineSlot(heapless::Vec::new()),
        #[cfg(lanes)]
        box_rows: InlineSlot(heapless::Vec::new()),
        bvh: Absent(core::marker::PhantomData),
    };
}

#[cfg(feature = "std")]
impl<const S: usize, const L: usize> FrameStorage<S, L, Heap> {
    /// Empty storage whose tables are each on the heap (about 15.4 MB at `<16384, 32>`, the
    /// desktop capacity): the storage itself is a few pointers. An unoptimised build copies
    /// each empty table through the stack on its way into its box, one at a time (at most
    /// 0.4 MB at the desktop capacity), where `Box::new(FrameStorage::new())` builds the whole
    /// storage on the stack first. [`Frame::new`] fills it.
    ///
    /// ```
    /// use microray::FrameStorage;
    /// let storage = FrameStorage::<16384, 32, _>::on_heap();
    /// assert!(core::mem::size_of_val(&storage) < 100);
    /// ```
    pub fn on_heap() -> Self {
        FrameStorage {
            eye: boxed(),
            boxes: boxed(),
            lights: boxed_array(),
            sweeps: boxed_array(),
            swept: 0,
            entries: boxed(),
            #[cfg(lanes)]
            sort_room: boxed(),
            all: boxed(),
            near: boxed(),
            #[cfg(lanes)]
            pile: boxed(),
            #[cfg(lanes)]
            box_rows: boxed(),
            bvh: boxed(),
        }
    }
}

/// A table's empty value, a constant: [`boxed`] copies it from the binary into its box.
#[cfg(feature = "std")]
trait Empty {
    const EMPTY: Self;
}

#[cfg(feature = "std")]
impl<T, const N: usize> Empty for heapless::Vec<T, N> {
    const EMPTY: Self = heapless::Vec::new();
}

#[cfg(feature = "std")]
impl<const S: usize> Empty for Sweep<S> {
    const EMPTY: Self = Sweep::empty();
}

#[cfg(feature = "std")]
impl<const S: usize> Empty for Bvh<S> {
    const EMPTY: Self = Bvh::<S>::EMPTY;
}

/// An empty table in a box. Safe Rust has no way to build a value in place on the heap, so an
/// unoptimised build copies the constant through this function's frame: one table (at most
/// 0.4 MB at the desktop capacity), never more, as each table has a call of its own.
#[cfg(feature = "std")]
#[inline(never)]
fn boxed<T: Empty>() -> std::boxed::Box<T> {
    std::boxed::Box::new(T::EMPTY)
}

/// `N` empty tables in a box, pushed one at a time, never the whole array on the stack.
#[cfg(feature = "std")]
#[inline(never)]
fn boxed_array<T: Empty, const N: usize>() -> std::boxed::Box<[T; N]> {
    let mut all = std::vec::Vec::with_capacity(N);
    for _ in 0..N {
        all.push(T::EMPTY);
    }
    // `N` values: the conversion cannot fail (and would only fall back to the stack).
    all.into_boxed_slice()
        .try_into()
        .unwrap_or_else(|_| std::boxed::Box::new([const { T::EMPTY }; N]))
}

impl<const S: usize, const L: usize, P: Place> FrameStorage<S, L, P> {
    /// The sweeps of the last frame filled.
    pub(super) fn built_sweeps(&self) -> &[Sweep<S>] {
        let sweeps = self.sweeps.get().and_then(|s| s.get(..self.swept));
        sweeps.unwrap_or(&[])
    }

    /// The hierarchy of the last frame filled, if the storage holds one.
    pub(super) fn bvh(&self) -> Option<&Bvh<S>> {
        self.bvh.get()
    }

    /// Fills the tables for `scene` seen by `camera`, in place: nothing of capacity size is
    /// built elsewhere and moved in.
    pub(super) fn fill(&mut self, scene: &Scene<S, L>, camera: &Camera) {
        // The capacity decides, a constant: a capacity of 8 or less links neither the sweeps
        // nor the hierarchy, whose tables then stay empty (or, in a `Small` storage, are not
        // there at all).
        let sweeps = Frame::<'_, S, L>::SWEEPS;
        self.eye.clear();
        self.boxes.clear();
        self.swept = 0;
        self.all.clear();
        self.near.clear();
        #[cfg(lanes)]
        self.pile.clear();
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
            #[cfg(lanes)]
            let _ = self.pile.push(super::lanes::pile_key(&k));
            let _ = self.eye.push(k);
        }
        #[cfg(lanes)]
        super::lanes::index_boxes(&self.boxes, &mut self.box_rows);
        if let (true, Some(bvh)) = (sweeps, self.bvh.get_mut()) {
            let secondary = scene.has_secondary().then_some(scene.spheres());
            bvh.fill(secondary.unwrap_or(&[]));
        }
        let axes = camera.basis();
        for consts in self.lights.iter_mut() {
            consts.clear();
        }
        for (light, consts) in scene.lights().iter().zip(self.lights.iter_mut()) {
            if let (Some(origin), true) = (light.origin(), scene.shadows()) {
                for s in scene.spheres() {
                    let _ = consts.push(Prepared::exact(origin, s).c);
                }
            }
            if !(scene.shadows() && sweeps) {
                continue;
            }
            #[cfg(lanes)]
            let room = self.sort_room.get_mut();
            // A `let` of its own keeps the `()` to the block's end: Rust 1.87, the crate's
            // `rust-version`, drops a temporary made inside `Some(..)` with its statement.
            #[cfg(not(lanes))]
            let room = &mut ();
            #[cfg(not(lanes))]
            let room = Some(room);
            let sweep = self.sweeps.get_mut().and_then(|s| s.get_mut(self.swept));
            if let (Some(sweep), Some(all), Some(room)) = (sweep, self.entries.get_mut(), room) {
                sweep.clear();
                sweep.fill(light, scene.spheres(), axes.0, axes.1, all, room);
                self.swept += 1;
            }
        }
    }
}

impl<const S: usize, const L: usize> Default for FrameStorage<S, L, Inline> {
    fn default() -> Self {
        Self::new()
    }
}

//! Scenes: spheres with materials, lights and global settings in fixed-capacity containers.
//!
//! Every value is checked when it is added, so the render path never meets an invalid scene.

use crate::error::Error;
use crate::geometry::{hit_point_near, offset_is_near, Prepared, Ray, Sphere, NEAR2_MIN};
use crate::math::{Color, Vec3};

mod hit;
mod id;
mod light;
mod material;

pub use hit::*;
pub(crate) use id::SphereId;
pub use light::*;
pub use material::*;

/// A scene of at most `S` spheres and `L` lights, with its global settings.
///
/// ```
/// use microray::{Color, Light, Material, Scene, Sphere, Vec3};
/// let mut scene: Scene<8, 2> = Scene::new();
/// scene.set_ambient(Color::splat(0.1))?;
/// scene.add_sphere(Sphere::new(Vec3::new(0.0, -1000.0, 0.0), 1000.0), Material::default())?;
/// scene.add_light(Light::Point { position: Vec3::new(3.0, 5.0, 4.0), intensity: Color::ONE })?;
/// assert_eq!((scene.spheres().len(), scene.lights().len()), (1, 1));
/// # Ok::<(), microray::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Scene<const S: usize, const L: usize> {
    spheres: heapless::Vec<Sphere, S>,
    materials: heapless::Vec<Material, S>,
    /// Per sphere, what shading derives from its material, once.
    derived: heapless::Vec<Derived, S>,
    lights: heapless::Vec<Light, L>,
    ambient: Color,
    background: Color,
    shadows: bool,
    max_depth: u8,
    /// Whether any sphere sends secondary rays (a mirror, or glass): most scenes have none,
    /// and their hits skip the per-sphere test.
    secondary: bool,
}

impl<const S: usize, const L: usize> Default for Scene<S, L> {
    fn default() -> Self {
        Self::new()
    }
}

/// What shading derives from a sphere's material, once when the sphere is added rather than at
/// every hit.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Derived {
    /// [`near2`] of the material.
    near2: f32,
    /// Bit 0: `k_s ≠ 0` (the hit needs the view vector and a highlight per light); bit 1:
    /// `k_m ≠ 0` or `k_t ≠ 0` (the hit sends a mirror or a refracted ray).
    flags: u8,
}

/// `(distance/radius)²` from the ray origin up to which `f + t·d` gives a hit offset accurate
/// enough for material `m`; beyond it [`hit_point`](crate::geometry::hit_point) recomputes it
/// from exact products (`hit_point_far`: a few times the cost, so only where it pays).
///
/// The f32 offset is off by ~4ε·distance, which turns the normal by ~4ε·distance/radius: a
/// diffuse term moves by that much, a highlight of shininess s by s times that. 2048/(1 + s)
/// radii keep either under 1/8 of a level (for a light of intensity 1); never fewer than 16
/// radii, and 16 for mirrors, whose rays go on; for glass, none beyond its surface.
fn near2(m: &Material) -> f32 {
    if cfg!(feature = "refraction") && m.refraction != Color::ZERO {
        // Glass is a lens, which magnifies the normal's error, and whether a hit enters or
        // leaves it turns on the normal's side: at a grazing hit from outside `f + t·d` errs
        // along the ray by t's error, which decides that side by chance. So the exact offset
        // for every hit from outside; `f + t·d` only for rays starting on the sphere
        // (|f|² = r² within a few ε), from inside, where it errs by a few ulp of r.
        return 1.0 + 1.0 / 1024.0;
    }
    let k = if m.mirror != Color::ZERO {
        16.0
    } else if m.specular == Color::ZERO {
        2048.0
    } else {
        let k = 2048.0 / (1.0 + m.shininess);
        if k > 16.0 {
            k
        } else {
            16.0
        }
    };
    k * k
}

// Out of line: set-up calls it for every colour, and one copy is what small flash prefers.
#[inline(never)]
fn check_color(c: Color) -> Result<Color, Error> {
    if c.is_finite() && c.x >= 0.0 && c.y >= 0.0 && c.z >= 0.0 {
        Ok(c)
    } else {
        Err(Error::InvalidColor)
    }
}

/// The largest [`Scene::set_max_depth`].
pub(crate) const MAX_DEPTH: u8 = 16;

fn check_point(p: Vec3) -> Result<Vec3, Error> {
    if p.is_finite() {
        Ok(p)
    } else {
        Err(Error::NotFinite)
    }
}

impl<const S: usize, const L: usize> Scene<S, L> {
    /// An empty scene: black background, no ambient light, shadows on, reflection depth 3.
    ///
    /// ```
    /// # use microray::Scene;
    /// let scene: Scene<4, 1> = Scene::new();
    /// assert!(scene.shadows() && scene.max_depth() == 3);
    /// ```
    pub const fn new() -> Self {
        Scene {
            spheres: heapless::Vec::new(),
            materials: heapless::Vec::new(),
            derived: heapless::Vec::new(),
            lights: heapless::Vec::new(),
            ambient: Color::ZERO,
            background: Color::ZERO,
            shadows: true,
            max_depth: 3,
            secondary: false,
        }
    }

    /// Adds a sphere and returns its index; rejects invalid values and overflow of `S`.
    ///
    /// ```
    /// # use microray::{Color, Error, Material, Scene, Sphere, Vec3};
    /// let mut scene: Scene<2, 0> = Scene::new();
    /// assert_eq!(scene.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default()), Ok(0));
    /// let flat = Sphere::new(Vec3::ZERO, 0.0);
    /// assert_eq!(scene.add_sphere(flat, Material::default()), Err(Error::InvalidRadius));
    /// let glass = Material { refraction: Color::splat(0.9), ior: 0.0, ..Material::default() };
    /// let ball = Sphere::new(Vec3::ZERO, 1.0);
    /// # #[cfg(feature = "refraction")]
    /// assert_eq!(scene.add_sphere(ball, glass), Err(Error::InvalidIor));
    /// # #[cfg(not(feature = "refraction"))]
    /// # assert_eq!(scene.add_sphere(ball, glass), Err(Error::RefractionNotEnabled));
    /// ```
    pub fn add_sphere(&mut self, sphere: Sphere, material: Material) -> Result<usize, Error> {
        check_point(sphere.center)?;
        if !(sphere.radius > 0.0 && sphere.radius.is_finite()) {
            return Err(Error::InvalidRadius);
        }
        check_color(material.diffuse)?;
        check_color(material.specular)?;
        check_color(material.mirror)?;
        if !(material.shininess > 0.0 && material.shininess.is_finite()) {
            return Err(Error::InvalidShininess);
        }
        let refraction = !material.refraction.is_zero();
        if refraction && !cfg!(feature = "refraction") {
            return Err(Error::RefractionNotEnabled);
        }
        #[cfg(feature = "refraction")]
        {
            check_color(material.refraction)?;
            if !(material.ior > 0.0 && material.ior.is_finite()) {
                return Err(Error::InvalidIor);
            }
        }
        self.spheres
            .push(sphere)
            .map_err(|_| Error::TooManySpheres)?;
        // The vectors have capacity S and grow together, so these pushes cannot fail.
        let _ = self.materials.push(material);
        let specular = !material.specular.is_zero();
        let secondary = !material.mirror.is_zero() || refraction;
        self.secondary |= secondary;
        let _ = self.derived.push(Derived {
            near2: near2(&material),
            flags: specular as u8 | (secondary as u8) << 1,
        });
        Ok(self.spheres.len() - 1)
    }

    /// Adds a light; a directional light's direction is stored normalised.
    ///
    /// ```
    /// # use microray::{Color, Error, Light, Scene, Vec3};
    /// let mut scene: Scene<1, 1> = Scene::new();
    /// let dark = Light::Directional { direction: Vec3::ZERO, intensity: Color::ONE };
    /// assert_eq!(scene.add_light(dark), Err(Error::ZeroDirection));
    /// let sun = Light::Directional { direction: Vec3::new(0.0, -1e30, 0.0), intensity: Color::ONE };
    /// scene.add_light(sun)?;
    /// assert_eq!(scene.add_light(sun), Err(Error::TooManyLights));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn add_light(&mut self, light: Light) -> Result<(), Error> {
        let light = light.checked()?;
        self.lights.push(light).map_err(|_| Error::TooManyLights)
    }

    /// Makes this scene a copy of `other`, a scene of another capacity: the same spheres,
    /// materials and lights in the same order, and the same settings, bit for bit. Adding
    /// `other`'s lights again would not do: [`Scene::add_light`] normalises a direction, and
    /// normalising one already normalised may round it differently. Where `other` does not
    /// fit, [`Error::TooManySpheres`] or [`Error::TooManyLights`], and this scene is left as
    /// it was.
    ///
    /// ```
    /// use microray::{Color, Error, Light, Material, Scene, Sphere, Vec3};
    /// let mut big: Scene<1024, 4> = Scene::new();
    /// big.add_sphere(Sphere::new(Vec3::ZERO, 1.0), Material::default())?;
    /// let sun = Light::Directional { direction: Vec3::new(1.0, -3.0, 0.3), intensity: Color::ONE };
    /// big.add_light(sun)?;
    /// let mut small: Scene<8, 1> = Scene::new();
    /// small.copy_from(&big)?;
    /// assert_eq!((small.spheres(), small.lights()), (big.spheres(), big.lights()));
    /// let mut none: Scene<8, 0> = Scene::new();
    /// assert_eq!(none.copy_from(&big), Err(Error::TooManyLights));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn copy_from<const S2: usize, const L2: usize>(
        &mut self,
        other: &Scene<S2, L2>,
    ) -> Result<(), Error> {
        if other.spheres.len() > S {
            return Err(Error::TooManySpheres);
        }
        if other.lights.len() > L {
            return Err(Error::TooManyLights);
        }
        // Every field named, so that a new one cannot be left out.
        let Scene {
            spheres,
            materials,
            derived,
            lights,
            ambient,
            background,
            shadows,
            max_depth,
            secondary,
        } = other;
        // Within the capacities, as checked: none of these can fail.
        self.spheres.clear();
        self.materials.clear();
        self.derived.clear();
        self.lights.clear();
        let _ = self.spheres.extend_from_slice(spheres);
        let _ = self.materials.extend_from_slice(materials);
        let _ = self.derived.extend_from_slice(derived);
        let _ = self.lights.extend_from_slice(lights);
        (self.ambient, self.background) = (*ambient, *background);
        (self.shadows, self.max_depth, self.secondary) = (*shadows, *max_depth, *secondary);
        Ok(())
    }

    /// Sets the ambient light (multiplied by each sphere's diffuse colour).
    ///
    /// ```
    /// # use microray::{Color, Scene};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_ambient(Color::splat(0.2))?;
    /// assert!(scene.set_ambient(Color::splat(-1.0)).is_err());
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn set_ambient(&mut self, ambient: Color) -> Result<(), Error> {
        self.ambient = check_color(ambient)?;
        Ok(())
    }

    /// Sets the colour of rays that hit nothing.
    ///
    /// ```
    /// # use microray::{Color, Scene};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_background(Color::new(0.1, 0.1, 0.3))?;
    /// assert_eq!(scene.background(), Color::new(0.1, 0.1, 0.3));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn set_background(&mut self, background: Color) -> Result<(), Error> {
        self.background = check_color(background)?;
        Ok(())
    }

    /// Turns hard shadows on or off.
    ///
    /// ```
    /// # use microray::Scene;
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_shadows(false);
    /// assert!(!scene.shadows());
    /// ```
    pub fn set_shadows(&mut self, on: bool) {
        self.shadows = on;
    }

    /// Sets how many mirror and refraction bounces a ray may take (0..=16; primary rays have
    /// depth 0).
    ///
    /// ```
    /// # use microray::{Error, Scene};
    /// let mut scene: Scene<1, 0> = Scene::new();
    /// scene.set_max_depth(0)?;
    /// assert_eq!(scene.set_max_depth(17), Err(Error::InvalidMaxDepth));
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn set_max_depth(&mut self, depth: u8) -> Result<(), Error> {
        if depth > MAX_DEPTH {
            return Err(Error::InvalidMaxDepth);
        }
        self.max_depth = depth;
        Ok(())
    }

    /// The spheres, in the order they were added.
    ///
    /// ```
    /// # use microray::Scene;
    /// assert!(Scene::<3, 0>::new().spheres().is_empty());
    /// ```
    pub fn spheres(&self) -> &[Sphere] {
        &self.spheres
    }

    /// The materials, index for index with [`Scene::spheres`].
    ///
    /// ```
    /// # use microray::Scene;
    /// assert!(Scene::<3, 0>::new().materials().is_empty());
    /// ```
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }

    /// Per sphere, the squared distance in radii up to which an f32 hit offset is good enough
    /// for its material (see [`near2`]).
    #[inline]
    pub(crate) fn near2(&self, i: usize) -> f32 {
        self.derived.get(i).map_or(NEAR2_MIN, |d| d.near2)
    }

    /// Whether sphere `i`'s material has a highlight (`k_s ≠ 0`).
    #[inline]
    pub(crate) fn has_specular(&self, i: usize) -> bool {
        self.derived.get(i).is_some_and(|d| d.flags & 1 != 0)
    }

    /// Whether sphere `i`'s hits send secondary rays (`k_m ≠ 0` or `k_t ≠ 0`).
    #[inline]
    pub(crate) fn sends_secondary(&self, i: usize) -> bool {
        self.derived.get(i).is_some_and(|d| d.flags & 2 != 0)
    }

    /// Whether any sphere sends secondary rays.
    #[inline]
    pub(crate) fn has_secondary(&self) -> bool {
        self.secondary
    }

    /// The lights (directional ones with unit direction).
    ///
    /// ```
    /// # use microray::Scene;
    /// assert!(Scene::<0, 3>::new().lights().is_empty());
    /// ```
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The ambient light.
    ///
    /// ```
    /// # use microray::{Color, Scene};
    /// assert_eq!(Scene::<1, 0>::new().ambient(), Color::ZERO);
    /// ```
    pub fn ambient(&self) -> Color {
        self.ambient
    }

    /// The background colour.
    ///
    /// ```
    /// # use microray::{Color, Scene};
    /// assert_eq!(Scene::<1, 0>::new().background(), Color::ZERO);
    /// ```
    pub fn background(&self) -> Color {
        self.background
    }

    /// Whether hard shadows are on.
    ///
    /// ```
    /// # use microray::Scene;
    /// assert!(Scene::<1, 0>::new().shadows());
    /// ```
    pub fn shadows(&self) -> bool {
        self.shadows
    }

    /// The maximum depth of mirror and refracted rays.
    ///
    /// ```
    /// # use microray::Scene;
    /// assert_eq!(Scene::<1, 0>::new().max_depth(), 3);
    /// ```
    pub fn max_depth(&self) -> u8 {
        self.max_depth
    }

    /// The closest hit over all spheres with `t` in `[tmin, tmax]` (the textbook
    /// `find_intersection`).
    ///
    /// ```
    /// # use microray::{Material, Ray, Scene, Sphere, Vec3};
    /// let mut scene: Scene<2, 0> = Scene::new();
    /// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -5.0), 1.0), Material::default())?;
    /// scene.add_sphere(Sphere::new(Vec3::new(0.0, 0.0, -9.0), 1.0), Material::default())?;
    /// let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -1.0));
    /// assert_eq!(scene.find_intersection(&ray, 0.0, f32::INFINITY).unwrap().sphere, 0);
    /// assert_eq!(scene.find_intersection(&ray, 6.5, f32::INFINITY).unwrap().sphere, 1);
    /// # Ok::<(), microray::Error>(())
    /// ```
    pub fn find_intersection(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        let mut best: Option<(f32, usize, Vec3)> = None;
        let mut tmax = tmax;
        for (i, sphere) in self.spheres.iter().enumerate() {
            if let Some((t, f)) = Prepared::ray_hit(ray, sphere, tmin, tmax) {
                tmax = t;
                best = Some((t, i, f));
            }
        }
        best.map(|(t, i, f)| {
            let sphere = &self.spheres[i];
            let near = offset_is_near(f, sphere.radius, self.near2(i));
            make_hit(ray, t, i, f, sphere, near, ray.origin, Vec3::ZERO)
        })
    }
}

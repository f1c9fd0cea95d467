#!/usr/bin/env python3
"""Writes a microray scene file (TOML) as a POV-Ray 3.7 scene of exactly the same model.

    toml2pov.py [--supersampled] [--scale K] SCENE.toml [WIDTH HEIGHT] > SCENE.pov

--supersampled accepts samples > 1 and sRGB encoding, which POV-Ray cannot do as microray does
(its anti-aliasing averages the pixel centre with an n×n grid, and it clamps before encoding):
the caller traces the file at samples·W × samples·H, whose pixel centres are microray's sample
points, and averages and encodes the linear pixels itself (bench/povray.sh). --scale K divides
the lights, the ambient and the background by K, which divides the image by K: headroom for
samples above 1, which POV-Ray clamps when it writes them and microray averages unclamped.

The mapping (see docs/speed.md): pigment = k_d with `ambient 1` and the scene's ambient as the
global `ambient_light`, `diffuse 1`, `specular k_s roughness 1/s` (POV's Blinn-Phong highlight,
exponent 1/roughness, light-coloured), mirrors as `reflection k_m`, point lights as
`light_source` (no fading), directional lights as `parallel` lights with `point_at`, shadows or
`shadowless`, `assumed_gamma 1.0`, and a camera with `right <-W/H,0,0>` (microray is
right-handed) and `angle` = the horizontal field of view. Coloured specular cannot be written
in POV-Ray (its `specular` is a float) and is rejected. Glass (`refraction`, `ior`): see
`glass`; such scenes get `adc_bailout 0`.
"""
import math
import sys
import tomllib


def vec(v):
    return "<%r, %r, %r>" % tuple(float(x) for x in v)


def col(v, default):
    if v is None:
        v = default
    if isinstance(v, (int, float)):
        v = [v, v, v]
    return "rgb " + vec(v)


def rgb(v, default):
    """A material colour (a number or [r, g, b]) as three floats."""
    if v is None:
        v = default
    if isinstance(v, (int, float)):
        v = [v, v, v]
    return [float(x) for x in v]


def glass(s, fin, shadows, eye):
    """A sphere with refraction k_t: the model's local terms, k_t times the refracted (or totally
    reflected) colour, and fully blocked shadows, in POV-Ray 3.7's terms.

    POV scales a layer's ambient and diffuse (not its specular or reflection) by the layer's
    opacity 1 - filter - transmit, and weighs the refracted colour by the product over the layers
    of rgb * filter + transmit. So the top layer carries the local terms, pigment 2 k_d with
    transmit 0.5 (opacity 0.5: exactly k_d, any colour), and passes 0.5 of the refracted light to
    a bottom layer of pigment 2 k_t with filter 1 (no local terms): k_t, any colour. Hits from
    inside use interior_texture. POV weighs a total internal reflection by no pigment and skips
    the layers' `reflection` there (the model adds k_t and k_m times that same mirror colour),
    but a fade over a vanishing distance multiplies whatever a ray inside the sphere brings out,
    refracted or totally reflected, by fade_colour: with fade_colour = k_t + k_m the interior
    texture's bottom layer passes k_t / (k_t + k_m). With ior < 1 total internal reflection
    happens on entering, where no fade applies: the deprecated `finish { refraction a }` weighs
    every transmitted colour by a grey a = mean(k_t + k_m), exact when k_t + k_m is grey.
    Transparent objects only filter shadow rays in POV, so the glass gets no_shadow and an opaque
    copy of the sphere, invisible to camera, refracted and reflected rays (no_image
    no_reflection), blocks them. With the eye inside the sphere the copy is a thin shell instead:
    POV starts camera rays inside every object that holds the eye, in no set order, and the glass
    wall, met inside the copy too, could refract as between two overlapping objects (index 1)."""
    kd, kt, km = rgb(s.get("diffuse"), 1), rgb(s.get("refraction"), 0), rgb(s.get("mirror"), 0)
    ior = float(s.get("ior", 1.5))
    tir = [t + m for t, m in zip(kt, km)]
    if ior >= 1:
        a, outside, fade = 1.0, kt, tir
        inside = [t / w if w else 0.0 for t, w in zip(kt, tir)]
    else:
        a, fade = sum(tir) / 3, None
        outside = inside = [t / a for t in kt]
    if a != 1:
        fin += " refraction %r" % a
    top = "pigment { rgb %s transmit 0.5 } finish { %s }" % (vec([2 * x for x in kd]), fin)
    bottom = "pigment { rgb %s filter 1 } finish { ambient 0 diffuse 0 }"
    # POV passes a ray through an interface of relative index 1 as the same ray, at the same trace
    # level; the model counts a level there. The next f32 above 1 refracts (by ~1e-7 rad).
    interior = "ior %r" % (1.0000001 if abs(ior - 1) < 1e-7 else ior)
    if fade:
        interior += " fade_colour rgb %s fade_distance 1e-8 fade_power 2" % vec(fade)
    c, r = vec(s["center"]), float(s["radius"])
    outside, inside = (bottom % vec([2 * x for x in v]) for v in (outside, inside))
    out = ("sphere { %s, %r\n  texture { %s }\n  texture { %s }\n  interior_texture { %s }\n"
           "  interior_texture { %s }\n  interior { %s }%s }"
           % (c, r, outside, top, inside, top, interior, " no_shadow" if shadows else ""))
    if shadows and math.dist(eye, s["center"]) > r:
        out += "\nsphere { %s, %r no_image no_reflection }" % (c, r)
    elif shadows:
        out += ("\ndifference { sphere { %s, %r } sphere { %s, %r } no_image no_reflection }"
                % (c, r, c, r * (1 - 1e-7)))
    return out


def main():
    args, supersampled, scale = sys.argv[1:], False, 1.0
    while args and args[0].startswith("--"):
        if args[0] == "--supersampled":
            supersampled, args = True, args[1:]
        elif args[0] == "--scale" and len(args) > 1:
            scale, args = float(args[1]), args[2:]
        else:
            sys.exit("usage: toml2pov.py [--supersampled] [--scale K] SCENE.toml [WIDTH HEIGHT]")
    # The image is linear in the lights, the ambient and the background together.
    def emitted(v, default):
        return col(v, default) if scale == 1 else col([x / scale for x in rgb(v, default)], 0)

    scene = tomllib.load(open(args[0], "rb"))
    cam = scene["camera"]
    rnd = scene.get("render", {})
    w = int(args[1]) if len(args) > 1 else rnd.get("width", 640)
    h = int(args[2]) if len(args) > 2 else rnd.get("height", 480)
    one_sample = rnd.get("samples", 1) == 1 and rnd.get("encoding", "linear") == "linear"
    if not (one_sample or supersampled):
        sys.exit("toml2pov: only samples = 1 and linear encoding map to POV-Ray here")
    vfov = math.radians(cam["vfov"])
    hfov = math.degrees(2 * math.atan(math.tan(vfov / 2) * w / h))
    up = cam.get("up", [0.0, 1.0, 0.0])
    ambient = rnd.get("ambient", [0, 0, 0])
    if isinstance(ambient, (int, float)):
        ambient = [ambient] * 3
    print("#version 3.7;")
    # With glass, adc_bailout 0: POV would drop rays weighing less than 1/255, microray doesn't.
    glassy = any(any(rgb(s.get("refraction"), 0)) for s in scene.get("sphere", []))
    print("global_settings { assumed_gamma 1.0 ambient_light %s max_trace_level %d%s }"
          % (emitted(ambient, 0), rnd.get("max_depth", 3) + 1, " adc_bailout 0" if glassy else ""))
    print("background { %s }" % emitted(rnd.get("background"), [0, 0, 0]))
    print("camera { perspective location %s sky %s up %s right <%r, 0, 0> angle %r look_at %s }"
          % (vec(cam["eye"]), vec(up), vec(up), -w / h, hfov, vec(cam["look_at"])))
    shadows = rnd.get("shadows", True)
    for s in scene.get("sphere", []):
        spec = s.get("specular", 0.0)
        if not isinstance(spec, (int, float)):
            if len(set(spec)) != 1:
                sys.exit("toml2pov: coloured specular has no POV-Ray equivalent")
            spec = spec[0]
        shin = s.get("shininess", 32.0)
        mirror = s.get("mirror", 0.0)
        fin = "ambient 1 diffuse 1 brilliance 1"
        if spec:
            fin += " specular %r roughness %r" % (float(spec), 1.0 / shin)
        if mirror and mirror != [0, 0, 0]:
            fin += " reflection { %s }" % col(mirror, 0)
        if any(rgb(s.get("refraction"), 0)):
            print(glass(s, fin, shadows, cam["eye"]))
            continue
        print("sphere { %s, %r pigment { %s } finish { %s } }"
              % (vec(s["center"]), float(s["radius"]), col(s.get("diffuse"), [1, 1, 1]), fin))
    for l in scene.get("light", []):
        extra = "" if shadows else " shadowless"
        if l["kind"] == "point":
            print("light_source { %s color %s%s }"
                  % (vec(l["position"]), emitted(l["intensity"], 1), extra))
        else:
            d = l["direction"]
            n = math.sqrt(sum(x * x for x in d))
            pos = [-1e5 * x / n for x in d]
            print("light_source { %s color %s parallel point_at <0, 0, 0>%s }"
                  % (vec(pos), emitted(l["intensity"], 1), extra))


main()

#!/usr/bin/env python3
"""Writes a microray scene file (TOML) as a POV-Ray 3.7 scene of exactly the same model.

    toml2pov.py SCENE.toml [WIDTH HEIGHT] > SCENE.pov

The mapping (see docs/speed.md): pigment = k_d with `ambient 1` and the scene's ambient as the
global `ambient_light`, `diffuse 1`, `specular k_s roughness 1/s` (POV's Blinn-Phong highlight,
exponent 1/roughness, light-coloured), mirrors as `reflection k_m`, point lights as
`light_source` (no fading), directional lights as `parallel` lights with `point_at`, shadows or
`shadowless`, `assumed_gamma 1.0`, and a camera with `right <-W/H,0,0>` (microray is
right-handed) and `angle` = the horizontal field of view. Coloured specular cannot be written
in POV-Ray (its `specular` is a float) and is rejected.
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


def main():
    scene = tomllib.load(open(sys.argv[1], "rb"))
    cam = scene["camera"]
    rnd = scene.get("render", {})
    w = int(sys.argv[2]) if len(sys.argv) > 2 else rnd.get("width", 640)
    h = int(sys.argv[3]) if len(sys.argv) > 3 else rnd.get("height", 480)
    if rnd.get("samples", 1) != 1 or rnd.get("encoding", "linear") != "linear":
        sys.exit("toml2pov: only samples = 1 and linear encoding map to POV-Ray here")
    vfov = math.radians(cam["vfov"])
    hfov = math.degrees(2 * math.atan(math.tan(vfov / 2) * w / h))
    up = cam.get("up", [0.0, 1.0, 0.0])
    ambient = rnd.get("ambient", [0, 0, 0])
    if isinstance(ambient, (int, float)):
        ambient = [ambient] * 3
    print("#version 3.7;")
    print("global_settings { assumed_gamma 1.0 ambient_light rgb %s max_trace_level %d }"
          % (vec(ambient), rnd.get("max_depth", 3) + 1))
    print("background { %s }" % col(rnd.get("background"), [0, 0, 0]))
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
        print("sphere { %s, %r pigment { %s } finish { %s } }"
              % (vec(s["center"]), float(s["radius"]), col(s.get("diffuse"), [1, 1, 1]), fin))
    for l in scene.get("light", []):
        extra = "" if shadows else " shadowless"
        if l["kind"] == "point":
            print("light_source { %s color %s%s }" % (vec(l["position"]), col(l["intensity"], 1), extra))
        else:
            d = l["direction"]
            n = math.sqrt(sum(x * x for x in d))
            pos = [-1e5 * x / n for x in d]
            print("light_source { %s color %s parallel point_at <0, 0, 0>%s }"
                  % (vec(pos), col(l["intensity"], 1), extra))


main()

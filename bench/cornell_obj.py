#!/usr/bin/env python3
"""Export the reference Cornell box (tests/data/reference/cbox/resolved.json) for Embree's own
`pathtracer` tutorial binary (Debian package embree-tools), a raw-Embree yardstick.

Writes, into --outdir (default out/embree, git-ignored):
  cornell.obj / cornell.mtl  the 17 non-emitting quads of resolved.json, same vertex order,
                             Kd = the diffuse reflectances;
  cornell.args               pathtracer arguments: the camera (--vp --vi --vu --fov; fov is the
                             vertical angle, the square image makes it the reference's 39.3077)
                             and the light, as a point light (see below).
The light's own quad is left out of the OBJ: Embree's OBJ loader has no emission (Ke), its
<QuadLight> XML node is parsed but not rendered by the pathtracer tutorial (scene_device.cpp:
LIGHT_QUAD "not implemented yet"), so the light becomes --pointlight at the quad's centre, 0.01
below it, intensity = radiance * area. The image is therefore not the reference image.

Usage: python3 bench/cornell_obj.py [--outdir out/embree]
then:  cd out/embree && pathtracer -i cornell.obj $(cat cornell.args) --size 256 256 \
           --spp 256 --max-path-length 7 --threads 2 -o cornell.ppm
(--max-path-length 1 = primary + shadow ray = Mitsuba max_depth 2, so 7 matches max_depth 8.)
Standard library only.
"""
import argparse
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def fmt(v):
    return " ".join(repr(float(x)) for x in v)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--resolved", type=Path, default=ROOT / "tests/data/reference/cbox/resolved.json")
    ap.add_argument("--outdir", type=Path, default=ROOT / "out/embree")
    args = ap.parse_args()
    res = json.loads(args.resolved.read_text())
    out = args.outdir
    out.mkdir(parents=True, exist_ok=True)

    mtl = ["# from resolved.json"]
    for name, m in res["materials"].items():
        mtl += [f"newmtl {name}", f"Kd {fmt(m['reflectance'])}", "Ks 0 0 0", "Ka 0 0 0", ""]
    (out / "cornell.mtl").write_text("\n".join(mtl))

    obj = ["# Cornell box from resolved.json (Mitsuba 3.9.1 mi.cornell_box()), light quad omitted",
           "mtllib cornell.mtl"]
    n = 0
    light = None
    for q in res["quads"]:
        if "emitter" in q:
            light = q
            continue
        obj += [f"o {q['name']}", f"usemtl {q['material']}"]
        obj += [f"v {fmt(p)}" for p in q["vertices"]]
        obj.append(f"f {n + 1} {n + 2} {n + 3} {n + 4}")
        n += 4
    (out / "cornell.obj").write_text("\n".join(obj) + "\n")

    # Embree's pathtracer tutorial loads area lights from XML (<QuadLight>) but does not render
    # them (scene_device.cpp: LIGHT_QUAD "not implemented yet"), so the light is approximated by
    # an isotropic point light at the quad's centre, 0.01 below it, with intensity
    # I = radiance * area (the quad's intensity straight down). Not the reference image: a
    # throughput yardstick only.
    c = [sum(p[i] for p in light["vertices"]) / 4 for i in range(3)]
    c[1] -= 0.01
    area = res["light"]["area"]
    intensity = [x * area for x in light["emitter"]["radiance"]]
    cam = res["camera"]
    (out / "cornell.args").write_text(
        f"--vp {fmt(cam['origin'])} --vi {fmt(cam['target'])} --vu {fmt(cam['up'])} "
        f"--fov {cam['fov_deg']} --righthanded --pointlight {fmt(c)} {fmt(intensity)}\n")
    print(f"wrote {out}/cornell.obj ({n // 4} quads), cornell.mtl, cornell.args")


if __name__ == "__main__":
    main()

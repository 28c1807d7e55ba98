#!/usr/bin/env python3
"""Every renderer on the Cornell box against the Mitsuba 3 reference, in one table (issue 13).

Renders scenes/cornell-box/{scene,lighttracer,photonmap,sppm,irradiancecache,pssmlt}.xml at 256²
with the settings below and prints, per renderer, the image mean and each wall's mean
(regions of tests/data/cornell/regions.txt) as a difference from the 2048-spp Mitsuba 3
reference (tests/data/cornell/mitsuba-reference.exr), with render time and peak memory.
Targets of issue 13: image within 1 %, every wall within 3 % (irradiancecache: 3 % / 5 %).

    python3 bench/renderers_cornell.py [--scale S] [--only a,b]

--scale multiplies every sample count (0.25 for a quick look).
"""
import argparse
import pathlib

from cornell_bench import ROOT, region_means, render

REFERENCE = ROOT / "tests/data/cornell/mitsuba-reference.exr"
SCENES = ROOT / "scenes/cornell-box"
# name, scene file, -D settings (spp scaled by --scale), the wall target in %
RUNS = [
    ("path", "scene.xml", {"spp": 256}, 3),
    ("lighttracer (ptracer)", "lighttracer.xml", {"spp": 256}, 3),
    ("photonmap, defaults", "photonmap.xml", {"spp": 64}, 3),
    ("photonmap, 1M photons", "photonmap.xml", {"spp": 64, "global_photons": 1000000}, 3),
    ("sppm", "sppm.xml", {"spp": 256}, 3),
    ("irradiancecache", "irradiancecache.xml", {"spp": 16}, 5),
    ("pssmlt", "pssmlt.xml", {"spp": 256}, 3),  # spp = mutations per pixel
]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scale", type=float, default=1.0, help="multiply every sample count")
    ap.add_argument("--only", default="", help="comma-separated renderer names (prefixes) to run")
    ap.add_argument("--effigi", default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--out", default=ROOT / "out/bench/renderers")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    only = [o for o in args.only.split(",") if o]
    ref = region_means(REFERENCE, 256)
    names = list(ref)
    print("| renderer | settings | " + " | ".join(names) + " | time s | peak MiB | targets |")
    print("|---|---|" + "---:|" * len(names) + "---:|---:|---|")
    for name, scene, defines, wall_target in RUNS:
        if only and not any(name.startswith(o) for o in only):
            continue
        d = dict(defines, res=256)
        d["spp"] = max(1, int(d["spp"] * args.scale))
        exr = out / (name.split()[0].strip(",") + ("-1M" if "1M" in name else "") + ".exr")
        seconds, peak, _ = render(args.effigi, SCENES / scene, exr, d, 0)
        means = region_means(exr, 256)
        diff = {k: 100.0 * (means[k] - ref[k]) / ref[k] for k in names}
        image_ok = abs(diff["image"]) <= (3 if wall_target == 5 else 1)
        walls_ok = all(abs(v) <= wall_target for k, v in diff.items() if k != "image")
        settings = " ".join(f"{k}={v}" for k, v in d.items() if k != "res")
        cells = " | ".join(f"{diff[k]:+.2f} %" for k in names)
        verdict = "met" if image_ok and walls_ok else "missed"
        print(f"| {name} | {settings} | {cells} | {seconds:.1f} | {peak:.0f} | {verdict} |", flush=True)


if __name__ == "__main__":
    main()

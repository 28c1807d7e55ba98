#!/usr/bin/env python3
"""Render the Cornell box with the path tracer (scenes/cornell-box/scene.xml) and with
radiosity (scenes/cornell-box/radiosity.xml, the same camera and geometry.xml), then print
both renderers' times, image and per-wall means and their relative differences.

    python3 bench/radiosity_vs_path.py                        # 1024 spp path, 2000 elements
    python3 bench/radiosity_vs_path.py --elements 4000 --formfactor analytic

The wall regions are those of tests/data/cornell/regions.txt (shared with the end-to-end
test and bench/compare_mitsuba.py). The issue's target: every wall within 3 %. EXR files
are read with oiiotool (OpenImageIO's command-line tool), no Python image module needed.
"""
import argparse
import pathlib
import re
import sys

from cornell_bench import ROOT, region_means, render

PATH_SCENE = ROOT / "scenes/cornell-box/scene.xml"
RAD_SCENE = ROOT / "scenes/cornell-box/radiosity.xml"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel of the path tracer")
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--elements", type=int, default=2000)
    ap.add_argument("--formfactor", default="hemicube", choices=["hemicube", "analytic", "montecarlo"])
    ap.add_argument("--solver", default="gaussseidel", choices=["jacobi", "gaussseidel", "southwell", "progressive", "gmres"])
    ap.add_argument("--effigi", default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--out", default=ROOT / "out/bench")
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path_exr, rad_exr = out / "cornell-path.exr", out / "cornell-radiosity.exr"
    path_sec, _, _ = render(args.effigi, PATH_SCENE, path_exr, {"spp": args.spp, "res": args.res}, args.threads)
    rad_sec, _, run = render(args.effigi, RAD_SCENE, rad_exr,
                             {"spp": 4, "res": args.res, "elements": args.elements, "formfactor": args.formfactor,
                              "solver": args.solver}, args.threads)
    solve = re.search(r"^radiosity: .*$", run.stderr, re.M)
    solve = solve.group(0) if solve else ""
    a, b = region_means(path_exr, args.res), region_means(rad_exr, args.res)
    print(f"Cornell box {args.res}x{args.res}: path tracer {args.spp} spp in {path_sec:.1f} s; "
          f"radiosity ({args.elements} elements, {args.formfactor}, {args.solver}) in {rad_sec:.1f} s")
    if solve:
        print(solve)
    print(f"\n{'region':<12}{'path':>10}{'radiosity':>11}{'rel. diff':>11}")
    worst = 0.0
    for name in a:
        rel = (b[name] - a[name]) / a[name]
        if name != "image":
            worst = max(worst, abs(rel))
        print(f"{name:<12}{a[name]:>10.4f}{b[name]:>11.4f}{100 * rel:>10.2f}%")
    print(f"\nworst wall difference: {100 * worst:.2f}% ({'within' if worst <= 0.03 else 'NOT within'} 3 %)")
    return 0 if worst <= 0.03 else 1


if __name__ == "__main__":
    sys.exit(main())

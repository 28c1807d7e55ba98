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
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
PATH_SCENE = ROOT / "scenes/cornell-box/scene.xml"
RAD_SCENE = ROOT / "scenes/cornell-box/radiosity.xml"
REGIONS = ROOT / "tests/data/cornell/regions.txt"


def regions():
    for line in REGIONS.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, *box = line.split()
            yield name, [float(v) for v in box]


def region_means(exr, res):
    """Mean of (R + G + B) / 3 per region, via oiiotool --cut --printstats."""
    out = {}
    for name, (x0, y0, x1, y1) in regions():
        X0, Y0, X1, Y1 = int(x0 * res), int(y0 * res), int(x1 * res), int(y1 * res)
        cmd = ["oiiotool", str(exr), "--cut", f"{X1 - X0}x{Y1 - Y0}+{X0}+{Y0}", "--printstats"]
        text = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
        avg = [float(v) for v in re.search(r"Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)", text).groups()]
        out[name] = sum(avg) / 3.0
    return out


def render(binary, scene, out, defines, threads):
    cmd = [str(binary), "render", str(scene), "-o", str(out), "--no-progress", "-v"]
    for k, v in defines.items():
        cmd += ["-D", f"{k}={v}"]
    if threads:
        cmd += ["-t", str(threads)]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"effigi failed:\n{run.stdout}\n{run.stderr}")
    seconds = float(re.search(r"samples in ([0-9.]+) s", run.stdout).group(1))
    solve = re.search(r"^radiosity: .*$", run.stderr, re.M)
    return seconds, solve.group(0) if solve else ""


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
    path_sec, _ = render(args.effigi, PATH_SCENE, path_exr, {"spp": args.spp, "res": args.res}, args.threads)
    rad_sec, solve = render(args.effigi, RAD_SCENE, rad_exr,
                            {"spp": 4, "res": args.res, "elements": args.elements, "formfactor": args.formfactor,
                             "solver": args.solver}, args.threads)
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

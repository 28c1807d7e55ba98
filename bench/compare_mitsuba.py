#!/usr/bin/env python3
"""Render scenes/cornell-box/scene.xml with effigi and with Mitsuba 3 in one run on one
machine, then print image and per-wall means of both and their relative differences.

    pip install mitsuba            # once
    python3 bench/compare_mitsuba.py --spp 1024
    python3 bench/compare_mitsuba.py --spp 4096 --write-reference   # refresh the test reference

The regions are those of tests/data/cornell/regions.txt (shared with the end-to-end test).
--write-reference stores Mitsuba's image as tests/data/cornell/mitsuba-reference.exr.
"""
import argparse
import os
import pathlib
import re
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENE = ROOT / "scenes/cornell-box/scene.xml"
REGIONS = ROOT / "tests/data/cornell/regions.txt"
REFERENCE = ROOT / "tests/data/cornell/mitsuba-reference.exr"


def regions():
    for line in REGIONS.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, *box = line.split()
            yield name, [float(v) for v in box]


def region_means(img):
    h, w = img.shape[:2]
    out = {}
    for name, (x0, y0, x1, y1) in regions():
        block = img[int(y0 * h):int(y1 * h), int(x0 * w):int(x1 * w), :3]
        out[name] = block.reshape(-1, 3).mean(axis=0)
    return out


def read_exr(mi, path):
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)


def render_mitsuba(mi, variant, spp, res, out):
    mi.set_variant(variant)
    scene = mi.load_file(str(SCENE), spp=spp, res=res)
    start = time.perf_counter()
    img = mi.render(scene, spp=spp)
    if variant.startswith("llvm"):
        import drjit as dr
        dr.eval(img)
        dr.sync_thread()
    seconds = time.perf_counter() - start
    bmp = mi.Bitmap(img)
    bmp.write(str(out))
    return seconds, res * res * spp / seconds


def render_effigi(binary, spp, res, out, threads):
    cmd = [str(binary), "render", str(SCENE), "-D", f"spp={spp}", "-D", f"res={res}", "-o", str(out), "--no-progress"]
    if threads:
        cmd += ["-t", str(threads)]
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    m = re.search(r"in ([0-9.]+) s .*?: ([0-9.]+) M samples/s.*peak memory (\d+) MiB", run.stdout)
    return float(m.group(1)), float(m.group(2)) * 1e6, int(m.group(3))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--variant", default="scalar_spectral")
    ap.add_argument("--effigi", default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--out", default=ROOT / "out/bench")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--write-reference", action="store_true")
    args = ap.parse_args()

    import mitsuba as mi
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    mi_path, ef_path = out / f"mitsuba-{args.variant}.exr", out / "effigi.exr"

    mi_sec, mi_rate = render_mitsuba(mi, args.variant, args.spp, args.res, mi_path)
    ef_sec, ef_rate, ef_mem = render_effigi(args.effigi, args.spp, args.res, ef_path, args.threads)

    a, b = region_means(read_exr(mi, mi_path)), region_means(read_exr(mi, ef_path))
    print(f"Cornell box {args.res}x{args.res}, {args.spp} spp, on {os.cpu_count()} cores")
    print(f"{'renderer':<28}{'seconds':>9}{'M samples/s':>13}")
    print(f"{'mitsuba ' + mi.__version__ + ' ' + args.variant:<28}{mi_sec:>9.2f}{mi_rate / 1e6:>13.3f}")
    print(f"{'effigi':<28}{ef_sec:>9.2f}{ef_rate / 1e6:>13.3f}   (peak memory {ef_mem} MiB)")
    print(f"throughput ratio effigi / mitsuba: {ef_rate / mi_rate:.2f}")
    print(f"\n{'region':<12}{'mitsuba RGB':>30}{'effigi RGB':>30}{'rel. diff (mean of RGB)':>26}")
    worst = 0.0
    for name in a:
        rel = (b[name].mean() - a[name].mean()) / a[name].mean()
        if name != "image":
            worst = max(worst, abs(rel))
        fa = ", ".join(f"{v:.4f}" for v in a[name])
        fb = ", ".join(f"{v:.4f}" for v in b[name])
        print(f"{name:<12}{fa:>30}{fb:>30}{100 * rel:>25.2f}%")
    print(f"\nworst wall difference: {100 * worst:.2f}%")
    if args.write_reference:
        REFERENCE.parent.mkdir(parents=True, exist_ok=True)
        mi.Bitmap(read_exr(mi, mi_path).astype(np.float32)).write(str(REFERENCE))
        print(f"wrote {REFERENCE}")


if __name__ == "__main__":
    sys.exit(main())

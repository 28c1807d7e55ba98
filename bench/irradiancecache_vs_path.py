#!/usr/bin/env python3
"""Render the Cornell box with the path tracer (scenes/cornell-box/scene.xml) and with
irradiance caching (scenes/cornell-box/irradiancecache.xml, the same camera and
geometry.xml), then print both renderers' times, the cache's record count and memory, peak
memory, and the image and per-wall means with their relative differences.

    python3 bench/irradiancecache_vs_path.py                   # 1024 spp path, resolution 14
    python3 bench/irradiancecache_vs_path.py --resolution 20 --quality 2 --ic-spp 16

The wall regions are those of tests/data/cornell/regions.txt (shared with the end-to-end
test and bench/radiosity_vs_path.py). Targets (issue 13): image mean within 3 %, every
wall within 5 %. EXR files are read with oiiotool, no Python image module needed.
"""
import argparse
import pathlib
import re

from cornell_bench import ROOT, region_means, render

PATH_SCENE = ROOT / "scenes/cornell-box/scene.xml"
IC_SCENE = ROOT / "scenes/cornell-box/irradiancecache.xml"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel of the path tracer")
    ap.add_argument("--ic-spp", type=int, default=16, help="samples per pixel of the irradiance cache's render pass")
    ap.add_argument("--res", type=int, default=256)
    ap.add_argument("--resolution", type=int, default=14, help="θ strata of a record's gather")
    ap.add_argument("--quality", type=float, default=1.0)
    ap.add_argument("--define", action="append", default=[], help="extra -D k=v for the irradiance cache scene")
    ap.add_argument("--effigi", default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--out", default=ROOT / "out/bench")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--reuse-path", action="store_true", help="reuse out/cornell-path.exr of an earlier run")
    ap.add_argument("--path-too", action="store_true", help="with --reference: also render the path tracer and "
                    "print its error against the reference")
    ap.add_argument("--reference", help="compare with this EXR instead of rendering the path tracer (e.g. "
                    "tests/data/cornell/mitsuba-reference.exr, Mitsuba 3 at 2048 spp, 256x256)")
    args = ap.parse_args()

    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path_exr, ic_exr = out / "cornell-path.exr", out / "cornell-irradiancecache.exr"
    path_sec = path_peak = None
    if args.reference:
        if args.path_too:  # the path tracer's own error against the reference, for scale
            path_sec, path_peak, _ = render(args.effigi, PATH_SCENE, path_exr, {"spp": args.spp, "res": args.res},
                                            args.threads)
            p = region_means(path_exr, args.res)
        path_exr = pathlib.Path(args.reference)
    elif not (args.reuse_path and path_exr.exists()):
        path_sec, path_peak, _ = render(args.effigi, PATH_SCENE, path_exr, {"spp": args.spp, "res": args.res},
                                        args.threads)
    defines = {"spp": args.ic_spp, "res": args.res, "resolution": args.resolution, "quality": args.quality}
    defines.update(d.split("=", 1) for d in args.define)
    ic_sec, ic_peak, run = render(args.effigi, IC_SCENE, ic_exr, defines, args.threads)
    cache = re.search(r"^.*irradiancecache: \d+ records.*$", run.stderr, re.M)
    misses = re.search(r"^.*irradiancecache: [0-9.]+ % of.*$", run.stderr, re.M)
    notes = [m.group(0).strip() for m in (cache, misses) if m]
    a, b = region_means(path_exr, args.res), region_means(ic_exr, args.res)
    if path_sec is not None:
        print(f"path tracer: {args.spp} spp in {path_sec:.1f} s, peak memory {path_peak:.0f} MiB")
    print(f"irradiancecache ({', '.join(f'{k}={v}' for k, v in defines.items())}): {ic_sec:.1f} s "
          f"(cache and render), peak memory {ic_peak:.0f} MiB")
    for n in notes:
        print("  " + n)
    both = args.reference and args.path_too
    print(f"{'region':12s} {'reference' if args.reference else 'path':>10s} {'irrcache':>10s} {'relative':>9s}"
          + (f" {'path':>10s} {'relative':>9s}" if both else ""))
    worst = {}
    for name in a:
        rel = (b[name] - a[name]) / a[name]
        worst[name] = rel
        extra = f" {p[name]:10.5f} {100 * (p[name] - a[name]) / a[name]:+8.2f} %" if both else ""
        print(f"{name:12s} {a[name]:10.5f} {b[name]:10.5f} {100 * rel:+8.2f} %{extra}")
    ok = abs(worst["image"]) < 0.03 and all(abs(v) < 0.05 for k, v in worst.items() if k != "image")
    print("targets (image 3 %, walls 5 %):", "met" if ok else "NOT met")


if __name__ == "__main__":
    main()

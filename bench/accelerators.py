#!/usr/bin/env python3
"""Build time and rays/s of every accelerator on the scenes of the accelerator suite.

Runs `effigi-conform --tag accelerator --json` on one thread (so that the jobs do not
compete for the cores while they are timed) and tabulates its `time <scene>` rows:
build time in ms, and millions of closest-hit and any-hit queries per second (single
rays, one thread). bruteforce is shown on the small scenes only; on the large mesh it
answers a few hundred rays, which say little about speed.

    bench/accelerators.py [--quick] [--all-configs] [--bin build/release/bin/effigi-conform]

A benchmark, not a test: run it on a quiet machine and compare runs of the same build.
"""
import argparse
import json
import os
import platform
import re
import subprocess
import sys
import time

ORDER = ["embree", "bvh", "kdtree", "bruteforce"]
FIGURE = re.compile(r"build ([0-9.e+-]+) ms, ([0-9.e+-]+) M/s closest, ([0-9.e+-]+) M/s any")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the --quick scenes (100k-triangle large mesh)")
    ap.add_argument("--all-configs", action="store_true", help="every conformance configuration, not only 'default'")
    ap.add_argument("--bin", default="build/release/bin/effigi-conform")
    args = ap.parse_args()
    os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    if not os.access(args.bin, os.X_OK):
        sys.exit(f"{args.bin} not found: build first (make build)")

    cmd = [args.bin, "--tag", "accelerator", "--threads", "1", "--json", "-", "--out", "out/bench/conform"]
    if args.quick:
        cmd.append("--quick")
    start = time.time()
    run = subprocess.run(cmd, capture_output=True, text=True, env={**os.environ, "EFFIGI_PLUGIN_PATH": ""})
    wall = time.time() - start
    try:
        report = json.loads(run.stdout)
    except json.JSONDecodeError:
        sys.exit(f"effigi-conform gave no JSON (exit {run.returncode}):\n{run.stderr}")

    rows = {}  # (accelerator, config) -> scene -> (build ms, closest M/s, any M/s)
    scenes = []
    for r in report["rows"]:
        if r["verdict"] != "INFO" or not r["check"].startswith("time "):
            continue
        if r["config"] != "default" and not args.all_configs:
            continue
        scene = r["check"][len("time "):]
        if scene not in scenes:
            scenes.append(scene)
        m = FIGURE.search(r["figure"])
        if m:
            rows.setdefault((r["component"].split("/")[-1], r["config"]), {})[scene] = tuple(map(float, m.groups()))

    print(f"effigi accelerators{' (--quick)' if args.quick else ''}: {platform.node()}, {os.cpu_count()} cores, "
          f"{time.strftime('%Y-%m-%d')}; one thread; effigi-conform took {wall:.0f} s, "
          f"{report['failed']} checks failed")
    keys = sorted(rows, key=lambda k: (ORDER.index(k[0]) if k[0] in ORDER else len(ORDER), k[0], k[1] != "default", k[1]))
    width = max(len(s) for s in scenes) if scenes else 10
    for what, col in (("build ms", 0), ("closest-hit M rays/s", 1), ("any-hit M rays/s", 2)):
        names = [k[0] if k[1] == "default" else f"{k[0]} ({k[1]})" for k in keys]
        widths = [max(10, len(n)) for n in names]
        print(f"\n{what:<{width}} " + " ".join(f"{n:>{w}}" for n, w in zip(names, widths)))
        for scene in scenes:
            cells = []
            for k, w in zip(keys, widths):
                v = rows[k].get(scene)
                if v is None or (k[0] == "bruteforce" and scene == "large mesh"):
                    cells.append(f"{'-':>{w}}")
                else:
                    cells.append(f"{v[col]:>{w}.3g}")
            print(f"{scene:<{width}} " + " ".join(cells))
    return 1 if report["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())

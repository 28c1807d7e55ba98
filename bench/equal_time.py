#!/usr/bin/env python3
"""effigi against Mitsuba 3 at equal sample count and at equal time, in one run.

For each scene, Mitsuba renders N spp (per variant) and we record its render time and its
whole-process time (a fresh Python process: interpreter, `import mitsuba`, scene load, JIT,
render, EXR write); effigi renders N spp (`effigi render`, whole process timed the same
way), then renders again for exactly Mitsuba's render time (`effigi render --time`).
Every image is compared with a common high-spp reference (relMSE, mean of
(x-r)^2/(r^2+0.01)). Each effigi/Mitsuba pair runs back to back, alternating, `--repeat`
times; the table shows the median. Prints a Markdown table ready for bench/RESULTS.md.

    python3 bench/equal_time.py --spp 64
    python3 bench/equal_time.py --make-reference cornell-glossy --ref-spp 1024

Needs `pip install mitsuba`; the llvm variant also needs libLLVM (see bench/README.md).
The llvm variant's kernels are cached on disk by Dr.Jit after the first run, as in any
real use; the first (warm-up) render of each variant is not counted.
"""
import argparse
import datetime
import json
import os
import pathlib
import platform
import re
import statistics
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = {
    "cornell-box": (ROOT / "scenes/cornell-box/scene.xml", ROOT / "tests/data/cornell/mitsuba-reference.exr"),
    "cornell-specular": (ROOT / "scenes/cornell-specular/scene.xml", ROOT / "bench/references/cornell-specular.exr"),
    "cornell-glossy": (ROOT / "scenes/cornell-glossy/scene.xml", ROOT / "bench/references/cornell-glossy.exr"),
}
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"

# Run in a child process: the whole-process time of a Mitsuba render.
MITSUBA_CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
import mitsuba as mi
variant, scene, spp, out, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], int(sys.argv[5])
mi.set_variant(variant)
s = mi.load_file(scene, spp=spp)
start = time.perf_counter()
img = mi.render(s, spp=spp, seed=seed)
if variant.startswith("llvm"):
    import drjit as dr
    dr.eval(img)
    dr.sync_thread()
render = time.perf_counter() - start
mi.Bitmap(img).write(out)
print(json.dumps({"render": render, "process_inner": time.perf_counter() - t0}))
"""


def relmse(img, ref):
    d = img[..., :3] - ref[..., :3]
    return float(np.mean(d * d / (ref[..., :3] ** 2 + 0.01)))


def read_exr(path):
    import mitsuba as mi
    return np.array(mi.Bitmap(str(path)), dtype=np.float64)


def mitsuba_render(variant, scene, spp, out, seed=1):
    # seed 1: the reference is rendered with seed 0, and must not share samples with this.
    start = time.perf_counter()
    run = subprocess.run([sys.executable, "-c", MITSUBA_CHILD, variant, str(scene), str(spp), str(out), str(seed)],
                         capture_output=True, text=True, check=True)
    process = time.perf_counter() - start
    return json.loads(run.stdout.strip().splitlines()[-1])["render"], process


def effigi_render(scene, out, extra):
    cmd = [str(ROOT / "build/release/bin/effigi"), "render", str(scene), "-o", str(out), "--no-progress"] + extra
    start = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    process = time.perf_counter() - start
    m = re.search(r"([0-9]+) samples in ([0-9.]+) s", run.stdout)
    return float(m.group(2)), int(m.group(1)), process


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--variants", default="llvm_ad_spectral,scalar_spectral")
    ap.add_argument("--repeat", type=int, default=3, help="back-to-back pairs per scene and variant (median)")
    ap.add_argument("--robust", choices=["default", "on", "off"], default="default",
                    help="Embree's robust mode for both renderers (scene-level embree_use_robust_intersections); "
                         "default: each renderer's own default (effigi on, Mitsuba off)")
    ap.add_argument("--make-reference", metavar="SCENE")
    ap.add_argument("--ref-spp", type=int, default=2048)
    args = ap.parse_args()
    if os.path.exists(LLVM):
        os.environ.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    import mitsuba as mi

    out = ROOT / "out/bench"
    out.mkdir(parents=True, exist_ok=True)
    if args.make_reference:
        scene, ref = SCENES[args.make_reference]
        ref.parent.mkdir(parents=True, exist_ok=True)
        variant = "scalar_spectral"  # llvm would hold every sample of the image in memory at once
        sec, _ = mitsuba_render(variant, scene, args.ref_spp, ref, seed=0)
        print(f"wrote {ref} ({variant}, {args.ref_spp} spp, {sec:.1f} s)")
        return

    variants = [v for v in args.variants.split(",") if v]
    if not os.path.exists(LLVM):
        variants = [v for v in variants if not v.startswith("llvm")]
    print(f"## {datetime.date.today()} — effigi vs Mitsuba {mi.__version__}, {args.spp} spp, "
          f"{os.cpu_count()} cores ({platform.processor() or platform.machine()}), median of {args.repeat}\n")
    print(f"`python3 {' '.join(sys.argv)}`; Embree robust mode: {args.robust}; "
          f"load average before: {os.getloadavg()[0]:.2f}\n")
    print("| scene | renderer | spp | render s | process s | M samples/s | effigi / Mitsuba samples/s "
          "| relMSE (equal spp) | effigi relMSE at Mitsuba's render time | relMSE effigi / Mitsuba at equal time |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    pairs = []  # per scene and variant: the samples/s ratio of each back-to-back pair
    for name in args.scenes.split(","):
        scene, ref_path = SCENES[name]
        if args.robust != "default":
            # A copy beside the original (its includes resolve the same way) that sets
            # Mitsuba's scene-level switch, which both renderers read.
            text = scene.read_text()
            flag = f'<boolean name="embree_use_robust_intersections" value="{"true" if args.robust == "on" else "false"}"/>'
            at = text.index(">", text.index("<scene")) + 1
            copy = scene.parent / f".equal-time-robust-{args.robust}.xml"
            copy.write_text(text[:at] + "\n    " + flag + text[at:])
            scene = copy
        ref = read_exr(ref_path)
        samples = ref.shape[0] * ref.shape[1] * args.spp
        ef_path = out / f"{name}-effigi.exr"
        for v in variants:
            mi_path = out / f"{name}-{v}.exr"
            mitsuba_render(v, scene, args.spp, mi_path)  # warm-up (JIT cache, page cache)
            effigi_render(scene, ef_path, ["-D", f"spp={args.spp}"])
            runs = []
            for _ in range(args.repeat):
                ef = effigi_render(scene, ef_path, ["-D", f"spp={args.spp}"])
                mr = mitsuba_render(v, scene, args.spp, mi_path)
                runs.append((ef, mr))
            ef_sec = statistics.median(r[0][0] for r in runs)
            ef_proc = statistics.median(r[0][2] for r in runs)
            mi_sec = statistics.median(r[1][0] for r in runs)
            mi_proc = statistics.median(r[1][1] for r in runs)
            ef_err = relmse(read_exr(ef_path), ref)
            mi_err = relmse(read_exr(mi_path), ref)
            eq_path = out / f"{name}-effigi-{v}-time.exr"
            effigi_render(scene, eq_path, ["--time", f"{mi_sec:.3f}"])
            eq_err = relmse(read_exr(eq_path), ref)
            print(f"| {name} | effigi | {args.spp} | {ef_sec:.2f} | {ef_proc:.2f} | {samples / ef_sec / 1e6:.3f} | "
                  f"**{mi_sec / ef_sec:.2f}** | {ef_err:.3g} | | |")
            print(f"| {name} | mitsuba {v} | {args.spp} | {mi_sec:.2f} | {mi_proc:.2f} | {samples / mi_sec / 1e6:.3f} "
                  f"| | {mi_err:.3g} | {eq_err:.3g} | **{eq_err / mi_err:.2f}** |")
            sys.stdout.flush()
            pairs.append((name, v, [mr[0] / ef[0] for ef, mr in runs]))
        if args.robust != "default":
            scene.unlink()
    # On a shared machine whole runs slow down together; the ratio within each pair is
    # what the table's ratio of medians estimates, and its spread shows how far to trust it.
    print("\neffigi / Mitsuba samples/s in each back-to-back pair:\n")
    for name, v, r in pairs:
        spread = (max(r) - min(r)) / statistics.median(r)
        print(f"- {name}, {v}: {' '.join(f'{x:.2f}' for x in r)} (median {statistics.median(r):.2f}, "
              f"spread {100 * spread:.0f} %)")
    print(f"\nload average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()

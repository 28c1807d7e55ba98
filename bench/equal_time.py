#!/usr/bin/env python3
"""effigi against Mitsuba 3 at equal sample count and at equal time, in one run.

For each scene, Mitsuba renders N spp (per variant) and we record its time; effigi renders
N spp, then renders again for exactly Mitsuba's time (`effigi render --time`). Every image
is compared with a common high-spp reference (relMSE, mean of (x-r)^2/(r^2+0.01)). Prints a
Markdown table ready for bench/RESULTS.md.

    python3 bench/equal_time.py --spp 64
    python3 bench/equal_time.py --make-reference cornell-specular --ref-spp 2048

Needs `pip install mitsuba`; the llvm variant also needs libLLVM (see bench/README.md).
"""
import argparse
import datetime
import os
import pathlib
import platform
import re
import subprocess
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = {
    "cornell-box": (ROOT / "scenes/cornell-box/scene.xml", ROOT / "tests/data/cornell/mitsuba-reference.exr"),
    "cornell-specular": (ROOT / "scenes/cornell-specular/scene.xml", ROOT / "bench/references/cornell-specular.exr"),
    "cornell-glossy": (ROOT / "scenes/cornell-glossy/scene.xml", ROOT / "bench/references/cornell-glossy.exr"),
}
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def relmse(img, ref):
    d = img[..., :3] - ref[..., :3]
    return float(np.mean(d * d / (ref[..., :3] ** 2 + 0.01)))


def mitsuba_render(mi, variant, scene, spp, out, seed=1):
    # seed 1: the reference is rendered with seed 0, and must not share samples with this.
    mi.set_variant(variant)
    s = mi.load_file(str(scene), spp=spp)
    start = time.perf_counter()
    img = mi.render(s, spp=spp, seed=seed)
    if variant.startswith("llvm"):
        import drjit as dr
        dr.eval(img)
        dr.sync_thread()
    seconds = time.perf_counter() - start
    mi.Bitmap(img).write(str(out))
    return seconds


def effigi_render(scene, out, extra):
    cmd = [str(ROOT / "build/release/bin/effigi"), "render", str(scene), "-o", str(out), "--no-progress"] + extra
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    m = re.search(r"([0-9]+) samples in ([0-9.]+) s", run.stdout)
    return float(m.group(2)), int(m.group(1))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--variants", default="scalar_spectral,llvm_ad_spectral")
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
        sec = mitsuba_render(mi, variant, scene, args.ref_spp, ref, seed=0)
        print(f"wrote {ref} ({variant}, {args.ref_spp} spp, {sec:.1f} s)")
        return

    variants = [v for v in args.variants.split(",") if v]
    if not os.path.exists(LLVM):
        variants = [v for v in variants if not v.startswith("llvm")]
    print(f"## {datetime.date.today()} — effigi vs Mitsuba {mi.__version__}, {args.spp} spp, "
          f"{os.cpu_count()} cores ({platform.processor() or platform.machine()})\n")
    print("| scene | renderer | spp | seconds | M samples/s | relMSE (equal spp) | effigi relMSE at equal time "
          "| relMSE ratio mitsuba / effigi at equal time |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for name in args.scenes.split(","):
        scene, ref_path = SCENES[name]
        ref = np.array(mi.Bitmap(str(ref_path)), dtype=np.float64)
        ef_sec, ef_samples = effigi_render(scene, out / f"{name}-effigi.exr", ["-D", f"spp={args.spp}"])
        ef_img = np.array(mi.Bitmap(str(out / f"{name}-effigi.exr")), dtype=np.float64)
        print(f"| {name} | effigi | {args.spp} | {ef_sec:.2f} | {ef_samples / ef_sec / 1e6:.3f} | "
              f"{relmse(ef_img, ref):.3g} | | |")
        for v in variants:
            mi_path = out / f"{name}-{v}.exr"
            sec = mitsuba_render(mi, v, scene, args.spp, mi_path)
            mi_err = relmse(np.array(mi.Bitmap(str(mi_path)), dtype=np.float64), ref)
            eq_path = out / f"{name}-effigi-{v}-time.exr"
            effigi_render(scene, eq_path, ["--time", f"{sec:.3f}"])
            eq_err = relmse(np.array(mi.Bitmap(str(eq_path)), dtype=np.float64), ref)
            samples = ref.shape[0] * ref.shape[1] * args.spp
            print(f"| {name} | mitsuba {v} | {args.spp} | {sec:.2f} | {samples / sec / 1e6:.3f} | {mi_err:.3g} | "
                  f"{eq_err:.3g} | {mi_err / eq_err:.2f} |")


if __name__ == "__main__":
    main()

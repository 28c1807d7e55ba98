#!/usr/bin/env python3
"""Mutation run over the example scenes: render mutated scenes, end to end.

libFuzzer's XML target (fuzz/) covers the parser and loader in process; this covers what it
cannot: a whole `effigi render` of a mutated scene, so that renderers, films and output
writers meet the absurd values too. Each iteration takes a scene from scenes/ (and the
small test scenes), shrinks its film and sample count, applies 1-4 random mutations
(extreme or malformed values, deleted / duplicated / moved elements, swapped plugin types,
truncation) and renders it with a time limit. A finding is:
  - a crash (a signal, a sanitizer report, std::terminate) or an exit code other than 0/1,
  - a hang (no exit within --timeout seconds),
  - exit 1 without exactly one line on stderr that starts with 'error' (or a file:line),
  - exit 0 with an output image holding NaN or Inf.
Findings are saved with the mutated scene and the command under --out. Seeded: a run is
reproducible from --seed.

  python3 fuzz/mutate_scenes.py --minutes 30 --out build/mutate [--effigi build/release/bin/effigi]
"""
import argparse
import copy
import glob
import os
import random
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

EXTREMES = ["0", "-0", "1", "-1", "1e38", "-1e38", "3.4e38", "1e-38", "1e-45", "nan", "inf", "-inf", "",
            "1e9", "-1e9", "18446744073709551615", "-2147483649", "0x10", "1,2", "1 2 3 4", "abc", "\x01",
            "\u00e9", "1e308", "0.5 nan 1"]


def scene_files():
    files = sorted(glob.glob(os.path.join(ROOT, "scenes", "*", "*.xml")))
    for pattern in ("tests/data/xml/*.xml", "tests/data/renderers/*.xml", "tests/data/emitters/*.xml",
                    "tests/data/wavefront/*.xml", "tests/data/textures/*.xml", "tests/data/shapes/*.xml"):
        files += sorted(glob.glob(os.path.join(ROOT, pattern)))
    return [f for f in files if os.path.getsize(f) < 64 * 1024]


def shrink(root):
    """Small film and few samples, so that an iteration renders in well under a second."""
    for film in root.iter("film"):
        for child in film:
            if child.get("name") in ("width", "height"):
                child.set("value", "16")
    for sampler in root.iter("sampler"):
        for child in sampler:
            if child.get("name") in ("sample_count", "sampleCount"):
                child.set("value", "4")


def mutate(root, rng, types):
    elements = [e for e in root.iter()]
    op = rng.choice(["value", "value", "value", "scale", "delete", "duplicate", "move", "type", "name"])
    e = rng.choice(elements)
    if op in ("value", "scale"):
        candidates = [x for x in elements if "value" in x.attrib]
        if not candidates:
            return
        e = rng.choice(candidates)
        if op == "value":
            e.set("value", rng.choice(EXTREMES))
        else:
            parts = e.get("value").replace(",", " ").split()
            try:
                k = rng.choice([-40, -20, -8, 8, 20, 40])
                e.set("value", " ".join(repr(float(p) * 10.0 ** k) for p in parts))
            except ValueError:
                e.set("value", rng.choice(EXTREMES))
    elif op == "delete" and e is not root:
        for parent in root.iter():
            if e in list(parent):
                parent.remove(e)
                break
    elif op == "duplicate" and e is not root:
        for parent in root.iter():
            if e in list(parent):
                parent.append(copy.deepcopy(e))
                break
    elif op == "move" and e is not root:
        for parent in root.iter():
            if e in list(parent):
                parent.remove(e)
                target = rng.choice([x for x in root.iter()])
                target.append(e)
                break
    elif op == "type" and "type" in e.attrib:
        e.set("type", rng.choice(types))
    elif op == "name" and "name" in e.attrib:
        e.set("name", rng.choice(["radius", "value", "filename", "to_world", "reflectance", "x", ""]))


def finite_image(path):
    import numpy as np
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    data = np.array(mi.Bitmap(path), copy=False)
    return bool(np.all(np.isfinite(data)))


def scene_workdir(workdir, src):
    """A folder beside which the mutated scene finds what its source scene references:
    relative paths (meshes, textures, includes) resolve from the scene file's folder, so
    the folder links to every entry of the source scene's folder."""
    srcdir = os.path.dirname(os.path.abspath(src))
    d = os.path.join(workdir, os.path.relpath(srcdir, ROOT).replace(os.sep, "_"))
    if not os.path.isdir(d):
        os.makedirs(d)
        for entry in os.listdir(srcdir):
            if not entry.endswith(".xml"):
                os.symlink(os.path.join(srcdir, entry), os.path.join(d, entry))
    return d


def run_one(effigi, scene_text, workdir, timeout):
    scene = os.path.join(workdir, "scene.xml")
    out = os.path.join(workdir, "out.exr")
    if os.path.exists(out):
        os.remove(out)
    with open(scene, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(scene_text)
    cmd = [effigi, "render", scene, "-o", out, "--spp", "4", "--no-progress", "-t", "1"]
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=timeout, cwd=workdir)
    except subprocess.TimeoutExpired:
        return "hang", ""
    err = p.stderr.decode("utf-8", "replace")
    lines = [l for l in err.splitlines() if l.strip()]
    if p.returncode < 0 or p.returncode not in (0, 1) or "Sanitizer" in err or "terminate" in err:
        return f"crash (exit {p.returncode})", err[-2000:]
    if p.returncode == 1:
        errors = [l for l in lines if "error" in l.lower()]
        if len(errors) != 1:
            return "error not one line", err[-2000:]
        return None, ""
    if os.path.exists(out) and not finite_image(out):
        return "non-finite output", err[-2000:]
    return None, ""


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--effigi", default=os.path.join(ROOT, "build/release/bin/effigi"))
    ap.add_argument("--minutes", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds before a render counts as a hang")
    ap.add_argument("--out", default=os.path.join(ROOT, "build/mutate"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    workdir = os.path.join(args.out, "work")
    os.makedirs(workdir, exist_ok=True)
    listed = subprocess.run([args.effigi, "list"], capture_output=True, text=True).stdout.splitlines()
    types = sorted({name for line in listed for name in line.split()[1:]}) or ["diffuse"]
    rng = random.Random(args.seed)
    files = scene_files()
    deadline = time.time() + 60.0 * args.minutes
    runs, findings = 0, 0
    while time.time() < deadline:
        src = rng.choice(files)
        try:
            root = ET.parse(src).getroot()
        except ET.ParseError:
            continue
        shrink(root)
        for _ in range(rng.randint(1, 4)):
            mutate(root, rng, types)
        text = ET.tostring(root, encoding="unicode")
        if rng.random() < 0.05:
            text = text[: rng.randint(0, len(text))]
        kind, detail = run_one(args.effigi, text, scene_workdir(workdir, src), args.timeout)
        runs += 1
        if kind is None:
            continue
        findings += 1
        stem = os.path.join(args.out, f"finding-{findings:03d}")
        with open(stem + ".xml", "w", encoding="utf-8", errors="surrogateescape") as f:
            f.write(text)
        with open(stem + ".txt", "w") as f:
            f.write(f"{kind}\nsource: {os.path.relpath(src, ROOT)}\n{detail}\n")
        print(f"[{runs}] {kind}: {stem}.xml (from {os.path.relpath(src, ROOT)})", flush=True)
    print(f"mutate_scenes: {runs} renders in {args.minutes:g} min, {findings} findings (seed {args.seed})")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Run effigi (and Mitsuba 3 when importable) over every scene file under DIR and print a
table: loads / renders / image mean against Mitsuba / first error, then the counts.

    python3 bench/mitsuba_corpus.py /path/to/mitsuba-data --spp 16 --out out/corpus \
            --variant llvm_ad_spectral --reuse

Point DIR at a checkout of the public Mitsuba scene corpus (the `mitsuba-data`
repository: its `scenes/`, `docs/scenes/` and `tests/scenes/` folders); files in folders
named `include` or `fragments` are parts of other scenes and are skipped. Each renderer
runs every scene in its own process, with a time limit, at the same spp (effigi's
`--spp`, Mitsuba's `render(spp=...)`) and the scene's own resolution; the scene files
are not changed. A scene "needs media or polarisation" when it (or a file it includes)
declares a medium or a polarisation plugin: those belong to other work and are counted
apart. The image mean is the mean of R, G and B over the whole image; the relative
difference is (effigi - mitsuba) / mitsuba.
"""
import argparse
import concurrent.futures
import json
import os
import pathlib
import re
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
EFFIGI = ROOT / "build/release/bin/effigi"
SKIP_DIRS = {"include", "fragments"}
MEDIA = re.compile(r'<(medium|volume)\b|type="(polarizer|measured_polarized|pplastic|stokes|retarder|'
                   r'circular)"')
MITSUBA_JOB = r"""
import json, sys, time
import mitsuba as mi
mi.set_variant(sys.argv[1])
res = {"loads": False}
try:
    scene = mi.load_file(sys.argv[2])
    res["loads"] = True
    t = time.perf_counter()
    img = mi.render(scene, spp=int(sys.argv[4]))
    res["seconds"] = time.perf_counter() - t
    mi.Bitmap(img).write(sys.argv[3])
    res["renders"] = True
except Exception as e:
    res["error"] = str(e).strip().splitlines()[-1][:300] if str(e).strip() else type(e).__name__
print("RESULT " + json.dumps(res))
"""


def scene_files(top):
    for p in sorted(pathlib.Path(top).rglob("*.xml")):
        if SKIP_DIRS.isdisjoint(p.relative_to(top).parts[:-1]):
            yield p


def included_text(path, seen=None):
    """The scene's text with the text of files it includes (for the media check)."""
    seen = seen if seen is not None else set()
    if path in seen or not path.exists():
        return ""
    seen.add(path)
    text = path.read_text(errors="replace")
    for inc in re.findall(r'<include\s+filename="([^"]+)"', text):
        text += included_text((path.parent / inc).resolve(), seen)
    return text


def run_effigi(scene, out, spp, timeout, threads):
    cmd = [str(EFFIGI), "render", str(scene), "-o", str(out), "--spp", str(spp), "--no-progress"]
    if threads:
        cmd += ["-t", str(threads)]
    start = time.perf_counter()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=scene.parent)
    except subprocess.TimeoutExpired:
        return {"loads": True, "renders": False, "error": f"time limit ({timeout} s)", "seconds": timeout}
    seconds = time.perf_counter() - start
    lines = [l for l in p.stderr.splitlines() if l.strip()]
    if p.returncode == 0:
        return {"loads": True, "renders": True, "seconds": seconds}
    error = lines[-1] if lines else f"exit code {p.returncode}"
    if p.returncode < 0:
        error = f"CRASH (signal {-p.returncode}): {error}"
    # A scene that got as far as rendering printed the renderer's header before failing.
    return {"loads": "render" in p.stderr.lower() and "error" not in error.lower(), "renders": False,
            "error": error[:300], "crash": p.returncode < 0}


def run_mitsuba(scene, out, spp, timeout, variant):
    try:
        p = subprocess.run([sys.executable, "-c", MITSUBA_JOB, variant, str(scene), str(out), str(spp)],
                           capture_output=True, text=True, timeout=timeout, cwd=scene.parent)
    except subprocess.TimeoutExpired:
        return {"loads": True, "renders": False, "error": f"time limit ({timeout} s)"}
    for line in p.stdout.splitlines():
        if line.startswith("RESULT "):
            return json.loads(line[7:])
    return {"loads": False, "error": (p.stderr.strip().splitlines() or ["no result"])[-1][:300]}


def image_mean(path):
    """Mean of R, G, B over the image and whether every value is finite, by oiiotool
    (no NumPy needed): --printstats gives per-channel averages and NaN/Inf counts."""
    out = subprocess.run(["oiiotool", str(path), "--ch", "0,1,2", "--printstats"], capture_output=True,
                         text=True).stdout
    avg, finite = None, True
    for line in out.splitlines():
        if "Stats Avg:" in line:
            avg = [float(v) for v in line.split(":", 1)[1].split()[:3]]
        elif "NanCount:" in line or "InfCount:" in line:
            finite = finite and all(v == "0" for v in line.split(":", 1)[1].split())
    if avg is None:
        raise RuntimeError(f"oiiotool could not read {path}")
    return sum(avg) / 3.0, finite


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--timeout", type=int, default=120, help="seconds per scene and renderer")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--variant", default="scalar_spectral", help="Mitsuba 3 variant")
    ap.add_argument("--no-mitsuba", action="store_true")
    ap.add_argument("--no-effigi", action="store_true", help="only run Mitsuba (fills the --reuse cache)")
    ap.add_argument("--reuse", action="store_true", help="reuse Mitsuba results of an earlier run in --out")
    ap.add_argument("--only", default="", help="regex on the scene path")
    ap.add_argument("--recheck-spp", type=int, default=0,
                    help="render scenes whose means differ by more than 2 %% again at this spp")
    ap.add_argument("--out", default="out/corpus")
    ap.add_argument("--json", help="also write the rows as JSON")
    args = ap.parse_args()

    try:
        import mitsuba  # noqa: F401
        have_mitsuba = not args.no_mitsuba
    except ImportError:
        have_mitsuba = False
    # Mitsuba's LLVM variants need libLLVM (Debian 12: apt-get install libllvm19).
    llvm = pathlib.Path("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
    if args.variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ and llvm.exists():
        os.environ["DRJIT_LIBLLVM_PATH"] = str(llvm)
    top = pathlib.Path(args.dir).resolve()
    out = pathlib.Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    scenes = [s for s in scene_files(top) if re.search(args.only, str(s.relative_to(top)))]
    for i, scene in enumerate(scenes):
        rel = str(scene.relative_to(top))
        row = {"scene": rel, "media": bool(MEDIA.search(included_text(scene)))}
        row.update(compare(scene, rel, args.spp, args, out, have_mitsuba))
        # At low spp a small or dark image's mean is noisy: a scene outside 2 % is rendered
        # again by both at --recheck-spp, and that comparison is the one reported.
        if args.recheck_spp and abs(row.get("rel_diff", 0.0)) > 0.02:
            row["recheck"] = compare(scene, rel, args.recheck_spp, args, out, have_mitsuba)
        rows.append(row)
        e = row["effigi"]
        print(f"[{i + 1}/{len(scenes)}] {rel}: effigi {'ok' if e.get('renders') else e.get('error')}", file=sys.stderr)

    print_table(rows, have_mitsuba, args)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(rows, indent=1))


def compare(scene, rel, spp, args, out, have_mitsuba):
    """Render the scene with effigi (and Mitsuba) at spp; image means and their ratio."""
    stem = rel.replace("/", "_")[:-4]
    res = {"spp": spp}
    eff_exr = out / f"{stem}-effigi-{spp}.exr"
    res["effigi"] = ({"loads": False, "error": "not run"} if args.no_effigi else
                     run_effigi(scene, eff_exr, spp, args.timeout, args.threads))
    m = {}
    if have_mitsuba:
        # Mitsuba's results do not change between runs of effigi: --reuse keeps them.
        mit_exr = out / f"{stem}-mitsuba-{args.variant}-{spp}.exr"
        cache = out / f"{stem}-mitsuba-{args.variant}-{spp}.json"
        if args.reuse and cache.exists():
            m = json.loads(cache.read_text())
        else:
            m = run_mitsuba(scene, mit_exr, spp, args.timeout, args.variant)
            cache.write_text(json.dumps(m))
        if m.get("renders"):
            m["mean"], _ = image_mean(mit_exr)
        res["mitsuba"] = m
    e = res["effigi"]
    if e.get("renders"):
        e["mean"], e["finite"] = image_mean(eff_exr)
    if e.get("renders") and m.get("renders") and m["mean"] > 0:
        res["rel_diff"] = (e["mean"] - m["mean"]) / m["mean"]
    return res


def yes(v):
    return "yes" if v else "no"


def final_diff(r):
    """The reported difference: the recheck's when there is one."""
    return r["recheck"].get("rel_diff") if "recheck" in r else r.get("rel_diff")


def print_table(rows, have_mitsuba, args):
    print("| scene | effigi loads | effigi renders | Mitsuba loads | mean effigi / Mitsuba - 1 | first error |")
    print("|---|---|---|---|---:|---|")
    for r in rows:
        e, m = r["effigi"], r.get("mitsuba", {})
        d = final_diff(r)
        diff = "" if d is None else f"{100 * d:+.1f} %"
        if "recheck" in r and d is not None:
            diff += f" ({r['recheck']['spp']} spp; {100 * r['rel_diff']:+.1f} % at {args.spp})"
        err = (e.get("error") or "").replace("|", "\\|")
        print(f"| {r['scene']}{' (media/pol.)' if r['media'] else ''} | {yes(e.get('loads'))} | "
              f"{yes(e.get('renders'))} | {yes(m.get('loads')) if have_mitsuba else '-'} | {diff} | {err} |")
    n = len(rows)
    renders = sum(bool(r["effigi"].get("renders")) for r in rows)
    crashes = sum(bool(r["effigi"].get("crash")) for r in rows)
    nonfinite = sum(r["effigi"].get("finite") is False for r in rows)
    print(f"\n{n} scene files; effigi renders {renders}; crashes {crashes}; images with NaN/Inf {nonfinite}; "
          f"spp {args.spp}, time limit {args.timeout} s per scene.")
    if have_mitsuba:
        mload = [r for r in rows if r["mitsuba"].get("loads")]
        target = [r for r in mload if not r["media"]]
        ok = [r for r in target if r["effigi"].get("renders")]
        print(f"Mitsuba 3 ({args.variant}) loads {len(mload)}. Of those, {len(target)} need neither media nor "
              f"polarisation; effigi renders {len(ok)} of them ({100 * len(ok) / max(len(target), 1):.0f} %).")
        both = [r for r in rows if final_diff(r) is not None]
        within = [r for r in both if abs(final_diff(r)) <= 0.02]
        print(f"Both render {len(both)}; image means within 2 %: {len(within)}"
              f"{f' (after re-rendering those outside at {args.recheck_spp} spp)' if args.recheck_spp else ''}.")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Start-up cost of `effigi render`: shared libraries linked and loaded, and wall time.

A render of a tiny scene (1 spp, 16x16 by default) is almost all start-up: loading
shared libraries, reading the scene, loading the modules it names, writing the EXR and
its PNG preview. This script prints one Markdown table row (with --header, the header
first) for bench/RESULTS.md:

  linked     `ldd <effigi>` lines: libraries the binary needs before main() runs
  loaded     libraries the dynamic loader initialised during the render
             (LD_DEBUG=files, "calling init" lines; dlopen'ed modules included)
  OIIO       whether any libOpenImageIO* was among them
  best, median   wall time of the whole command over --repeats runs, in seconds

  bench/startup.py [--repeats 5] [--spp 1] [--res 16] [--scene scenes/cornell-box/scene.xml]
                   [--bin build/release/bin/effigi] [--header]

A benchmark, not a test: run it on a quiet machine; compare rows of the same machine.
"""
import argparse
import datetime
import os
import pathlib
import platform
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent


def render_command(args, out):
    return [str(args.bin), "render", str(args.scene), "-D", f"spp={args.spp}", "-D", f"res={args.res}",
            "-o", str(out), "--no-progress"]


def linked_libraries(binary):
    out = subprocess.run(["ldd", str(binary)], check=True, capture_output=True, text=True).stdout
    return len([line for line in out.splitlines() if line.strip()])


def loaded_libraries(cmd, tmp):
    """Paths of the shared objects the loader initialised while running cmd."""
    log = tmp / "ld"
    env = dict(os.environ, LD_DEBUG="files", LD_DEBUG_OUTPUT=str(log))
    subprocess.run(cmd, check=True, capture_output=True, env=env)
    paths = []
    for f in tmp.glob("ld.*"):  # the loader appends the process id
        for line in f.read_text(errors="replace").splitlines():
            if "calling init:" in line:
                paths.append(line.split("calling init:", 1)[1].strip())
        f.unlink()
    if not paths:
        sys.exit("startup.py: LD_DEBUG produced no output (not glibc, or a secure-execution binary?)")
    return paths


def wall_times(cmd, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        times.append(time.perf_counter() - t0)
    return times


def commit():
    try:
        return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", type=pathlib.Path, default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--scene", type=pathlib.Path, default=ROOT / "scenes/cornell-box/scene.xml")
    ap.add_argument("--spp", type=int, default=1)
    ap.add_argument("--res", type=int, default=16)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--header", action="store_true", help="print the table header first")
    args = ap.parse_args()
    if not args.bin.is_file():
        sys.exit(f"startup.py: {args.bin} not found (build first: make build)")
    if args.repeats < 1:
        sys.exit("startup.py: --repeats must be at least 1")

    with tempfile.TemporaryDirectory(prefix="effigi-startup-") as d:
        tmp = pathlib.Path(d)
        cmd = render_command(args, tmp / "x.exr")
        subprocess.run(cmd, check=True, capture_output=True)  # warm the page cache
        loaded = loaded_libraries(cmd, tmp)
        times = wall_times(cmd, args.repeats)
    oiio = any("libOpenImageIO" in p for p in loaded)

    if args.header:
        print("| date | commit | machine | linked (ldd) | loaded by the render | OpenImageIO loaded "
              f"| wall s, best of {args.repeats} | median s |")
        print("|---|---|---|---:|---:|---|---:|---:|")
    machine = f"{platform.machine()}, {os.cpu_count()} cores"
    print(f"| {datetime.date.today().isoformat()} | {commit()} | {machine} | {linked_libraries(args.bin)} "
          f"| {len(loaded)} | {'yes' if oiio else 'no'} | {min(times):.3f} | {statistics.median(times):.3f} |")


if __name__ == "__main__":
    main()

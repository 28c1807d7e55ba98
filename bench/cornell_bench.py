"""Helpers shared by the *_vs_path.py benchmarks: the wall regions of
tests/data/cornell/regions.txt, EXR means and relMSE via oiiotool (OpenImageIO's
command-line tool, apt-get install openimageio-tools), and one `effigi render` run."""
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
REGIONS = ROOT / "tests/data/cornell/regions.txt"
STATS_AVG = r"Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)"


def regions():
    """(name, [x0, y0, x1, y1]) per region, as fractions of width and height."""
    for line in REGIONS.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            name, *box = line.split()
            yield name, [float(v) for v in box]


def oiio(*args):
    return subprocess.run(["oiiotool", *map(str, args)], capture_output=True, text=True, check=True).stdout


def cut(box, res):
    x0, y0, x1, y1 = (int(v * res) for v in box)
    return ["--cut", f"{x1 - x0}x{y1 - y0}+{x0}+{y0}"]


def mean_rgb(exr, box=None, res=256):
    """Mean of R, G, B over the box (fractions of the res x res image), via --cut --printstats."""
    text = oiio(exr, *(cut(box, res) if box else []), "--printstats")
    return [float(v) for v in re.search(STATS_AVG, text).groups()]


def region_means(exr, res):
    """Mean of (R + G + B) / 3 per region of regions()."""
    return {name: sum(mean_rgb(exr, box, res)) / 3.0 for name, box in regions()}


def relmse(img, ref, box=None, res=256):
    """Mean over pixels and R, G, B of (x - r)^2 / (r^2 + 0.01)."""
    c = cut(box, res) if box else []
    text = oiio(img, *c, "--ch", "R,G,B", ref, *c, "--ch", "R,G,B", "--sub", "--powc", "2",
                ref, *c, "--ch", "R,G,B", "--powc", "2", "--addc", "0.01", "--div", "--printstats")
    return sum(float(v) for v in re.search(STATS_AVG, text).groups()) / 3.0


def render(binary, scene, out, defines, threads, extra=()):
    """Run `effigi render -v`; exit on failure. Returns (seconds, peak MiB, the CompletedProcess);
    seconds and peak MiB are None where the summary line is missing."""
    cmd = [str(binary), "render", str(scene), "-o", str(out), "--no-progress", "-v", *map(str, extra)]
    for k, v in dict(defines).items():
        cmd += ["-D", f"{k}={v}"]
    if threads:
        cmd += ["-t", str(threads)]
    run = subprocess.run(cmd, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"effigi failed: {' '.join(cmd)}\n{run.stdout}\n{run.stderr}")
    seconds = re.search(r"samples in ([0-9.]+) s", run.stdout)
    peak = re.search(r"peak memory ([0-9.]+) MiB", run.stdout)
    return (float(seconds.group(1)) if seconds else None, float(peak.group(1)) if peak else None, run)

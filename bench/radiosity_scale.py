#!/usr/bin/env python3
"""Radiosity at scale: mesh the room of scenes/radiosity-room with 1k, 10k and 100k
elements, run progressive refinement (form factors on demand: memory O(elements)) for a
fixed number of shots, and report element count, meshing and solving time, time per
shot, the unshot power left, and peak memory. Also shows that the full-matrix solvers
refuse a matrix that would not fit (100k² floats = 40 GB), naming the progressive one.

    python3 bench/radiosity_scale.py                  # 1000 10000 100000 elements, 200 shots
    python3 bench/radiosity_scale.py --elements 100000 --shots 1000 --formfactor analytic
"""
import argparse
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
ROOM = ROOT / "scenes/radiosity-room/room.xml"

SCENE = """<scene version="3.0.0">
    <integrator type="radiosity">
        <mesh type="uniform"><integer name="element_count" value="{elements}"/></mesh>
        <formfactor type="{formfactor}"/>
        <solver type="{solver}">
            <integer name="max_iterations" value="{shots}"/>
            <float name="tolerance" value="1e-6"/>
        </solver>
    </integrator>
    <sensor type="perspective">
        <float name="fov" value="82"/>
        <transform name="to_world"><lookat origin="0.4, 1.5, 2.4" target="0, 1.35, -2.5" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
        <film type="hdrfilm"><integer name="width" value="160"/><integer name="height" value="120"/></film>
    </sensor>
    <include filename="{room}"/>
</scene>
"""


def run(binary, elements, shots, formfactor, solver, threads, out):
    with tempfile.TemporaryDirectory() as tmp:
        scene = pathlib.Path(tmp) / "scale.xml"
        scene.write_text(SCENE.format(elements=elements, shots=shots, formfactor=formfactor, solver=solver,
                                      room=ROOM))
        cmd = [str(binary), "render", str(scene), "-o", str(out), "--no-progress", "-v"]
        if threads:
            cmd += ["-t", str(threads)]
        return subprocess.run(cmd, capture_output=True, text=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--elements", type=int, nargs="+", default=[1000, 10000, 100000])
    ap.add_argument("--shots", type=int, default=200)
    ap.add_argument("--formfactor", default="hemicube", choices=["hemicube", "analytic", "montecarlo"])
    ap.add_argument("--effigi", default=ROOT / "build/release/bin/effigi")
    ap.add_argument("--out", default=ROOT / "out/bench")
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"{'target':>8}{'elements':>10}{'mesh s':>8}{'solve s':>9}{'ms/shot':>9}{'shots':>7}"
          f"{'unshot':>10}{'peak MiB':>10}")
    for n in args.elements:
        r = run(args.effigi, n, args.shots, args.formfactor, "progressive", args.threads, out / f"scale-{n}.exr")
        if r.returncode != 0:
            print(f"{n:>8}  failed: {r.stderr.strip().splitlines()[-1]}")
            continue
        line = re.search(r"^radiosity: (\d+) elements.*mesh ([0-9.]+) s; (.*)$", r.stderr, re.M)
        elements, mesh, summary = int(line.group(1)), float(line.group(2)), line.group(3)
        it = int(re.search(r"(?:after|residual [0-9.e+-]+ after) (\d+) iterations", summary).group(1))
        residual = float(re.search(r"residual ([0-9.e+-]+)", summary).group(1))
        solve = float(re.search(r"in ([0-9.]+) s", summary).group(1))
        peak = int(re.search(r"peak memory (\d+) MiB", r.stdout).group(1))
        print(f"{n:>8}{elements:>10}{mesh:>8.2f}{solve:>9.2f}{1000 * solve / max(it, 1):>9.1f}{it:>7}"
              f"{residual:>10.3g}{peak:>10}")
    # The full-matrix solvers on the largest mesh: a clear refusal, not an allocation failure.
    n = max(args.elements)
    r = run(args.effigi, n, 10, args.formfactor, "gaussseidel", args.threads, out / "scale-matrix.exr")
    print(f"\ngaussseidel with {n} elements: exit {r.returncode}: "
          f"{(r.stderr.strip().splitlines() or [''])[-1]}")


if __name__ == "__main__":
    sys.exit(main())

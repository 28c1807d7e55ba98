#!/usr/bin/env python3
"""Peak memory, scene load / BVH build time and 1→2-thread scaling: effigi beside Mitsuba 3.

Every render runs in its own process under GNU time (`/usr/bin/time -f %M ...`), so the
peak resident set (ru_maxrss) of that process alone is measured: effigi, or a child Python
process that imports Mitsuba, loads the scene and renders it. (A child's ru_maxrss also
counts the memory of the process that spawned it at exec time, so it is GNU time, a 2 MB
program, that spawns the renderer, not this script.)

1. Memory and build time, on the Cornell box and on a generated height-field mesh of
   10^7 triangles (10^6 with --quick), all cores: load time (effigi: its "(load X s)",
   which covers XML parsing, creating every component -- the PLY read and vertex normals
   included -- emitter preprocessing and the Embree build; Mitsuba: `mi.load_file`, which
   reads the mesh and builds its Embree BVH), peak RSS after load (effigi: `render
   --dry-run`; Mitsuba: ru_maxrss in the child after load_file) and of the whole run.
2. Scaling: samples/s with 1 and 2 threads on the Cornell box and on a 10^6-triangle mesh
   (10^5 with --quick). effigi: `-t N`; Mitsuba: `dr.set_thread_count(N)` before
   loading, which sizes the nanothread pool that both the scalar renderer (dr::parallel_for)
   and the LLVM backend use. The llvm variant renders once untimed first, so that its
   timed render does not include JIT compilation.

The meshes (binary little-endian PLY: float x, y, z; list uchar int vertex_indices) and
their scene files are written once under out/bench/ and reused.

    python3 bench/memory_scaling.py                # full run (10^7 / 10^6 triangles)
    python3 bench/memory_scaling.py --quick        # smoke test: 10^6 / 10^5 triangles, under a minute
    python3 bench/memory_scaling.py --skip-mitsuba --spp 32

Needs GNU time (/usr/bin/time) and, unless --skip-mitsuba, `pip install mitsuba`; the llvm
variant also needs libLLVM (see bench/README.md). Prints Markdown for bench/RESULTS.md.
"""
import argparse
import datetime
import json
import math
import os
import pathlib
import platform
import re
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
EFFIGI = ROOT / "build/release/bin/effigi"
CORNELL = ROOT / "scenes/cornell-box/scene.xml"
LLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
GNU_TIME = "/usr/bin/time"
TIMEOUT = 3600  # seconds per process: a hang is reported, not waited for forever


# ----------------------------------------------------------------------------------------
# Generated scenes: a height field of n x n vertices, 2 (n-1)^2 triangles.

def grid_size(triangles):
    return int(round(math.sqrt(triangles / 2.0))) + 1


def ply_size(n):
    header = ply_header(n * n, 2 * (n - 1) ** 2)
    return len(header) + 12 * n * n + 13 * 2 * (n - 1) ** 2


def ply_header(nv, nf):
    return (f"ply\nformat binary_little_endian 1.0\ncomment effigi bench/memory_scaling.py height field\n"
            f"element vertex {nv}\nproperty float x\nproperty float y\nproperty float z\n"
            f"element face {nf}\nproperty list uchar int vertex_indices\nend_header\n").encode("ascii")


def write_terrain(path, n):
    """Height field over [-1, 1]^2 (y up), written in row blocks to bound the memory."""
    import numpy as np
    nf = 2 * (n - 1) ** 2
    tmp = path.with_suffix(".tmp")
    with open(tmp, "wb") as f:
        f.write(ply_header(n * n, nf))
        t = np.linspace(-1.0, 1.0, n)
        x = t[None, :]
        for i0 in range(0, n, 512):
            z = t[i0:i0 + 512, None]
            # Smooth hills plus finer ripples, so that the fine tessellation is visible.
            h = (0.12 * np.sin(3.1 * x + 0.7) * np.cos(2.3 * z - 0.4) + 0.05 * np.sin(9.0 * x * z + 1.3)
                 + 0.012 * np.sin(41.0 * x + 29.0 * z) + 0.004 * np.cos(157.0 * x - 113.0 * z))
            v = np.empty((z.shape[0], n, 3), dtype="<f4")
            v[..., 0] = x
            v[..., 1] = h
            v[..., 2] = z
            f.write(v.tobytes())
        face = np.dtype([("n", "u1"), ("i", "<i4", (3,))])  # packed: 13 bytes a face
        j = np.arange(n - 1, dtype=np.int64)[None, :]
        for i0 in range(0, n - 1, 256):
            i = np.arange(i0, min(i0 + 256, n - 1), dtype=np.int64)[:, None]
            a, b, c, d = i * n + j, (i + 1) * n + j, i * n + j + 1, (i + 1) * n + j + 1
            # Both triangles wind counter-clockwise seen from +y: normals face the camera.
            tri = np.stack([np.stack([a, b, c], -1), np.stack([b, d, c], -1)], 2).reshape(-1, 3)
            rec = np.empty(tri.shape[0], dtype=face)
            rec["n"] = 3
            rec["i"] = tri
            f.write(rec.tobytes())
    os.replace(tmp, path)


SCENE_XML = """<?xml version="1.0" encoding="utf-8"?>
<!-- Written by bench/memory_scaling.py: a {tris}-triangle height field under a sky and a
     sun. Loads unchanged in effigi and Mitsuba 3. -->
<scene version="3.0.0">
    <default name="spp" value="4"/>
    <default name="res" value="256"/>
    <default name="max_depth" value="3"/>

    <integrator type="path">
        <integer name="max_depth" value="$max_depth"/>
    </integrator>

    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world">
            <lookat origin="0, 0.9, 1.5" target="0, -0.1, -0.3" up="0, 1, 0"/>
        </transform>
        <sampler type="independent">
            <integer name="sample_count" value="$spp"/>
        </sampler>
        <film type="hdrfilm">
            <integer name="width" value="$res"/>
            <integer name="height" value="$res"/>
            <rfilter type="gaussian"/>
        </film>
    </sensor>

    <shape type="ply">
        <string name="filename" value="{ply}"/>
        <bsdf type="diffuse">
            <rgb name="reflectance" value="0.45, 0.4, 0.3"/>
        </bsdf>
    </shape>

    <emitter type="constant">
        <rgb name="radiance" value="0.3, 0.4, 0.5"/>
    </emitter>
    <emitter type="directional">
        <vector name="direction" value="-0.5, -1, -0.3"/>
        <rgb name="irradiance" value="3, 2.8, 2.5"/>
    </emitter>
</scene>
"""


def mesh_scene(out, triangles):
    """The scene file of a generated mesh of about `triangles` triangles (written once)."""
    n = grid_size(triangles)
    tris = 2 * (n - 1) ** 2
    ply = out / f"terrain-{tris}.ply"
    xml = out / f"terrain-{tris}.xml"
    gen = None
    if not ply.exists() or ply.stat().st_size != ply_size(n):
        start = time.perf_counter()
        write_terrain(ply, n)
        gen = time.perf_counter() - start
    text = SCENE_XML.format(tris=f"{tris:,}", ply=ply.name)
    if not xml.exists() or xml.read_text() != text:
        xml.write_text(text)
    return {"xml": xml, "ply": ply, "tris": tris, "verts": n * n, "gen": gen, "mib": ply.stat().st_size / 2**20}


# ----------------------------------------------------------------------------------------
# Measured processes.

def timed(cmd, env=None):
    """Runs cmd under GNU time; returns rc, stdout, stderr, peak RSS (MiB), wall, CPU s."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as tf:
        full = [GNU_TIME, "-f", "%M %e %U %S", "-o", tf.name] + [str(c) for c in cmd]
        try:
            run = subprocess.run(full, capture_output=True, text=True, env=env, timeout=TIMEOUT)
            rc, out, err = run.returncode, run.stdout, run.stderr
        except subprocess.TimeoutExpired as e:
            return {"rc": "timeout", "out": e.stdout or "", "err": f"killed after {TIMEOUT} s", "rss": None,
                    "wall": TIMEOUT, "cpu": None}
        fields = tf.read().split()
    # GNU time writes "Command exited with non-zero status N" / "Command terminated by signal N"
    # before the format line; the figures are the last four words.
    res = {"rc": rc, "out": out, "err": err, "rss": None, "wall": None, "cpu": None}
    if len(fields) >= 4:
        kib, wall, user, sys_ = fields[-4:]
        res.update(rss=float(kib) / 1024.0, wall=float(wall), cpu=float(user) + float(sys_))
    if any(w == "signal" for w in fields):
        res["rc"] = "signal " + fields[fields.index("signal") + 1]
    return res


def failure(r):
    last = (r["err"].strip().splitlines() or r["out"].strip().splitlines() or ["(no output)"])[-1]
    rss = f", peak RSS {r['rss']:.0f} MiB" if r["rss"] is not None else ""
    return f"exit {r['rc']}{rss}: {last[:300]}"


def effigi_run(scene, spp, res, threads=None, dry=False, out=None):
    cmd = [EFFIGI, "render", scene, "--no-progress", "-D", f"spp={spp}", "-D", f"res={res}"]
    if threads:
        cmd += ["-t", str(threads)]
    cmd += ["--dry-run"] if dry else ["-o", out]
    r = timed(cmd)
    r["cmd"] = " ".join(shlex.quote(str(c)) for c in cmd)
    m = re.search(r"\(load ([0-9.]+) s\)", r["out"])
    r["load"] = float(m.group(1)) if m else None
    m = re.search(r"([0-9]+) samples in ([0-9.]+) s", r["out"])
    if m:
        r["samples"], r["render"] = int(m.group(1)), float(m.group(2))
    r["ok"] = r["rc"] == 0 and (dry or m is not None)
    return r


def mitsuba_run(variant, scene, spp, res, threads=None, warmup=False):
    cmd = [sys.executable, __file__, "--mitsuba-child", variant, str(scene), str(spp), str(res),
           str(threads or 0), "1" if warmup else "0"]
    env = dict(os.environ)
    if os.path.exists(LLVM):
        env.setdefault("DRJIT_LIBLLVM_PATH", LLVM)
    r = timed(cmd, env)
    r["cmd"] = " ".join(shlex.quote(str(c)) for c in cmd)
    lines = [l for l in r["out"].splitlines() if l.startswith("{")]
    r["ok"] = r["rc"] == 0 and bool(lines)
    if r["ok"]:
        r.update(json.loads(lines[-1]))
    return r


def mitsuba_child(variant, scene, spp, res, threads, warmup):
    """Runs inside the measured child process; prints one JSON line."""
    import resource

    def peak():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0

    def cpu():
        ru = resource.getrusage(resource.RUSAGE_SELF)
        return ru.ru_utime + ru.ru_stime

    import drjit as dr
    import mitsuba as mi
    if threads > 0:
        # Before anything is loaded: Mitsuba sizes its Embree device from this pool.
        dr.set_thread_count(threads)
    mi.set_variant(variant)
    rss_setup = peak()
    start = time.perf_counter()
    scene = mi.load_file(scene, spp=spp, res=res)
    if variant.startswith("llvm"):
        dr.sync_thread()
    load = time.perf_counter() - start
    rss_load = peak()

    def render(seed):
        img = mi.render(scene, spp=spp, seed=seed)
        if variant.startswith("llvm"):
            dr.eval(img)
            dr.sync_thread()
        return img

    if warmup:
        render(0)
    c0, t0 = cpu(), time.perf_counter()
    img = render(1)
    seconds = time.perf_counter() - t0
    c1 = cpu()
    size = scene.sensors()[0].film().crop_size()
    import numpy as np
    mean = float(np.mean(np.array(img)[..., :3]))
    print(json.dumps({"rss_setup": rss_setup, "load": load, "rss_load": rss_load, "render": seconds,
                      "render_cpu": c1 - c0, "samples": int(size[0]) * int(size[1]) * spp, "mean": mean,
                      "threads_used": dr.thread_count()}))


# ----------------------------------------------------------------------------------------
# Tables.

def fmt(v, spec, missing="—"):
    return missing if v is None else format(v, spec)


def memory_table(scenes, args, variants, notes):
    print("### Peak memory and load / acceleration-structure build time\n")
    print(f"All cores; {args.mem_spp} spp at {args.res}x{args.res}. *load* is effigi's \"(load X s)\" or "
          "the time of Mitsuba's `mi.load_file`; *peak after load* is effigi `render --dry-run` or Mitsuba's "
          "ru_maxrss right after `load_file`; *peak whole run* is the process's ru_maxrss (GNU time) for "
          "load + render + exit.\n")
    print("| scene | triangles | renderer | load s | peak after load MiB | peak whole run MiB | render s "
          "| M samples/s |")
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    setup, means = {}, []
    for name, sc in scenes:
        tris = f"{sc['tris']:,}" if sc.get("tris") else "8 shapes"
        dry = effigi_run(sc["xml"], args.mem_spp, args.res, dry=True)
        full = effigi_run(sc["xml"], args.mem_spp, args.res, out=args.out / f"mem-{name}-effigi.exr")
        if not dry["ok"]:
            notes.append(f"effigi --dry-run on {name} failed ({failure(dry)}); command: `{dry['cmd']}`")
        if not full["ok"]:
            notes.append(f"effigi render on {name} failed ({failure(full)}); command: `{full['cmd']}`")
        sps = full["samples"] / full["render"] / 1e6 if full["ok"] and full["render"] > 0 else None
        print(f"| {name} | {tris} | effigi | {fmt(dry['load'] if dry['ok'] else None, '.2f', 'FAILED')} "
              f"| {fmt(dry['rss'], '.0f')} | {fmt(full['rss'], '.0f')}{'' if full['ok'] else ' (FAILED)'} "
              f"| {fmt(full.get('render'), '.2f')} | {fmt(sps, '.3f')} |", flush=True)
        if sc.get("tris"):
            # effigi only: the same scene with another accelerator, loaded and not rendered, to
            # split the load time: bruteforce builds nothing (so its row is parsing, the PLY
            # read, vertex normals and the area table), bvh is effigi's own binned-SAH BVH.
            for accel in ("bruteforce", "bvh"):
                alt = sc["xml"].with_name(sc["xml"].stem + f"-{accel}.xml")
                alt.write_text(sc["xml"].read_text().replace(
                    '<integrator type="path">', f'<accelerator type="{accel}"/>\n    <integrator type="path">', 1))
                r = effigi_run(alt, args.mem_spp, args.res, dry=True)
                if not r["ok"]:
                    notes.append(f"effigi --dry-run with accelerator {accel} on {name} failed ({failure(r)}); "
                                 f"command: `{r['cmd']}`")
                print(f"| {name} | {tris} | effigi, accelerator {accel} (load only) "
                      f"| {fmt(r['load'] if r['ok'] else None, '.2f', 'FAILED')} | {fmt(r['rss'], '.0f')} "
                      f"| | | |", flush=True)
        for v in variants:
            r = mitsuba_run(v, sc["xml"], args.mem_spp, args.res)
            if not r["ok"]:
                notes.append(f"Mitsuba {v} on {name} failed ({failure(r)}); command: `{r['cmd']}`")
                print(f"| {name} | {tris} | mitsuba {v} | FAILED | | {fmt(r['rss'], '.0f')} | | |", flush=True)
                continue
            jit = " (incl. JIT)" if v.startswith("llvm") else ""
            print(f"| {name} | {tris} | mitsuba {v} | {r['load']:.2f} | {r['rss_load']:.0f} | {r['rss']:.0f} "
                  f"| {r['render']:.2f}{jit} | {r['samples'] / r['render'] / 1e6:.3f} |", flush=True)
            setup.setdefault(v, []).append(r["rss_setup"])
            means.append(f"{v} {r['mean']:.4g} on {name}")
    print()
    if setup:
        notes.append("Mitsuba's peak RSS after `import mitsuba` and `set_variant`, before loading a scene: "
                     + ", ".join(f"{v} {max(x):.0f} MiB" for v, x in setup.items())
                     + f". Image means (RGB; a check that the renders are alike): {'; '.join(means)}.")


def scaling_table(scenes, args, variants, notes):
    print("### Thread scaling\n")
    print(f"{args.spp} spp at {args.res}x{args.res}. *CPU/wall* is the render's CPU time over its wall time "
          "(effigi: the process's CPU time minus that of a `--dry-run`; Mitsuba: measured around "
          "`mi.render`); below 1.0 / 2.0 the threads were waiting for a core. Mitsuba llvm is timed on its "
          "second render (the first compiles the kernels).\n")
    print("| scene | triangles | renderer | M samples/s, 1 thread | CPU/wall | M samples/s, 2 threads | CPU/wall "
          "| speed-up 2 / 1 |")
    print("|---|---:|---|---:|---:|---:|---:|---:|")
    contended = []
    for name, sc in scenes:
        tris = f"{sc['tris']:,}" if sc.get("tris") else "8 shapes"
        dry = effigi_run(sc["xml"], args.spp, args.res, dry=True)
        rows = []
        cells = {}
        for t in (1, 2):
            r = effigi_run(sc["xml"], args.spp, args.res, threads=t, out=args.out / f"scale-{name}-effigi-{t}.exr")
            if not r["ok"]:
                notes.append(f"effigi -t {t} on {name} failed ({failure(r)}); command: `{r['cmd']}`")
                cells[t] = None
                continue
            cpu = (r["cpu"] - dry["cpu"]) / r["render"] if dry["ok"] and r["render"] > 0 else None
            cells[t] = (r["samples"] / r["render"] / 1e6, cpu)
        rows.append(("effigi", cells))
        for v in variants:
            cells = {}
            for t in (1, 2):
                r = mitsuba_run(v, sc["xml"], args.spp, args.res, threads=t, warmup=v.startswith("llvm"))
                if not r["ok"]:
                    notes.append(f"Mitsuba {v} with {t} thread(s) on {name} failed ({failure(r)}); "
                                 f"command: `{r['cmd']}`")
                    cells[t] = None
                    continue
                if r["threads_used"] != t:
                    notes.append(f"Mitsuba {v} on {name}: asked for {t} thread(s), drjit reports "
                                 f"{r['threads_used']}.")
                cells[t] = (r["samples"] / r["render"] / 1e6, r["render_cpu"] / r["render"])
            rows.append((f"mitsuba {v}", cells))
        for renderer, cells in rows:
            def cell(t):
                return ("FAILED", "") if cells[t] is None else (f"{cells[t][0]:.3f}", fmt(cells[t][1], ".2f"))
            a, b = cell(1), cell(2)
            ratio = f"{cells[2][0] / cells[1][0]:.2f}" if cells[1] and cells[2] else "—"
            if cells[2] and cells[2][1] is not None and cells[2][1] < 1.5:
                contended.append(f"{renderer} on {name} ({cells[2][1]:.2f})")
            print(f"| {name} | {tris} | {renderer} | {a[0]} | {a[1]} | {b[0]} | {b[1]} | {ratio} |", flush=True)
    print()
    if contended:
        notes.append(f"Contended: with 2 threads these got less than 1.5 cores (CPU/wall): {', '.join(contended)}; "
                     "their speed-up measures the machine's load, not the renderer. (Under the kernel's autogroup "
                     "scheduling a 2-thread process gets about one core while another session keeps a core busy.)")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--mitsuba-child":
        variant, scene, spp, res, threads, warmup = sys.argv[2:8]
        mitsuba_child(variant, scene, int(spp), int(res), int(threads), warmup == "1")
        return 0

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="smoke test: 10^6- and 10^5-triangle meshes (not 10^7 / 10^6), 128x128, fewer spp")
    ap.add_argument("--skip-mitsuba", action="store_true", help="effigi only")
    ap.add_argument("--spp", type=int, help="spp of the scaling renders (default 32; --quick 4)")
    ap.add_argument("--mem-spp", type=int, help="spp of the memory renders (default 4; --quick 1)")
    ap.add_argument("--res", type=int, help="image width and height (default 256; --quick 128)")
    ap.add_argument("--big", type=float, help="triangles of the memory mesh (default 1e7; --quick 1e6)")
    ap.add_argument("--mid", type=float, help="triangles of the scaling mesh (default 1e6; --quick 1e5)")
    ap.add_argument("--variants", default="scalar_spectral,llvm_ad_spectral")
    ap.add_argument("--only", choices=["memory", "scaling"], help="one of the two tables")
    ap.add_argument("--out", type=pathlib.Path, default=ROOT / "out/bench")
    args = ap.parse_args()
    q = args.quick
    args.spp = args.spp or (4 if q else 32)
    args.mem_spp = args.mem_spp or (1 if q else 4)
    args.res = args.res or (128 if q else 256)
    args.big = int(args.big or (1e6 if q else 1e7))
    args.mid = int(args.mid or (1e5 if q else 1e6))
    if not os.access(EFFIGI, os.X_OK):
        sys.exit(f"{EFFIGI} not found: build it first (eb effigi-app)")
    if not os.access(GNU_TIME, os.X_OK):
        sys.exit(f"{GNU_TIME} (GNU time) not found: apt-get install time")
    args.out.mkdir(parents=True, exist_ok=True)

    variants = [] if args.skip_mitsuba else [v for v in args.variants.split(",") if v]
    mi_version = None
    if variants:
        probe = subprocess.run([sys.executable, "-c", "import mitsuba; print(mitsuba.__version__)"],
                               capture_output=True, text=True)
        if probe.returncode != 0:
            sys.exit("Mitsuba 3 not importable (pip install mitsuba) -- or pass --skip-mitsuba")
        mi_version = probe.stdout.strip()
        if not os.path.exists(LLVM) and "DRJIT_LIBLLVM_PATH" not in os.environ:
            variants = [v for v in variants if not v.startswith("llvm")]

    notes = []
    meshes = {}
    for key in ("big", "mid"):
        if (args.only == "memory" and key == "mid") or (args.only == "scaling" and key == "big"):
            continue
        sc = mesh_scene(args.out, getattr(args, key))
        meshes[key] = sc
        made = f"generated in {sc['gen']:.1f} s" if sc["gen"] is not None else "reused"
        notes.append(f"{sc['ply'].relative_to(ROOT) if sc['ply'].is_relative_to(ROOT) else sc['ply']}: "
                     f"{sc['tris']:,} triangles, {sc['verts']:,} vertices, {sc['mib']:.0f} MiB ({made}).")

    cmdline = " ".join(shlex.quote(a) for a in ["python3", "bench/memory_scaling.py"] + sys.argv[1:])
    mem_gib = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    load0 = os.getloadavg()
    version = subprocess.run([EFFIGI, "version"], capture_output=True, text=True).stdout.strip()
    built = datetime.datetime.fromtimestamp(EFFIGI.stat().st_mtime).strftime("%Y-%m-%d %H:%M")
    version += f" (build/release/bin/effigi of {built})"
    print(f"## {datetime.date.today()} — peak memory, load/build time and thread scaling "
          f"(`bench/memory_scaling.py`)\n")
    print(f"    {cmdline}\n")
    print(f"{version}{f', Mitsuba {mi_version}' if mi_version else ''}; {os.cpu_count()} cores "
          f"({platform.processor() or platform.machine()}), {mem_gib:.0f} GiB; load average "
          f"{load0[0]:.2f} at the start.\n")
    start = time.time()
    cornell = {"xml": CORNELL, "tris": None}
    if args.only != "scaling":
        memory_table([("cornell-box", cornell), ("terrain", meshes["big"])], args, variants, notes)
    if args.only != "memory":
        scaling_table([("cornell-box", cornell), ("terrain", meshes["mid"])], args, variants, notes)
    load1 = os.getloadavg()
    notes.append(f"Load average {load1[0]:.2f} (1 min) / {load1[1]:.2f} (5 min) at the end; the run took "
                 f"{time.time() - start:.0f} s.")
    for n in notes:
        print(f"- {n}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

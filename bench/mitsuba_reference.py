#!/usr/bin/env python3
"""Render one scene file with Mitsuba 3 and write the image as EXR: the references that
end-to-end tests compare effigi against (tests/data/<area>/mitsuba-reference.exr).

    pip install mitsuba            # once
    python3 bench/mitsuba_reference.py tests/data/textures/scene.xml \
            tests/data/textures/mitsuba-reference.exr --spp 1024 -D res=64

The variant defaults to scalar_spectral (an independent spectral renderer). The spp,
variant and Mitsuba version are printed, so a test's header comment can quote the command.
"""
import argparse
import pathlib
import sys
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--variant", default="scalar_spectral")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("-D", action="append", default=[], metavar="NAME=VALUE",
                    help="scene parameter (Mitsuba's -D)")
    args = ap.parse_args()

    import mitsuba as mi
    mi.set_variant(args.variant)
    params = {}
    for d in args.D:
        name, _, value = d.partition("=")
        params[name] = value
    scene = mi.load_file(str(pathlib.Path(args.scene).resolve()), **params)
    start = time.perf_counter()
    img = mi.render(scene, spp=args.spp, seed=args.seed)
    bmp = mi.Bitmap(img)
    bmp.write(args.out)
    print(f"mitsuba {mi.__version__} {args.variant}: {args.scene} -> {args.out}, "
          f"{args.spp} spp, {time.perf_counter() - start:.1f} s", file=sys.stderr)


if __name__ == "__main__":
    main()

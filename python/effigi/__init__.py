"""effigi from Python: load Mitsuba-3-grammar scenes, render them into NumPy arrays,
inspect the component registry and run the conformance suites.

    import effigi
    scene = effigi.load_file("scenes/cornell-box/scene.xml", res=128)  # $res, as -D res=128
    image = scene.render(spp=16, seed=1)       # float32, (height, width, 3), linear sRGB
    xyz = scene.render(spp=16, space="xyz")
    effigi.components()                        # ["accelerator/bruteforce", ...]
    effigi.info("bsdf/diffuse")["parameters"]
    effigi.conform("bsdf/diffuse")["failed"]   # 0

Errors in a scene or a call raise effigi.Error (a RuntimeError) whose message names the
file and line, as the CLI's do.
"""

import os as _os

from ._effigi import Error, Scene, components, info, version
from ._effigi import _load_file, _load_string, _read_image, _write_png

__all__ = ["Error", "Scene", "load_file", "load_string", "components", "info", "conform", "read_image",
           "write_png", "version"]
__version__ = version()


def _define(value):
    """A $-default as the XML would write it: true/false for booleans, else str()."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def _defines(defaults):
    return {name: _define(value) for name, value in defaults.items()}


def load_file(path, *, spectral_bins=None, **defaults):
    """Load a scene file. Keyword arguments set its $-defaults as `effigi render -D name=value`
    does (override a <default>, or supply one the scene does not declare).
    spectral_bins=N makes the film record N spectral bins (for render(spectral=True))."""
    return _load_file(_os.fspath(path), _defines(defaults), spectral_bins)


def load_string(xml, *, spectral_bins=None, **defaults):
    """Load a scene from XML text (named "<string>" in errors; relative file names resolve
    against the working directory). Keywords as for load_file."""
    return _load_string(xml, _defines(defaults), spectral_bins)


def read_image(path):
    """R, G, B of an image file as a height x width x 3 float32 array: EXR through OpenEXR
    (e.g. what `effigi render` writes), other formats through OpenImageIO (8-bit files give
    code values / 255)."""
    return _read_image(_os.fspath(path))


def write_png(path, image):
    """Write a height x width x 3 linear-RGB array as an 8-bit sRGB PNG (clamped to [0, 1])."""
    import numpy
    _write_png(_os.fspath(path), numpy.ascontiguousarray(image, dtype=numpy.float32))


def conform(component, *, tag=None, quick=True, seed=None, threads=0, out_dir="conform-out"):
    """Run the conformance suite of a component ("bsdf/diffuse", or "diffuse" with tag=...),
    in every configuration its schema declares, as effigi-conform does. Returns the report
    as a dict with the keys of `effigi-conform --json`: passed, failed, skipped, info,
    statistical_tests, alpha_single, seconds, power and rows (one dict per check: tag,
    component, config, check, verdict, figure, p_value, detail, files, seconds).
    quick=True is `--quick` (what `make test` runs); images of failing chi-square tests go
    to out_dir."""
    from . import _conform
    if "/" in component:
        prefix, component = component.split("/", 1)
        if tag is not None and tag != prefix:
            raise Error(f"conform: tag '{tag}' does not match '{prefix}/{component}'")
        tag = prefix
    if seed is None:
        seed = _conform.default_seed()
    return _conform.run(tag or "", component, bool(quick), int(seed), int(threads), _os.fspath(out_dir))

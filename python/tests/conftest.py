"""Shared set-up of the effigi module's tests: the repository root, the CLI, a small scene.

Run through ctest (`make test`: the test python:pytest sets PYTHONPATH to the build's
python/ folder and EFFIGI_APP to the CLI), or by hand:
    PYTHONPATH=build/release/python python3 -m pytest python/tests
"""
import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CORNELL = ROOT / "scenes" / "cornell-box" / "scene.xml"

# A sphere on a floor under a constant sky, small enough to render in milliseconds.
SMALL_SCENE = """<scene version="3.0.0">
    <default name="alpha" value="0.2"/>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 1, 4" target="0, 0.3, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/>
            <integer name="height" value="24"/>
        </film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.8, 0.9, 1.0"/></emitter>
    <shape type="sphere">
        <point name="center" x="0" y="0.5" z="0"/>
        <float name="radius" value="0.5"/>
        <bsdf type="roughconductor">
            <string name="material" value="Au"/>
            <float name="alpha" value="$alpha"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><rotate x="1" angle="-90"/><scale value="3"/></transform>
        <bsdf type="diffuse"/>
    </shape>
</scene>
"""


@pytest.fixture(scope="session")
def effigi_app():
    """The CLI: EFFIGI_APP (set by ctest), else the release build's, else skip."""
    app = os.environ.get("EFFIGI_APP") or str(ROOT / "build" / "release" / "bin" / "effigi")
    if not (os.path.isfile(app) and os.access(app, os.X_OK)):
        found = shutil.which("effigi")
        if not found:
            pytest.skip("the effigi CLI is not built (EFFIGI_APP unset, build/release/bin/effigi absent)")
        app = found
    return app

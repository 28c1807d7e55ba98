"""examples/python/roughness_sweep.py, run small; only where matplotlib is installed (the
script's fallback without it writes PNGs, checked here by forcing it)."""
import os
import subprocess
import sys

import pytest

from conftest import ROOT

SCRIPT = ROOT / "examples" / "python" / "roughness_sweep.py"


def run(tmp_path, *extra):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(SCRIPT), "--res", "24", "--spp", "2", "--steps", "3",
                           "--out", str(tmp_path), *extra], env=env, capture_output=True, text=True, check=True)


def test_sweep_plots_with_matplotlib(tmp_path):
    pytest.importorskip("matplotlib")
    run(tmp_path)
    assert (tmp_path / "roughness_sweep.png").is_file()


def test_sweep_without_matplotlib_writes_pngs(tmp_path):
    out = run(tmp_path, "--no-plot")
    assert sorted(p.name for p in tmp_path.glob("alpha_*.png")) == ["alpha_0.010.png", "alpha_0.305.png",
                                                                      "alpha_0.600.png"]
    assert "PNG" in out.stdout

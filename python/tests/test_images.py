"""Image files through effigi's own reader and writer (no imageio, no OpenCV)."""
import numpy as np
import pytest

import effigi


def test_png_written_and_read_back(tmp_path):
    ramp = np.zeros((4, 5, 3), dtype=np.float32)
    ramp[..., 0] = np.linspace(0, 1, 5)  # linear values, written sRGB-encoded
    ramp[..., 2] = 2.0                    # clamped to 1
    png = tmp_path / "ramp.png"
    effigi.write_png(png, ramp)
    back = effigi.read_image(png)         # 8-bit code values / 255
    assert back.shape == (4, 5, 3)
    assert back[0, 0, 0] == 0 and back[0, -1, 0] == 1 and (back[..., 2] == 1).all()
    # sRGB encoding of 0.25 (IEC 61966-2-1): 0.537 -> code 137.
    assert abs(back[0, 1, 0] - 137 / 255) <= 1 / 255


def test_bad_image_arguments(tmp_path):
    with pytest.raises(effigi.Error, match="float32"):
        effigi.write_png(tmp_path / "x.png", np.zeros((4, 4)))
    with pytest.raises(effigi.Error, match="missing.exr"):
        effigi.read_image(tmp_path / "missing.exr")

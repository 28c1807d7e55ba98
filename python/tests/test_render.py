"""Loading and rendering from Python: shapes, colour spaces, spectral bins, and the same
image as the CLI for the same seed and sample count."""
import subprocess

import numpy as np
import pytest

import effigi
from conftest import CORNELL, SMALL_SCENE


def test_cornell_box_renders_with_the_film_size():
    scene = effigi.load_file(CORNELL)
    width, height = scene.size
    image = scene.render(spp=4, seed=1)
    assert image.shape == (height, width, 3) == (256, 256, 3)
    assert image.dtype == np.float32
    assert np.isfinite(image).all()
    assert image.mean() > 0.0
    assert scene.stats["samples"] == 4 * width * height
    # No copy: the array is a view on the film's developed pixels, owned by a capsule.
    assert not image.flags["OWNDATA"] and image.base is not None


def test_defaults_are_the_cli_defines():
    scene = effigi.load_file(str(CORNELL), res=24, spp=2)
    assert scene.size == (24, 24)
    assert scene.render().shape == (24, 24, 3)  # spp=None: the sampler's sample_count ($spp)
    assert scene.stats["samples"] == 2 * 24 * 24


def test_image_equals_the_cli_render(tmp_path, effigi_app):
    exr = tmp_path / "cli.exr"
    subprocess.run([effigi_app, "render", str(CORNELL), "-D", "res=48", "--spp", "4", "--seed", "7",
                    "--no-progress", "-o", str(exr)], check=True, capture_output=True)
    reference = effigi.read_image(exr)
    image = effigi.load_file(CORNELL, res=48).render(spp=4, seed=7)
    assert reference.shape == image.shape == (48, 48, 3)
    # The CLI's EXR is float16 (relative precision 2^-11); the sums' order across tiles
    # may differ in the last float bit. Another seed would differ by the noise (~10 %).
    np.testing.assert_allclose(image, reference, rtol=2e-3, atol=1e-4)
    other = effigi.load_file(CORNELL, res=48).render(spp=4, seed=8)
    assert np.abs(other - reference).max() > 1e-2


def test_colour_spaces_are_one_linear_map_of_xyz():
    scene = effigi.load_string(SMALL_SCENE)
    assert scene.colorspace == "srgb"
    rgb = scene.render(spp=2, seed=3, space="srgb-linear")
    xyz = scene.render(spp=2, seed=3, space="xyz")
    default = scene.render(spp=2, seed=3)
    np.testing.assert_allclose(default, rgb, rtol=1e-5, atol=1e-6)
    # Y of linear sRGB (IEC 61966-2-1 primaries, D65).
    y = rgb @ np.array([0.2126729, 0.7151522, 0.0721750], dtype=np.float32)
    np.testing.assert_allclose(xyz[..., 1], y, rtol=1e-4, atol=1e-5)
    rec2020 = scene.render(spp=2, seed=3, space="rec2020")
    assert not np.allclose(rec2020, rgb)  # other primaries: other numbers, same luminance
    y2020 = rec2020 @ np.array([0.2627002, 0.6779981, 0.0593017], dtype=np.float32)
    np.testing.assert_allclose(y2020, xyz[..., 1], rtol=1e-3, atol=1e-5)
    with pytest.raises(effigi.Error, match="space 'cmyk'"):
        scene.render(spp=1, space="cmyk")


def test_load_string_and_its_defaults():
    smooth = effigi.load_string(SMALL_SCENE, alpha=0.01).render(spp=4, seed=2)
    rough = effigi.load_string(SMALL_SCENE, alpha=0.6).render(spp=4, seed=2)
    assert smooth.shape == rough.shape == (24, 32, 3)
    assert np.isfinite(smooth).all() and smooth.mean() > 0
    assert np.abs(smooth - rough).mean() > 1e-3  # the roughness reached the BSDF


def test_spectral_bins():
    scene = effigi.load_file(CORNELL, res=16, spectral_bins=8)
    assert scene.spectral_bins == 8
    bins, wavelengths = scene.render(spp=2, seed=1, spectral=True)
    assert bins.shape == (16, 16, 8) and bins.dtype == np.float32
    assert wavelengths.shape == (8,)
    assert np.all(np.diff(wavelengths) > 0) and 360 < wavelengths[0] and wavelengths[-1] < 830
    np.testing.assert_allclose(np.diff(wavelengths), (830 - 360) / 8, rtol=1e-6)
    assert np.isfinite(bins).all() and bins.min() >= 0 and bins.mean() > 0
    with pytest.raises(effigi.Error, match="records no spectral bins"):
        effigi.load_file(CORNELL, res=16).render(spp=1, spectral=True)


def test_bad_arguments_raise():
    scene = effigi.load_string(SMALL_SCENE)
    with pytest.raises(effigi.Error, match="spp"):
        scene.render(spp=0)
    with pytest.raises(effigi.Error, match="threads"):
        scene.render(spp=1, threads=-2)

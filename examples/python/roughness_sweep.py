"""Sweep the roughness of a gold sphere and plot the renders side by side.

A plain script that also runs cell by cell in Jupyter (`%run` it, or paste the cells
marked `# %%`). The scene is inline XML whose roughconductor takes its GGX alpha from the
$-default `alpha`; each render passes another one, as `effigi render -D alpha=...` would.

    pip install ./python            # once (README), or PYTHONPATH=build/release/python
    python3 examples/python/roughness_sweep.py --steps 5 --spp 64

With matplotlib (not an effigi dependency) it shows the images, or saves them as
<out>/roughness_sweep.png without a display; without matplotlib it says so and writes one
PNG per roughness through effigi.write_png instead.
"""
# %%
import argparse
import pathlib

import numpy as np

import effigi

SCENE = """<scene version="3.0.0">
    <default name="alpha" value="0.2"/>
    <default name="res" value="128"/>
    <integrator type="path"><integer name="max_depth" value="6"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="35"/>
        <transform name="to_world"><lookat origin="0, 1.2, 4" target="0, 0.45, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="$res"/>
            <integer name="height" value="$res"/>
        </film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.25, 0.3, 0.4"/></emitter>
    <shape type="rectangle">
        <transform name="to_world">
            <scale value="0.6"/><rotate x="1" angle="90"/><translate value="-1, 2.5, 1"/>
        </transform>
        <emitter type="area"><rgb name="radiance" value="12, 11, 9"/></emitter>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.5" z="0"/>
        <float name="radius" value="0.5"/>
        <bsdf type="roughconductor">
            <string name="material" value="Au"/>
            <string name="distribution" value="ggx"/>
            <float name="alpha" value="$alpha"/>
        </bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
    </shape>
</scene>
"""


def render_sweep(alphas, res, spp, seed=1):
    """One linear-sRGB image per roughness, same seed: only the BSDF changes."""
    images = []
    for alpha in alphas:
        scene = effigi.load_string(SCENE, alpha=alpha, res=res)
        images.append(scene.render(spp=spp, seed=seed))
    return images


def display(image):
    """Linear RGB -> sRGB-encoded values in [0, 1] for matplotlib (IEC 61966-2-1)."""
    x = np.clip(image, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=5, help="number of roughness values")
    ap.add_argument("--min", type=float, default=0.01, help="smallest GGX alpha")
    ap.add_argument("--max", type=float, default=0.6, help="largest GGX alpha")
    ap.add_argument("--res", type=int, default=128, help="image width and height")
    ap.add_argument("--spp", type=int, default=32, help="samples per pixel")
    ap.add_argument("--out", default="out/roughness-sweep", help="folder for the saved images")
    ap.add_argument("--no-plot", action="store_true", help="write PNGs even when matplotlib is there")
    args = ap.parse_args()

    # %%
    alphas = np.linspace(args.min, args.max, args.steps)
    images = render_sweep(alphas, args.res, args.spp)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    # %%
    plt = None
    if not args.no_plot:
        try:
            import matplotlib.pyplot as plt  # imported here: optional
        except ImportError:
            print("matplotlib is not installed: writing one PNG per roughness instead")
    if plt is None:
        for alpha, image in zip(alphas, images):
            path = out / f"alpha_{alpha:.3f}.png"
            effigi.write_png(path, image)
            print(f"wrote PNG {path}")
        return
    fig, axes = plt.subplots(1, len(images), figsize=(2.6 * len(images), 2.9), squeeze=False)
    for ax, alpha, image in zip(axes[0], alphas, images):
        ax.imshow(display(image))
        ax.set_title(f"GGX alpha = {alpha:.3g}")
        ax.axis("off")
    fig.tight_layout()
    path = out / "roughness_sweep.png"
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")
    if plt.get_backend().lower() not in ("agg", "pdf", "svg", "ps", "cairo", "template"):
        plt.show()


if __name__ == "__main__":
    main()

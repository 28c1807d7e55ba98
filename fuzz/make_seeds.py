#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets, fuzz/corpus/<target>/: a handful of tiny,
valid inputs per target that between them use each feature of the format (every PLY
encoding and list type, OBJ index forms, both .serialized versions and precisions, ...),
so that the fuzzer starts from inputs that get past the first checks.

    python3 fuzz/make_seeds.py        (images other than PNG need Mitsuba 3: pip mitsuba)

The XML target copies every seed of every target into its scratch folder, so the scene
seeds name the other seeds by their bare file names (names are unique across targets).
Scene seeds hold no '/' outside tags: the XML target skips inputs that could name files
outside its folder. Two seeds are copies of test data: tests/data/textures/quad.ply and
grid.png, tests/data/shapes/prism.serialized.
"""
import pathlib
import shutil
import struct
import zlib

FUZZ = pathlib.Path(__file__).resolve().parent
ROOT = FUZZ.parent
CORPUS = FUZZ / "corpus"


def write(target, name, data):
    d = CORPUS / target
    d.mkdir(parents=True, exist_ok=True)
    (d / name).write_bytes(data.encode() if isinstance(data, str) else data)


# ---- PLY ---------------------------------------------------------------------------------
def ply_binary(endian, fmt_name):
    e = "<" if endian == "le" else ">"
    header = (f"ply\nformat {fmt_name} 1.0\ncomment tiny test mesh\n"
              "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
              "property uchar red\nproperty uchar green\nproperty uchar blue\n"
              "element face 2\nproperty list uchar int vertex_indices\nproperty float quality\n"
              "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n")
    body = b""
    for (x, y), (u, v) in zip([(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 0), (1, 0), (1, 1), (0, 1)]):
        body += struct.pack(e + "8f3B", x, y, 0, 0, 0, 1, u, v, 200, 100, 50)
    body += struct.pack(e + "B3if", 3, 0, 1, 2, 0.5) + struct.pack(e + "B3if", 3, 0, 2, 3, 0.25)
    body += struct.pack(e + "2i", 0, 1)
    return header.encode() + body


def ply_seeds():
    shutil.copy(ROOT / "tests/data/textures/quad.ply", CORPUS / "ply" / "quad.ply")
    write("ply", "quad-le.ply", ply_binary("le", "binary_little_endian"))
    write("ply", "quad-be.ply", ply_binary("be", "binary_big_endian"))
    write("ply", "pentagon.ply",
          "ply\nformat ascii 1.0\nelement vertex 5\nproperty double x\nproperty double y\nproperty double z\n"
          "property double s\nproperty double t\n"
          "element face 1\nproperty list ushort uint vertex_index\nend_header\n"
          "0 0 0 0 0\n1 0 0 1 0\n1.5 1 0 1 1\n0.5 1.6 0 0.5 1\n-0.5 1 0 0 1\n5 0 1 2 3 4\n")


# ---- OBJ ---------------------------------------------------------------------------------
def obj_seeds():
    write("obj", "tri.obj", "# one triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    write("obj", "quad-vtn.obj",
          "o quad\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
          "s off\nf 1/1/1 2/2/1 3/3/1 4/4/1\n")
    write("obj", "relative.obj",
          "mtllib none.mtl\ng a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl red\nf -4 -3 -2\n"
          "g b\nvn 0 0 1\nf 1//1 3//1 4//1\nv 2 2 2 1\nl 1 2\np 3\n")


# ---- .serialized -------------------------------------------------------------------------
def serialized_mesh(version, positions, faces, normals=None, uvs=None, colors=None, double=False, name="m"):
    flags = (0x1 if normals else 0) | (0x2 if uvs else 0) | (0x8 if colors else 0) | (0x2000 if double else 0)
    real = "d" if double else "f"
    data = struct.pack("<I", flags)
    if version == 4:
        data += name.encode() + b"\0"
    data += struct.pack("<QQ", len(positions), len(faces))
    for arr in (positions, normals, uvs, colors):
        if arr:
            for v in arr:
                data += struct.pack("<%d%s" % (len(v), real), *v)
    for f in faces:
        data += struct.pack("<3I", *f)
    return struct.pack("<HH", 0x041C, version) + zlib.compress(data, 9)


def serialized_file(version, meshes):
    out, offsets = b"", []
    for m in meshes:
        offsets.append(len(out))
        out += m
    entry = "<Q" if version == 4 else "<I"
    for o in offsets:
        out += struct.pack(entry, o)
    return out + struct.pack("<I", len(meshes))


def serialized_seeds():
    shutil.copy(ROOT / "tests/data/shapes/prism.serialized", CORPUS / "serialized" / "prism.serialized")
    tri = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    write("serialized", "tri-v3-double.serialized",
          serialized_file(3, [serialized_mesh(3, tri, [(0, 1, 2)], normals=[(0, 0, 1)] * 3, double=True),
                              serialized_mesh(3, tri, [(2, 1, 0)], uvs=[(0, 0), (1, 0), (0, 1)], double=True)]))
    write("serialized", "tri-v4-colors.serialized",
          serialized_file(4, [serialized_mesh(4, tri, [(0, 1, 2)], uvs=[(0, 0), (1, 0), (0, 1)],
                                              colors=[(1, 0, 0), (0, 1, 0), (0, 0, 1)], name="coloured")]))


# ---- spectra -----------------------------------------------------------------------------
def spd_seeds():
    write("spd", "ramp.spd", "# wavelength (nm)  value\n380 0.1\n480 0.3   # blue\n580 0.6\n680 0.8\n780 0.9\n")
    write("spd", "flat.spd", "360\t0.5\r\n830\t0.5\r\n")
    write("spd", "sci.spd", "\n# scientific notation, signs\n+4.0e2 1e-3\n5.5E2 -0.0\n700.5 .25\n")


# ---- .vol --------------------------------------------------------------------------------
def vol(res, channels, values, bbox=(0, 0, 0, 1, 1, 1)):
    head = b"VOL" + bytes([3]) + struct.pack("<i3ii6f", 1, *res, channels, *bbox)
    return head + struct.pack("<%df" % len(values), *values)


def vol_seeds():
    n = 4  # a sphere of radius 0.35 around the centre of the unit cube
    vals = [((i / (n - 1) - 0.5) ** 2 + (j / (n - 1) - 0.5) ** 2 + (k / (n - 1) - 0.5) ** 2) ** 0.5 - 0.35
            for k in range(n) for j in range(n) for i in range(n)]
    write("vol", "sphere4.vol", vol((n, n, n), 1, vals))
    write("vol", "plane2.vol", vol((2, 2, 2), 1, [-0.5, -0.5, -0.5, -0.5, 0.5, 0.5, 0.5, 0.5], (-1, -1, -1, 1, 1, 1)))
    write("vol", "rgb2x1x3.vol", vol((2, 1, 3), 3, [0.1 * i for i in range(18)]))


# ---- images ------------------------------------------------------------------------------
def image_seeds():
    shutil.copy(ROOT / "tests/data/textures/grid.png", CORPUS / "image" / "grid.png")
    try:
        import mitsuba as mi
        import numpy as np
    except ImportError:
        print("make_seeds: no Mitsuba 3: only the PNG image seed is written")
        return
    mi.set_variant("scalar_rgb")
    px = np.array([[[0.1, 0.5, 0.9], [1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0], [0.0, 0.0, 4.0]]], dtype=np.float32)
    d = CORPUS / "image"
    b = mi.Bitmap(px)
    b.write(str(d / "tiny.exr"))
    b.write(str(d / "tiny.hdr"))
    b.write(str(d / "tiny.pfm"))
    b8 = b.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, True)
    b8.write(str(d / "tiny.jpg"))
    b8.write(str(d / "tiny.ppm"))
    rgba = np.concatenate([px, np.full((2, 2, 1), 0.5, np.float32)], axis=2)
    mi.Bitmap(rgba, mi.Bitmap.PixelFormat.RGBA).convert(
        mi.Bitmap.PixelFormat.RGBA, mi.Struct.Type.UInt16, True).write(str(d / "rgba16.png"))


# ---- scenes ------------------------------------------------------------------------------
SENSOR = """    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
"""


def scene(body, version="3.0.0", sensor=SENSOR):
    return f'<scene version="{version}">\n{sensor}{body}</scene>\n'


def xml_seeds():
    write("xml", "minimal.xml", scene('    <shape type="sphere"/>\n'))
    write("xml", "meshes.xml", scene("""    <default name="mat" value="rough"/>
    <bsdf type="roughconductor" id="rough"><string name="material" value="Au"/><float name="alpha" value="0.2"/></bsdf>
    <shape type="obj"><string name="filename" value="quad-vtn.obj"/><ref id="$mat"/></shape>
    <shape type="ply"><string name="filename" value="quad-le.ply"/><boolean name="face_normals" value="true"/>
        <transform name="to_world"><rotate x="1" angle="30"/><translate value="0, 0, -1"/></transform>
        <bsdf type="twosided"><bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/></bsdf></bsdf>
    </shape>
    <shape type="serialized"><string name="filename" value="prism.serialized"/><integer name="shape_index" value="1"/>
        <emitter type="area"><blackbody name="radiance" temperature="3200K"/></emitter>
    </shape>
    <shape type="sdfgrid"><string name="filename" value="sphere4.vol"/></shape>
"""))
    write("xml", "textures.xml", scene("""    <emitter type="envmap"><string name="filename" value="tiny.exr"/><float name="scale" value="0.5"/></emitter>
    <texture type="checkerboard" id="checks">
        <transform name="to_uv"><scale x="2" y="2"/></transform>
    </texture>
    <shape type="rectangle">
        <bsdf type="diffuse"><texture type="bitmap" name="reflectance">
            <string name="filename" value="grid.png"/><string name="filter_type" value="nearest"/></texture></bsdf>
    </shape>
    <shape type="ply"><string name="filename" value="quad.ply"/>
        <bsdf type="blendbsdf"><ref name="weight" id="checks"/>
            <bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance">
                <string name="name" value="vertex_color"/></texture></bsdf>
            <bsdf type="dielectric"><string name="int_ior" value="bk7"/></bsdf>
        </bsdf>
    </shape>
"""))
    write("xml", "spectra.xml", scene("""    <emitter type="point"><spectrum name="intensity" filename="ramp.spd"/><point name="position" value="0, 2, 2"/></emitter>
    <emitter type="spot"><spectrum name="intensity" value="d65"/><float name="cutoff_angle" value="20"/></emitter>
    <shape type="cube"><bsdf type="diffuse"><spectrum name="reflectance" value="400:0.1, 500 : 0.4, 700:0.8"/></bsdf></shape>
    <shape type="disk"><bsdf type="conductor"><spectrum name="eta" value="0.2"/><spectrum name="k" value="3"/></bsdf></shape>
    <shape type="cylinder"><bsdf type="diffuse"><spectrum name="reflectance" value="macbeth-13"/></bsdf></shape>
"""))
    write("xml", "renderers.xml", scene("""    <integrator type="moment">
        <integrator type="aov"><string name="aovs" value="dd.y:depth,nn:sh_normal"/>
            <integrator type="path"><integer name="max_depth" value="3"/></integrator></integrator>
        <integrator type="direct"/>
    </integrator>
    <accelerator type="bvh"/>
    <emitter type="directional"><vector name="direction" value="0, 0, -1"/><rgb name="irradiance" value="1"/></emitter>
    <shape type="rectangle"><bsdf type="null"/></shape>
"""))
    write("xml", "instances.xml", scene("""    <shape type="shapegroup" id="group">
        <shape type="sphere"><float name="radius" value="0.3"/></shape>
    </shape>
    <shape type="instance"><ref id="group"/>
        <transform name="to_world"><matrix value="1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1"/></transform></shape>
"""))
    write("xml", "legacy.xml", scene("""    <integrator type="direct"><integer name="emitterSamples" value="2"/></integrator>
    <shape type="sphere"><float name="radius" value="0.5"/>
        <bsdf type="roughplastic"><float name="intIOR" value="1.5"/></bsdf></shape>
    <emitter type="constant"/>
""", version="0.6.0", sensor=SENSOR.replace("sample_count", "sampleCount")))
    write("xml", "include.xml", scene("""    <path value="."/>
    <include filename="minimal-part.xml"/>
    <shape type="rectangle" id="r"><bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="diffuse"/></bsdf></shape>
"""))
    write("xml", "minimal-part.xml", '<scene version="3.0.0">\n    <bsdf type="diffuse" id="shared"/>\n'
          '    <shape type="sphere"><ref id="shared"/></shape>\n</scene>\n')
    write("xml", "radiosity.xml", scene("""    <integrator type="radiosity">
        <mesh type="uniform"><float name="max_edge" value="0.5"/></mesh>
        <formfactor type="analytic"/><solver type="gaussseidel"/>
    </integrator>
    <shape type="rectangle"><emitter type="area"><rgb name="radiance" value="1, 1, 1"/></emitter></shape>
    <shape type="cube"><bsdf type="diffuse"/></shape>
"""))


# ---- XML dictionary ----------------------------------------------------------------------
def xml_dict():
    """fuzz/xml.dict: the words of the scene grammar and every component type and parameter
    name of docs/components.md, so that the fuzzer writes valid names from the start."""
    import re
    words = set()
    for tag in ("scene", "default", "include", "path", "ref", "boolean", "integer", "float", "string",
                "point", "vector", "rgb", "spectrum", "blackbody", "transform", "translate", "rotate",
                "scale", "matrix", "lookat", "sensor", "integrator"):
        words.update({"<" + tag, "</" + tag + ">"})
    words.update(' %s="' % a for a in ("version", "type", "id", "name", "value", "filename", "x", "y", "z",
                                          "angle", "origin", "target", "up", "temperature", "scale"))
    words.update(("/>", "$", "3.0.0", "0.6.0", "true", "false", "nan", "inf", "-1", "1e30", "400:0.5",
                  "d65", "macbeth-13", "Au", "bk7"))
    for line in (ROOT / "docs/components.md").read_text().splitlines():
        if m := re.match(r"### `(\w+)/(\w+)`", line):
            words.update(("<" + m.group(1), "</" + m.group(1) + ">", m.group(2)))
        elif m := re.match(r"\| `(\w+)` \|", line):
            words.add(m.group(1))
            if c := re.search(r"\(([\w.-]+(?: \\\| [\w.-]+)+)\)", line):  # choices: (a \| b \| c)
                words.update(w.strip() for w in c.group(1).split("\\|"))
    text = "".join('"%s"\n' % w.replace("\\", "\\\\").replace('"', '\\"') for w in sorted(words))
    (FUZZ / "xml.dict").write_text("# libFuzzer dictionary of the xml target (written by make_seeds.py)\n" + text)
    return len(words)


# ---- checkpoints ---------------------------------------------------------------------------
def checkpoint_seeds():
    """A checkpoint of fuzz/checkpoint_scene.xml as effigi writes it, whole and as a bare
    payload (the target frames inputs without the magic with a valid header). Needs a
    built effigi (build/release/bin/effigi); skipped without one."""
    import subprocess
    import tempfile
    effigi = ROOT / "build/release/bin/effigi"
    if not effigi.exists():
        print("checkpoint: no build/release/bin/effigi, seeds not written")
        return
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([str(effigi), "render", str(FUZZ / "checkpoint_scene.xml"), "-o", f"{tmp}/out.exr",
                        "--no-progress", "--checkpoint", f"{tmp}/cp"], check=True, capture_output=True)
        data = (pathlib.Path(tmp) / "cp/checkpoint.effigi").read_bytes()
    write("checkpoint", "render-8px.effigi", data)
    write("checkpoint", "render-8px.payload", data[32:])  # header: magic, version, 0, length, checksum


def main():
    for t in ("ply", "obj", "serialized", "spd", "vol", "image", "xml", "checkpoint"):
        (CORPUS / t).mkdir(parents=True, exist_ok=True)
    ply_seeds()
    obj_seeds()
    serialized_seeds()
    spd_seeds()
    vol_seeds()
    image_seeds()
    xml_seeds()
    checkpoint_seeds()
    print(f"xml.dict: {xml_dict()} words")
    for d in sorted(CORPUS.iterdir()):
        files = sorted(d.iterdir())
        print(f"{d.name}: {len(files)} seeds, {sum(f.stat().st_size for f in files)} bytes")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Regenerates the CSV tables in data/ from colour-science (pip install colour-science),
which transcribes the CIE publications named in each file's header. Not part of the
build: the CSVs are committed; run this only to audit or refresh them."""
import colour
import numpy as np
from colour.colorimetry import sd_CIE_illuminant_D_series

HEADER = "# {what}\n# Source: {source}\n# Transcribed by colour-science {ver} (data/generate.py).\n"


def write(path, what, source, columns, rows, fmt):
    with open(path, "w") as f:
        f.write(HEADER.format(what=what, source=source, ver=colour.__version__))
        f.write(",".join(columns) + "\n")
        for r in rows:
            f.write(",".join(fmt(v) for v in r) + "\n")


def main():
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    rows = [(l, *cmfs[l]) for l in range(360, 831)]
    write("cie1931_2deg.csv", "CIE 1931 2-degree colour matching functions, 1 nm, 360-830 nm",
          "CIE 018:2019 / CIE 15:2004 Table T.4 (CIE 1931 standard colorimetric observer)",
          ["lambda", "x", "y", "z"], rows, lambda v: f"{v:.8g}")

    # D65 as tabulated (CIE 15:2004 Table T.1, 300-780 nm at 5 nm), extended to 830 nm with
    # the CIE daylight formula (CIE 15:2004 section 3.1) at the D65 chromaticity; the colour
    # matching functions are below 2e-4 of their peak there.
    table = colour.SDS_ILLUMINANTS["D65"]
    xy = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    series = sd_CIE_illuminant_D_series(xy)
    rows = [(l, table[l] if l <= 780 else series[l]) for l in range(300, 831, 5)]
    write("cie_illuminant_d65.csv", "CIE standard illuminant D65, relative SPD (100 at 560 nm), 5 nm",
          "CIE 15:2004 Table T.1 (300-780 nm); 785-830 nm from the CIE daylight series formula",
          ["lambda", "value"], rows, lambda v: f"{v:.6g}")


if __name__ == "__main__":
    main()

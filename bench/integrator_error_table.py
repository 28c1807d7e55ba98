#!/usr/bin/env python3
"""The error-against-samples table of docs/conformance.md from an effigi-conform run.

    build/release/bin/effigi-conform --tag integrator --json out/integrators.json
    python3 bench/integrator_error_table.py out/integrators.json

Reads the integrator suite's "error vs samples" rows of each integrator's first (default)
configuration and prints a Markdown table: per integrand and integrator, the RMS error of
the runs at N = 2^10 and N = 2^14 samples divided by plain Monte Carlo's σ/√N (σ the
integrand's standard deviation), and the fitted slope of log error against log N. Needs a
full run (without --quick, which stops at N = 2^10).
"""
import json
import re
import sys

ORDER = ["mean", "stratified", "vegas", "adaptive"]
PART = re.compile(r"2\^(\d+): [^ ]+ \(([^×]+)× MC")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    report = json.load(open(sys.argv[1]))
    first = {}  # component -> its first configuration
    cells = {}  # (integrand, component) -> text
    integrands = []
    for row in report["rows"]:
        if row["tag"] != "integrator" or not row["check"].startswith("error vs samples "):
            continue
        component = row["component"]
        first.setdefault(component, row["config"])
        if row["config"] != first[component]:
            continue
        integrand = row["check"][len("error vs samples "):]
        if integrand not in integrands:
            integrands.append(integrand)
        ratios = {int(k): v for k, v in PART.findall(row["detail"])}
        slope = row["figure"].replace("slope ", "")
        cells[(integrand, component)] = "{} · {} ({})".format(
            fmt(ratios.get(10)), fmt(ratios.get(14)), slope.replace("-", "−"))
    components = [c for c in ORDER if c in first] + sorted(c for c in first if c not in ORDER)
    print("| integrand | " + " | ".join(components) + " |")
    print("|---|" + "---|" * len(components))
    for g in integrands:
        print("| {} | ".format(g) + " | ".join(cells.get((g, c), "–") for c in components) + " |")


def fmt(text):
    if text is None:
        return "–"
    try:
        v = float(text)
    except ValueError:
        return text
    return "{:.2g}".format(v) if v < 10 else "{:.0f}".format(v)


if __name__ == "__main__":
    main()

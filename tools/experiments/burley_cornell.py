#!/usr/bin/env python3
"""Burley 2020's Cornell-box comparison beside nuld's rows of the same kind.

Burley, "Practical Hash-based Owen Scrambling" (JCGT 9(4), 2020), gives the
RMSE of a direct-lit Cornell box at 16 spp. Its absolute RMSE belongs to its
own scene and resolution, so the comparison is of RMSE over independent's.
Usage: burley_cornell.py STUDY/render.csv [SPP]   (SPP default 16)
Prints a Markdown table: nuld's RMSE with its standard error, the ratio to
independent, and Burley's row it stands beside with his ratio.
"""
import csv
import math
import sys

# Burley 2020's table (RMSE, 16 spp, direct lighting): his name -> RMSE.
BURLEY = {
    "independent": 0.020,
    "Laine-Karras scrambled Sobol": 0.0065,
    "random digit scrambled Sobol": 0.0048,
    "Sobol enumerated over the image": 0.0021,
    "Owen-scrambled Sobol": 0.0017,
}
# nuld's row -> the Burley row it is closest to (None: no counterpart).
COUNTERPART = {
    "independent": "independent",
    "sobol": "Owen-scrambled Sobol",  # Owen-Sobol per 2D domain, padded
    "sobol-full": "Owen-scrambled Sobol",  # consecutive dimensions, one sequence
    "zsobol": None,  # Ahmed and Wonka's Morton-ordered Owen-Sobol: not in his table
    "pmj02": None,
}


def main():
    path = sys.argv[1]
    spp = sys.argv[2] if len(sys.argv) > 2 else "16"
    rows = {r["backend"]: r for r in csv.DictReader(open(path)) if r["spp"] == spp}
    if "independent" not in rows:
        sys.exit(f"burley_cornell: {path}: no independent row at {spp} spp")
    base = math.sqrt(float(rows["independent"]["mse"]))
    print("| row | RMSE | / independent | Burley's row | his RMSE | his / independent |")
    print("|---|---|---|---|---|---|")
    for name, burley in COUNTERPART.items():
        if name not in rows:
            continue
        mse, se = float(rows[name]["mse"]), float(rows[name]["mse_stderr"])
        rmse = math.sqrt(mse)
        rmse_se = se / (2 * rmse)  # delta method
        his = (f"{burley} | {BURLEY[burley]:.4f} | {BURLEY[burley] / BURLEY['independent']:.3f}"
               if burley else "none | | ")
        print(f"| `{name}` | {rmse:.5f} +- {rmse_se:.5f} | {rmse / base:.3f} | {his} |")


main()

#!/usr/bin/env python3
"""Writes OUT/summary.md from the sam_compare runs in OUT (one folder each,
holding report.json): a table of every technique's PSNRs, whether SAM
scores highest on all three scores, and the truth's share of translucency;
then, for runs with a cut map's samples sweep, the cut map against the flat
map and the flat-scaled baseline at each N. Prints the text too.

    scripts/summarise_compare.py OUT [--title TEXT]

scripts/compare_scenes.sh and scripts/held_out.sh call it. Exit status 1
when OUT holds no report, 2 on a usage error."""
import argparse
import json
import math
import os
import sys

NAMES = ["sam", "tsm", "transmittance", "thickness", "none"]
SCORES = ("psnr_differing_db", "psnr_db", "psnr_translucency_db")


def db(x):
    return "inf" if x is None else "%.2f" % x


def psnr(rmse):
    return "inf" if rmse <= 0 else "%.2f" % (20 * math.log10(255 / rmse))


def sam_best(t):
    """Whether SAM is above every other available technique on all three
    scores. A PSNR of None (an exact picture) counts as infinite, above any
    finite one; equal scores are not above."""
    sam = t.get("sam")
    if not sam or not sam["available"]:
        return False
    for n in NAMES[1:]:
        x = t.get(n)
        if not x or not x["available"]:
            continue
        for k in SCORES:
            a, b = sam[k], x[k]
            a = math.inf if a is None else a
            b = math.inf if b is None else b
            if a <= b:
                return False
    return True


def share(truth):
    s = truth.get("translucency_share")
    if s is None:
        return "n/a"
    return "%.2g%%" % (100 * s) if s < 0.01 else "%.1f%%" % (100 * s)


def main():
    ap = argparse.ArgumentParser(usage="summarise_compare.py OUT [--title TEXT]")
    ap.add_argument("out")
    ap.add_argument("--title", default="", help="a first paragraph for summary.md")
    a = ap.parse_args()
    reports = []
    for d in sorted(os.listdir(a.out)) if os.path.isdir(a.out) else []:
        path = os.path.join(a.out, d, "report.json")
        if os.path.isfile(path):
            with open(path) as f:
                reports.append((d, json.load(f)))
    if not reports:
        print("summarise_compare.py: no DIR/report.json in %s" % a.out, file=sys.stderr)
        return 1
    rows = ["| scene | truth samples (s) | " + " | ".join(NAMES) + " | SAM best? | truth's translucency |",
            "| --- " * (len(NAMES) + 4) + "|"]
    for d, r in reports:
        t = {x["name"]: x for x in r["techniques"]}
        cells = []
        for n in NAMES:
            x = t.get(n)
            cells.append("n/a" if not x or not x["available"] else " / ".join(db(x[k]) for k in SCORES))
        tr = r["truth"]
        rows.append("| %s | %d (%.0f) | %s | %s | %s |" % (d, tr["samples"], tr["seconds"], " | ".join(cells),
                                                           "yes" if sam_best(t) else "no", share(tr)))
    text = (a.title + "\n\n" if a.title else "")
    text += "PSNR in dB: differing pixels / all object pixels / translucency normalised\n\n" + "\n".join(rows) + "\n"
    sweeps = []
    for d, r in reports:
        points = r.get("samples_sweep", {}).get("points", [])
        if points and "flat_rmse" in points[0]:
            cells = ["%s / %s / %s" % (psnr(p["rmse"]), psnr(p["flat_rmse"]), psnr(p["flat_scaled_rmse"]))
                     for p in points]
            cells_t = ["%s / %s / %s" % (psnr(p["rmse_translucency"]), psnr(p["flat_rmse_translucency"]),
                                         psnr(p["flat_scaled_rmse_translucency"])) for p in points]
            sweeps.append((d, [p["n"] for p in points], cells, cells_t))
    if sweeps:
        ns = sweeps[0][1]
        text += ("\nCut map / flat map / flat-scaled baseline with the same N, PSNR of all object pixels; then of the "
                 "translucency (normalised):\n\n| scene | " + " | ".join("N = %d" % n for n in ns) + " | " +
                 " | ".join("translucency N = %d" % n for n in ns) + " |\n|" + " --- |" * (1 + 2 * len(ns)) + "\n")
        for d, n, cells, cells_t in sweeps:
            text += "| %s | %s | %s |\n" % (d, " | ".join(cells), " | ".join(cells_t))
    tmp = os.path.join(a.out, "summary.md.tmp")
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, os.path.join(a.out, "summary.md"))
    print(text, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Plots tools/field_accuracy's CSVs (bench/field_accuracy.sh): the guiding field's error inside media.

Left: the in-scattered estimate's relMSE against depth (mean free paths), the field's (solid) and the
best isotropic guess's shape error (dashed: what a field without directional information would get).
Right: the field's fluence over the reference fluence against the leaf's optical size (sigma_t x the
cube root of its volume). The reference fluence is 4 pi x the in-scattered reference averaged over the
travel directions (it holds small and delta lights, which the incident probes on a direction grid miss).

    python3 examples/python/plot_field_accuracy.py bench/results/field-accuracy/*.csv -o field_accuracy.png
"""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    rows = list(csv.DictReader(open(path)))
    return [{k: (v if k == "scene" else float(v)) for k, v in r.items()} for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv", nargs="+")
    ap.add_argument("-o", "--output", default="field_accuracy.png")
    args = ap.parse_args()
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    for path in args.csv:
        # Points whose reference is mostly noise (relative variance of the mean > 0.25: e.g. sss beyond
        # the depth max_depth lets paths reach) say nothing about the field.
        rows = [r for r in load(path) if r["inscatter_mean_ref"] > 0 and r["ref_rel_noise"] <= 0.25]
        if not rows:
            continue
        name = rows[0]["scene"]
        depth = [r["depth_mfp"] for r in rows]
        line, = a.plot(depth, [max(r["inscatter_relmse"], 1e-4) for r in rows], "o-", label=name)
        a.plot(depth, [max(r["inscatter_iso_shape_relmse"], 1e-4) for r in rows], "--", color=line.get_color())
        b.plot([r["leaf_tau"] for r in rows],
               [r["fluence_field"] / (4 * math.pi * r["inscatter_mean_ref"]) for r in rows], "o",
               color=line.get_color(), label=name)
    a.set(xscale="log", yscale="log", xlabel="depth (mean free paths)",
          ylabel="in-scattered relMSE", title="solid: field; dashed: isotropic shape")
    b.set(xscale="log", yscale="log", xlabel="leaf optical size (sigma_t x cbrt(volume))",
          ylabel="fluence: field / reference", title="per point, by its leaf's optical size")
    b.axhline(1, color="grey", lw=0.8)
    a.legend(fontsize=8)
    b.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(args.output)


if __name__ == "__main__":
    main()

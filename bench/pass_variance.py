#!/usr/bin/env python3
"""Per-sample variance of each stretch of passes of a render, from its convergence record (issue 22).

A render's --stats JSON holds, after every pass, the relMSE of the image so far against the reference
("convergence"). With independent samples, relMSE(n) = R + (sum over the samples of their variances)
/ n^2 (R: the reference's own error, from its .json), so the samples between two records at n1 < n2
have the mean per-sample relative variance

    v = ((relMSE(n2) - R) n2^2 - (relMSE(n1) - R) n1^2) / (n2 - n1).

A field refined during the render (guided_volpath's refine_passes) changes between passes, and the
passes are merged weighted by their sample count. This prints v for every stretch, the relMSE
the count weighting gives (the render's own, minus R) and what inverse-variance weighting of the
same stretches would give, 1 / sum(n_i / v_i): how much the count weighting loses. The figures are
as noisy as the relMSE of each record (one run, one seed); a stretch of few samples is noisy.

    python3 bench/pass_variance.py STATS.json [STATS.json ...] [--reference-error R]
"""
import argparse
import json
import os


def reference_error(stats, given=None):
    """The reference's estimated relMSE(1e-2): `given`, else its .json's (the reference as it is now:
    pass --reference-error for a run measured against an earlier one)."""
    if given is not None:
        return given
    ref = stats.get("reference", {}).get("file")
    if ref and os.path.exists(ref[:-4] + ".json"):
        with open(ref[:-4] + ".json") as f:
            return json.load(f).get("estimated_relmse_1e-2", 0.0)
    return 0.0


def stretches(stats, given_error=None):
    """(n1, n2, per-sample relative variance) for consecutive records."""
    R = reference_error(stats, given_error)
    out, prev = [], None
    for rec in stats["convergence"]:
        n, e = rec["spp"], rec["relmse_1e-2"] - R
        if prev is not None and n > prev[0]:
            n1, e1 = prev
            out.append((n1, n, (e * n * n - e1 * n1 * n1) / (n - n1)))
        elif prev is None and n > 0:
            out.append((0, n, e * n))
        prev = (n, e)
    return R, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("stats", nargs="+", help="--stats JSON files of renders")
    ap.add_argument("--reference-error", type=float, default=None,
                    help="the reference's relMSE(1e-2) the run was measured against (default: its .json now)")
    args = ap.parse_args()
    for path in args.stats:
        with open(path) as f:
            stats = json.load(f)
        R, parts = stretches(stats, args.reference_error)
        online = int(stats.get("integrator", {}).get("online_updates", 0))
        print(f"{os.path.basename(path)}: reference error {R:.3g}, online updates {online}")
        N = parts[-1][1] if parts else 0
        for n1, n2, v in parts:
            print(f"  samples [{n1}, {n2}): per-sample relative variance {v:.4g}")
        if not parts or any(v <= 0 for _, _, v in parts):
            print("  (a stretch with a non-positive estimate: too noisy to weigh)")
            continue
        count = sum((n2 - n1) * v for n1, n2, v in parts) / (N * N)
        inverse = 1.0 / sum((n2 - n1) / v for n1, n2, v in parts)
        print(f"  relMSE - R: count weighting {count:.4g}, inverse-variance weighting {inverse:.4g} "
              f"(count weighting loses {count / inverse:.3f}x)")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Re-scores a finished benchmark run against the current references, without rendering again.

When a reference is re-rendered (e.g. longer, to meet the 1/10 rule of issue 5), the images of a run
stay valid but their relMSE/MSE were measured against the old reference. This recomputes them from
the run's own EXR images (images/<scene>__<method>.exr, kept next to the report) with `volguide diff`,
regenerates the error images, the speed-ups, the reference checks, results.csv, results.json,
table.md and index.html. The convergence curves (plots/) are left as rendered: they were measured
during the renders against the references of that time, which the table says.

    python3 bench/rescore.py bench/results/2026-11-23 [--references bench/references] [--build-dir build]
"""
import argparse
import json
import os
import subprocess
import sys
import types

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import run_bench  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="a results directory written by bench/run_bench.py")
    ap.add_argument("--references", default=os.path.join(run_bench.ROOT, "bench", "references"))
    ap.add_argument("--build-dir", default=os.path.join(run_bench.ROOT, "build"))
    args = ap.parse_args()
    volguide = os.path.join(args.build_dir, "volguide")
    if not os.access(volguide, os.X_OK):
        sys.exit(f"rescore: {volguide} is missing; run `make build` first")
    with open(os.path.join(args.run, "results.json")) as f:
        run = json.load(f)
    rows = run["rows"]
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    for scene in scenes:
        subprocess.run([volguide, "convert", os.path.join(args.references, scene + ".exr"),
                        os.path.join(args.run, "images", scene + "__reference.png")], check=True, capture_output=True)
    for r in rows:
        if r["status"] != "ok":
            continue
        name = f"{r['scene']}__{run_bench.slug(r['method'])}"
        exr = os.path.join(args.run, "images", name + ".exr")
        if not os.path.exists(exr):
            sys.exit(f"rescore: {exr} is missing (the run's EXR images are not committed: re-score on the machine "
                     "that rendered them, or render again)")
        ref = os.path.join(args.references, r["scene"] + ".exr")
        d = json.loads(subprocess.run([volguide, "diff", exr, ref, "--json", "--error-image",
                                       os.path.join(args.run, "images", name + "__error.png")],
                                      check=True, capture_output=True, text=True).stdout)
        for key in ("relmse_1e-2", "relmse_1e-3", "relmse_1e-2_trimmed", "relmse_1e-3_trimmed", "mse", "mean",
                    "reference_mean"):
            r[key] = d[key]
        r.pop("speedup_1e-2", None)
        r.pop("speedup_1e-3", None)
        for key in ("best_unguided", "speedup_best_unguided_1e-2", "speedup_best_unguided_1e-3"):
            r.pop(key, None)
    run_bench.add_speedups(rows)
    run_bench.add_net_of_reference(rows, args.references)
    checks = run_bench.check_references(rows, scenes, args.references)
    refs = {s: run_bench.reference_record(args.references, s) for s in scenes}
    note = ("re-scored by `python3 bench/rescore.py` against bench/references/ as of "
            + run_bench.machine_description()["commit"] + " (reference spp: "
            + ", ".join(f"{s} {refs[s]['spp']}" for s in scenes) + "); the convergence plots are from the renders, "
            "against the references of that time")
    ns = types.SimpleNamespace(time=run["time_budget"], command_line=run["command"])
    machine = run["machine"]
    run_bench.write_csv(rows, os.path.join(args.run, "results.csv"))
    with open(os.path.join(args.run, "table.md"), "w") as f:
        table = run_bench.table_markdown(rows, scenes, machine, ns, checks)
        head, _, rest = table.partition("\n\n## ")  # the bullets above the first scene's section
        f.write(head + f"\n- {note}\n\n## " + rest + "\n")
    run["reference_checks"] = checks
    run["rescored"] = note
    with open(os.path.join(args.run, "results.json"), "w") as f:
        json.dump(run, f, indent=1)
    plots = {s: os.path.join("plots", s + ".png") for s in scenes
             if os.path.exists(os.path.join(args.run, "plots", s + ".png"))}
    run_bench.write_html(rows, scenes, plots, machine, ns, checks, args.run)
    for s, c in checks.items():
        print(f"{s}: reference relMSE {c['reference_relmse_1e-2']:.3g} = {c['ratio']:.3f} x best "
              f"({c['best_method']}): {'meets' if c['meets_rule'] else 'DOES NOT meet'} the 1/10 rule")
    return 0 if all(c["meets_rule"] for c in checks.values()) else 1


if __name__ == "__main__":
    sys.exit(main())

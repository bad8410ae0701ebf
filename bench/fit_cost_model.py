#!/usr/bin/env python3
"""The cost model's fit and its check (issue 59, src/volguide/integrators/guided/estimates/cost_model.h).

Renders every benchmark scene with several methods at a fixed sample count on one thread, reads each
render's counted work (--stats: integrator.work_*) and its CPU time over the passes (time.render_cpu,
the process's CPU time: robust to other processes on the machine, unlike wall-clock time), fits one
weight per unit (ns) by non-negative least squares on the relative error of the time per sample, and
checks the model: modelled against measured time per sample, per scene and method.

    python3 bench/fit_cost_model.py --build-dir build [--spp 32] [--width 64 --height 48]
        [--scenes a,b] [--out DIR] [--check-only WEIGHTS.json]

Writes DIR/runs.json (every render's counts and times), DIR/weights.json, DIR/check.md (the check
table) and prints the C++ table for cost_model.cpp. --check-only checks given weights against the runs
of this invocation (the figures of an earlier fit on other renders: the check on data it was not fitted
to).
"""
import argparse
import datetime
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENES = ["shafts", "backlit", "thin", "sss", "aniso", "cloud", "fogbox", "densesphere", "glassfog",
          "fogcornell", "skyglobe"]
UNITS = ["camera_samples", "intersections", "shadow_rays", "medium_vertices", "surface_vertices", "segments",
         "tracked_segments", "continuations", "branches", "recorded_events", "policy_samples", "guided_segments",
         "bins",
         "descents", "lobe_pairs", "guide_evals", "surface_guides", "estimates"]
# The methods whose counts differ the most: the unguided walk, each guided decision alone, all of them
# configured everywhere, and the defaults (the allocation, recording every sample).
METHODS = {
    "volpath rr_rule=bounded": None,
    "guided distance": {"distance": "incremental", "direction": "phase", "rrs": "standard", "allocation": "false"},
    "guided direction": {"distance": "standard", "direction": "product", "rrs": "standard", "allocation": "false"},
    "guided grrs": {"distance": "standard", "direction": "phase", "rrs": "grrs", "allocation": "false"},
    "guided all": {"allocation": "false"},
    "guided_volpath": {},
}


def integrator_file(params, directory):
    """A guided_volpath integrator file with `params` (None: the scenes' own integrator.xml)."""
    if params is None:
        return None
    lines = ['<?xml version="1.0" encoding="utf-8"?>', '<scene version="3.0.0">',
             '    <integrator type="guided_volpath">', '        <integer name="max_depth" value="$max_depth"/>']
    for k, v in params.items():
        kind = "boolean" if v in ("true", "false") else "string"
        lines.append(f'        <{kind} name="{k}" value="{v}"/>')
    lines += ["    </integrator>", "</scene>"]
    fd, path = tempfile.mkstemp(suffix=".xml", dir=directory)
    with os.fdopen(fd, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def render(cli, scene, method, params, args, directory):
    stats = os.path.join(directory, f"{scene}__{method.replace(' ', '_')}.json")
    cmd = [cli, "render", os.path.join(ROOT, "bench", "scenes", scene + ".xml"), "--spp", str(args.spp),
           "--threads", "1", "--seed", "1", "--quiet", "--stats", stats, "-o", stats[:-5] + ".exr",
           "-D", f"width={args.width}", "-D", f"height={args.height}"]
    xml = integrator_file(params, directory)
    if xml:
        cmd += ["-D", f"integrator_xml={xml}"]
    else:
        cmd += ["-D", "integrator=volpath", "-D", "rr_rule=bounded"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(stats) as f:
        d = json.load(f)
    work = d["integrator"]
    counts = [float(work.get("work_" + u, 0.0)) for u in UNITS]
    # The full training stage runs between the passes (guided_volpath.h): not the samples' cost.
    cpu = d["time"]["render_cpu"] - float(work.get("training_full_stage_cpu_seconds", 0.0))
    return {"scene": scene, "method": method, "counts": counts, "cpu": cpu, "samples": float(d["samples"])}


def nnls(A, b, iterations=2000):
    """Non-negative least squares (Lawson-Hanson active set)."""
    n = A.shape[1]
    x = np.zeros(n)
    passive = np.zeros(n, dtype=bool)
    w = A.T @ (b - A @ x)
    for _ in range(iterations):
        if passive.all() or not (w[~passive] > 1e-12 * max(1.0, np.abs(w).max())).any():
            break
        j = np.argmax(np.where(passive, -np.inf, w))
        passive[j] = True
        while True:
            z = np.zeros(n)
            z[passive] = np.linalg.lstsq(A[:, passive], b, rcond=None)[0]
            if (z[passive] > 0).all():
                x = z
                break
            neg = passive & (z <= 0)
            alpha = np.min(x[neg] / (x[neg] - z[neg]))
            x = x + alpha * (z - x)
            passive &= x > 1e-15
        w = A.T @ (b - A @ x)
    return x


# The unguided walk's units, which volpath's renders alone determine (the rest are 0 there).
WALK_UNITS = UNITS[:UNITS.index("continuations")]


def fit(runs):
    """Two stages, so that units that always come together in guided renders (a guided vertex's lobe pairs,
    evaluations, descents) are not traded against the walk's: the walk's units from volpath's renders,
    then the others from the guided renders with the walk's fixed. Each stage minimises the relative error
    of the time per camera sample (each run's row divided by its measured time)."""
    walk = [UNITS.index(u) for u in WALK_UNITS]
    rest = [k for k in range(len(UNITS)) if k not in walk]
    unguided = [r for r in runs if r["method"].startswith("volpath")]
    guided = [r for r in runs if not r["method"].startswith("volpath")]
    weights = np.zeros(len(UNITS))
    A = np.array([np.array(r["counts"])[walk] / r["cpu"] for r in unguided])
    weights[walk] = nnls(A, np.ones(len(unguided)))
    A = np.array([np.array(r["counts"])[rest] / r["cpu"] for r in guided])
    b = np.array([1.0 - float(np.dot(np.array(r["counts"])[walk], weights[walk])) / r["cpu"] for r in guided])
    weights[rest] = nnls(A, b)
    return weights * 1e9  # ns per unit


def check(runs, weights_ns):
    rows, worst = [], 0.0
    for r in runs:
        model = float(np.dot(r["counts"], weights_ns)) * 1e-9
        err = model / r["cpu"] - 1.0
        worst = max(worst, abs(err))
        rows.append((r["scene"], r["method"], 1e9 * r["cpu"] / r["samples"], 1e9 * model / r["samples"], err))
    return rows, worst


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build-dir", default="build")
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--width", type=int, default=64)
    p.add_argument("--height", type=int, default=48)
    p.add_argument("--scenes", default=",".join(SCENES))
    p.add_argument("--out", default=os.path.join(ROOT, "bench", "results",
                                                 datetime.date.today().isoformat() + "-cost-model"))
    p.add_argument("--check-only", help="weights.json of an earlier fit: check it, do not fit")
    p.add_argument("--runs", help="runs.json of an earlier invocation: fit and check those, render nothing")
    args = p.parse_args()
    cli = os.path.join(args.build_dir, "volguide")
    os.makedirs(args.out, exist_ok=True)
    runs = []
    if args.runs:
        with open(args.runs) as f:
            runs = json.load(f)
    else:
        for scene in args.scenes.split(","):
            for method, params in METHODS.items():
                print(f"{scene}: {method}", file=sys.stderr)
                runs.append(render(cli, scene, method, params, args, args.out))
    with open(os.path.join(args.out, "runs.json"), "w") as f:
        json.dump(runs, f, indent=1)
    if args.check_only:
        with open(args.check_only) as f:
            weights = np.array(json.load(f)["ns"])
    else:
        weights = fit(runs)
        with open(os.path.join(args.out, "weights.json"), "w") as f:
            json.dump({"units": UNITS, "ns": list(weights)}, f, indent=1)
    rows, worst = check(runs, weights)
    with open(os.path.join(args.out, "check.md"), "w") as f:
        f.write("| scene | method | measured ns/sample | modelled | error |\n|---|---|---:|---:|---:|\n")
        for scene, method, measured, model, err in rows:
            f.write(f"| {scene} | {method} | {measured:.0f} | {model:.0f} | {100 * err:+.1f} % |\n")
        f.write(f"\nlargest |error|: {100 * worst:.1f} %\n")
    print(open(os.path.join(args.out, "check.md")).read())
    print("// cost_model.cpp: ns per unit, in volpath/work.h's order")
    for u, w in zip(UNITS, weights):
        print(f"        {w:.1f},  // {u}")
    return 0 if worst <= 0.2 else 1


if __name__ == "__main__":
    sys.exit(main())

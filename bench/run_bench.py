#!/usr/bin/env python3
"""Equal-time benchmark (issue 5, docs/theory.md §12): every scene x method renders for the same
wall-clock budget (training included), is compared with the scene's reference, and the report goes to
bench/results/<date>/: results.csv, table.md (the seed's layout), plots/ (relMSE vs time, log-log),
index.html (images side by side, zoomed crops, false-colour error maps).

    python3 bench/run_bench.py [--time 60] [--quick] [--scenes a,b] [--methods m1,m2] [--out DIR]

A method that volguide does not implement yet is reported as skipped with volguide's own message;
it is never faked. Any other failure makes the run exit with status 1 after the report is written.
"""
import argparse
import csv
import datetime
import html
import json
import os
import platform
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENES = ["shafts", "backlit", "thin", "sss", "aniso", "cloud", "fogbox", "densesphere", "glassfog"]
# Scenes the defaults are judged on but not tuned on (bench/scenes/README.md): --scenes names them.
HELD_OUT = ["fogcornell", "skyglobe", "smoke", "envsss", "door", "keyhole"]
BASELINE = "volpath"
# The best unguided method of a scene (issue 21): the lowest relMSE at this budget among these; every
# method's speed-up is also quoted against it ("vs best unguided").
UNGUIDED_METHODS = ["volpath", "volpath rr_rule=bounded", "volpath+equiangular"]

# Methods, named by their integrator parameters (docs/interface.md). `None` = the scenes' default
# integrator file with the given -D values; a dict = a generated guided_volpath integrator file.
METHODS = {
    # What a user gets (issue 55): guided_volpath with no options, the default photons. Each scene's first
    # table compares it with the best unguided method.
    "guided_volpath": {"guided_defaults": True},
    # The same with every decision guided everywhere (the configured mixtures, nothing learned): what the
    # allocation (issue 59) chooses from.
    "guided_volpath allocation=false": {"guided_defaults": True, "guided": {"allocation": False}},
    "volpath": {"defines": ["integrator=volpath"]},
    "volpath+equiangular": {"defines": ["integrator=volpath", "equiangular=true"]},
    # Weights bounded by the roulette (survival min(1, max(beta) eta^2)): the strong unguided baseline in
    # dense high-albedo media, where Mitsuba's rule (the `volpath` row) lets weights grow.
    "volpath rr_rule=bounded": {"defines": ["integrator=volpath", "rr_rule=bounded"]},
    "guided_volpath distance=incremental": {"guided": {"distance": "incremental"}},
    "guided_volpath direction=incident": {"guided": {"direction": "incident"}},
    "guided_volpath direction=product": {"guided": {"direction": "product"}},
    # Guided RR and splitting alone (unguided distances and directions): the third decision by itself.
    "guided_volpath rrs=grrs": {"guided": {"rrs": "grrs"}},
    "guided_volpath distance=incremental direction=product": {
        "guided": {"distance": "incremental", "direction": "product"}},
    "guided_volpath distance=incremental direction=product rrs=grr": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grr"}},
    "guided_volpath distance=incremental direction=product rrs=grrs": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs"}},
    # The full system with issue 37's one decision per segment (theory §7.10) in place of the bins.
    "guided_volpath distance=vsp direction=product rrs=grrs": {
        "guided": {"distance": "vsp", "direction": "product", "rrs": "grrs"}},
    # The full system without the guided distance decision (issue 22: is it worth its cost on fogbox?).
    "guided_volpath direction=product rrs=grrs": {"guided": {"direction": "product", "rrs": "grrs"}},
    # The peer (issue 19): Intel Open PGL's directional guiding as Cycles drives it, trained online
    # from the render's own passes (training_spp 128, or under --time the passes up to 25 % of the
    # budget; those samples are in the image). Skipped when volguide was built without Open PGL.
    "openpgl_volpath": {"defines": ["integrator=openpgl_volpath"]},
    # The VSPG peer (issue 37): the same with Open PGL 0.8's volume scattering probability deciding each
    # segment leaving a guided vertex. Runs with the binary of a build configured with
    # -DVOLGUIDE_OPENPGL_SOURCE=0.8 (--openpgl08-build-dir); skipped, saying so, without one.
    "openpgl_volpath vsp=true": {"openpgl": {"vsp": True}, "openpgl08": True},
}

# Methods run only when named in --methods (comparisons of variants, not part of the default table).
EXTRA_METHODS = {
    # Efficiency-aware RR and splitting (issue 38, docs/theory.md §9.8) by itself (unguided distances
    # and directions) and with the guided distance and direction decisions.
    "guided_volpath rrs=ears": {"guided": {"rrs": "ears"}},
    "guided_volpath distance=incremental direction=product rrs=ears": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "ears"}},
    # Ablations of the direction decision at surfaces and of the distance mixture's defensive share.
    "guided_volpath distance=incremental direction=product surface_guiding=false": {
        "guided": {"distance": "incremental", "direction": "product", "surface_guiding": False}},
    "guided_volpath distance=incremental direction=product c_T=0.25": {
        "guided": {"distance": "incremental", "direction": "product", "c_T": 0.25}},
    # Guided RR/splitting (issue 8): guided sampling without any RR (rr_depth = the scenes' max_depth
    # 64: the seed's "no RR" column), and the weight windows: the paper's s = 1 and ADRRS's s = 5
    # (the default since 2026-11-24; before, "rrs=grr" and "rrs=grrs" meant s = 1).
    "guided_volpath distance=incremental direction=product rr_depth=64": {
        "guided": {"distance": "incremental", "direction": "product", "rr_depth": 64}},
    "guided_volpath distance=incremental direction=product rrs=grrs rrs_window=5": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "rrs_window": 5.0}},
    "guided_volpath distance=incremental direction=product rrs=grr rrs_window=5": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grr", "rrs_window": 5.0}},
    "guided_volpath distance=incremental direction=product rrs=grrs rrs_window=1": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "rrs_window": 1.0}},
    "guided_volpath distance=incremental direction=product rrs=grr rrs_window=1": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grr", "rrs_window": 1.0}},
    # Issue 21: the branch budget (a quarter of the cap), branches bounded by construction.
    "guided_volpath distance=incremental direction=product rrs=grrs rrs_branch_budget=16": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "rrs_branch_budget": 16.0}},
    # Issue 20: the full system with half the photon deposits (training ~half as long, ~half the
    # leaves: coarser and shorter distance walks); 2 M is guided_volpath's default since 2026-11-25
    # (so that method is the full system itself, named explicitly for comparisons with earlier runs).
    "guided_volpath distance=incremental direction=product rrs=grrs max_deposits=2000000": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "max_deposits": 2000000}},
    "guided_volpath distance=incremental direction=product rrs=grrs max_deposits=1000000": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "max_deposits": 1000000}},
    # Issue 22's 600 s comparison: does a longer budget afford a finer photon field (4x the deposits)?
    # Issue 39: the field refined during the render (further photon passes at doublings of spp while
    # they pay, docs/theory.md §22).
    "guided_volpath distance=incremental direction=product rrs=grrs refine_passes=8": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "refine_passes": 8}},
    "guided_volpath distance=incremental direction=product rrs=grrs max_deposits=8000000": {
        "guided": {"distance": "incremental", "direction": "product", "rrs": "grrs", "max_deposits": 8000000}},
}

# Zoomed crops shown in the HTML report: (x, y, width, height) in pixels of the 160x120 image.
CROPS = {
    "shafts": [(60, 30, 40, 30), (10, 70, 40, 30)],
    "backlit": [(60, 45, 40, 30), (100, 20, 40, 30)],
    "thin": [(60, 45, 40, 30), (20, 20, 40, 30)],
    "sss": [(60, 45, 40, 30), (40, 70, 40, 30)],
    "aniso": [(60, 45, 40, 30), (100, 60, 40, 30)],
    "cloud": [(60, 45, 40, 30), (20, 30, 40, 30)],
    "fogbox": [(60, 60, 40, 30), (60, 20, 40, 30)],
    "densesphere": [(60, 40, 40, 30), (60, 85, 40, 30)],
    "glassfog": [(60, 72, 40, 30), (10, 45, 40, 30)],
}


def log(msg):
    print(f"[{time.strftime('%H:%M:%S')}] {msg}", file=sys.stderr, flush=True)


def slug(method):
    return re.sub(r"[^A-Za-z0-9]+", "-", method).strip("-")


# A guided method names the decisions it guides; every other decision is pinned to its unguided value
# (guided_volpath's defaults are the full system, so an unnamed decision would otherwise be guided).
UNGUIDED = {"distance": "standard", "direction": "phase", "rrs": "standard"}
# Training: the paper's 50 M photons, cut short by the integrator at training_fraction (25 %) of the
# time budget: the field gets a quarter of the equal-time budget, whatever the scene's photon rate.
TRAINING = {"photons": 50000000}


def openpgl_integrator_xml(params):
    """An openpgl_volpath integrator file with the scenes' max_depth and the given parameters."""
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             "<!-- Generated by bench/run_bench.py for one benchmark method. -->",
             '<scene version="3.0.0">', '    <integrator type="openpgl_volpath">',
             '        <integer name="max_depth" value="$max_depth"/>']
    for k, v in params.items():
        if isinstance(v, bool):
            lines.append(f'        <boolean name="{k}" value="{str(v).lower()}"/>')
        else:
            lines.append(f'        <float name="{k}" value="{v}"/>')
    lines += ["    </integrator>", "</scene>"]
    return "\n".join(lines) + "\n"


def method_binary(volguide, spec, args):
    """The volguide binary a method runs with: the 0.8 build's for the VSPG peer, else the main one;
    None when the 0.8 build is needed and not given."""
    if not spec.get("openpgl08"):
        return volguide
    if not args.openpgl08_build_dir:
        return None
    return os.path.join(args.openpgl08_build_dir, "volguide")


def guided_integrator_xml(params, defaults=False):
    """A guided_volpath integrator file with the scenes' max_depth and `params` over the benchmark's training
    and unguided decisions; `defaults`: guided_volpath's own defaults, nothing else."""
    params = dict(params) if defaults else {**TRAINING, **UNGUIDED, **params}
    lines = ['<?xml version="1.0" encoding="utf-8"?>',
             "<!-- Generated by bench/run_bench.py for one benchmark method. -->",
             '<scene version="3.0.0">',
             '    <integrator type="guided_volpath">',
             '        <integer name="max_depth" value="$max_depth"/>']
    for name, value in params.items():
        if isinstance(value, bool):
            kind, value = "boolean", "true" if value else "false"
        else:
            kind = "integer" if isinstance(value, int) else "float" if isinstance(value, float) else "string"
        lines.append(f'        <{kind} name="{name}" value="{value}"/>')
    lines += ["    </integrator>", "</scene>", ""]
    return "\n".join(lines)


def machine_description():
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=ROOT,
                           capture_output=True, text=True).stdout.strip()
    return {"cpu": cpu, "cores": os.cpu_count(), "os": platform.platform(), "commit": commit + ("+dirty" if dirty else ""),
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")}


def run_method(volguide, scene, method, spec, args, out):
    """Renders one scene with one method; returns the result row (a dict)."""
    name = f"{scene}__{slug(method)}"
    binary = method_binary(volguide, spec, args)
    if binary is None:
        return {"scene": scene, "method": method, "time_budget": args.time, "command": "", "status": "skipped",
                "note": "needs a volguide built with -DVOLGUIDE_OPENPGL_SOURCE=0.8: --openpgl08-build-dir DIR"}
    exr = os.path.join(out, "images", name + ".exr")
    stats_file = os.path.join(out, "stats", name + ".json")
    reference = os.path.join(args.references, scene + ".exr")
    cmd = [binary, "render", os.path.join(ROOT, "bench", "scenes", scene + ".xml"), "-o", exr,
           "--time", str(args.time), "--seed", str(args.seed), "--reference", reference,
           "--stats", stats_file, "--quiet"]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    for d in spec.get("defines", []):
        cmd += ["-D", d]
    if "guided" in spec or spec.get("guided_defaults"):
        xml = os.path.join(out, "integrators", slug(method) + ".xml")
        with open(xml, "w") as f:
            f.write(guided_integrator_xml(spec.get("guided", {}), defaults=spec.get("guided_defaults", False)))
        cmd += ["-D", f"integrator_xml={xml}"]
    if "openpgl" in spec:
        xml = os.path.join(out, "integrators", slug(method) + ".xml")
        with open(xml, "w") as f:
            f.write(openpgl_integrator_xml(spec["openpgl"]))
        cmd += ["-D", f"integrator_xml={xml}"]
    row = {"scene": scene, "method": method, "time_budget": args.time, "command": " ".join(
        os.path.relpath(c, ROOT) if os.path.isabs(c) and c.startswith(ROOT) else c for c in cmd)}
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        message = res.stderr.strip().splitlines()[-1] if res.stderr.strip() else f"exit code {res.returncode}"
        skipped = "not implemented" in message or "built without Intel Open PGL" in message
        row["status"] = "skipped" if skipped else "failed"
        row["note"] = message
        return row
    with open(stats_file) as f:
        st = json.load(f)
    ref = st["reference"]
    row.update(status="ok", note="", spp=st["spp"], seconds=st["time"]["total"],
               preprocess_seconds=st["time"]["preprocess"], render_seconds=st["time"]["render"])
    for key in ("relmse_1e-2", "relmse_1e-3", "relmse_1e-2_trimmed", "relmse_1e-3_trimmed", "mse", "mean",
                "reference_mean"):
        row[key] = ref[key]
    row["convergence"] = st["convergence"]
    # Guided RR/splitting: branches per camera sample (mean, 99.9th percentile) and the budget overrun.
    integ = st.get("integrator", {})
    # The allocation (issue 59): the share of each decision kind's decisions in guided cells, and the
    # training's stage at the end (0 coarse, 1 full, 2 stopped: nothing paid).
    for kind in ("distance", "direction", "surface", "continuation"):
        key = f"allocation_{kind}_guided_fraction"
        if key in integ:
            row[f"guided_{kind}"] = integ[key]
    if "training_stage" in integ:
        row["training_stage"] = integ["training_stage"]
    if "rrs_branches_per_camera_sample" in integ:
        row["branches_mean"] = integ["rrs_branches_per_camera_sample"]
        row["branches_p999"] = integ["rrs_branches_p999"]
        row["branches_max"] = integ["rrs_branches_max"]
        row["pixel_estimate_seconds"] = integ["rrs_pixel_estimate_seconds"]
    # Open PGL trains during the render: the job time when its last field update ended.
    if "openpgl_training_seconds" in integ:
        row["training_seconds"] = integ["openpgl_training_seconds"]
        row["training_spp"] = integ["openpgl_training_spp"]
    if "openpgl_vsp_decision_fraction" in integ:
        row["vsp_decision_fraction"] = integ["openpgl_vsp_decision_fraction"]
    png = os.path.join(out, "images", name + ".png")
    heat = os.path.join(out, "images", name + "__error.png")
    subprocess.run([volguide, "convert", exr, png], check=True, capture_output=True)
    subprocess.run([volguide, "diff", exr, reference, "--error-image", heat], check=True, capture_output=True)
    row["image"] = os.path.relpath(png, out)
    row["error_image"] = os.path.relpath(heat, out)
    return row


def add_speedups(rows):
    """Speed-ups at equal time = relMSE(baseline) / relMSE(method), against volpath and against the
    scene's best unguided method (the lowest relMSE among UNGUIDED_METHODS rows that ran)."""
    base = {r["scene"]: r for r in rows if r["method"] == BASELINE and r["status"] == "ok"}
    best = {}
    for r in rows:
        if r["method"] in UNGUIDED_METHODS and r["status"] == "ok":
            b = best.get(r["scene"])
            if b is None or r["relmse_1e-2"] < b["relmse_1e-2"]:
                best[r["scene"]] = r
    for r in rows:
        if r["status"] != "ok" or not r["relmse_1e-2"] > 0:
            continue
        b = base.get(r["scene"])
        if b:
            r["speedup_1e-2"] = b["relmse_1e-2"] / r["relmse_1e-2"]
            r["speedup_1e-3"] = b["relmse_1e-3"] / r["relmse_1e-3"]
        u = best.get(r["scene"])
        if u:
            r["best_unguided"] = u["method"]
            r["speedup_best_unguided_1e-2"] = u["relmse_1e-2"] / r["relmse_1e-2"]
            r["speedup_best_unguided_1e-3"] = u["relmse_1e-3"] / r["relmse_1e-3"]


def add_net_of_reference(rows, references):
    """relMSE net of the reference's own error. Against a reference R with its own error, an image I
    independent of it measures E[relMSE(I, R)] ~ relMSE(I) + relMSE(R) (the cross terms have mean 0;
    bench/references/README.md checks this sum on the guided references, within 1 %), so the
    reference's estimated relMSE is subtracted. It matters where the reference misses the 1/10 rule
    (long budgets): there the measured figure flatters the worse method and understates every gain."""
    for r in rows:
        if r["status"] != "ok":
            continue
        ref = reference_record(references, r["scene"])["estimated_relmse_1e-2"]
        net = r["relmse_1e-2"] - ref
        r["reference_relmse_1e-2"] = ref
        r["relmse_1e-2_net"] = net if net > 0 else None
        r.pop("speedup_1e-2_net", None)
    base = {r["scene"]: r for r in rows if r["method"] == BASELINE and r["status"] == "ok"}
    for r in rows:
        b = base.get(r["scene"])
        if r["status"] == "ok" and b and r["relmse_1e-2_net"] and b["relmse_1e-2_net"]:
            r["speedup_1e-2_net"] = b["relmse_1e-2_net"] / r["relmse_1e-2_net"]


def reference_record(references, scene):
    path = os.path.join(references, scene + ".json")
    with open(path) as f:
        return json.load(f)


def check_references(rows, scenes, references):
    """The rule of issue 5: a reference's own relMSE <= 1/10 of the best method's at this budget."""
    checks = {}
    for scene in scenes:
        ok_rows = [r for r in rows if r["scene"] == scene and r["status"] == "ok"]
        rec = reference_record(references, scene)
        if not ok_rows:
            continue
        best = min(ok_rows, key=lambda r: r["relmse_1e-2"])
        ratio = rec["estimated_relmse_1e-2"] / best["relmse_1e-2"]
        checks[scene] = {"reference_relmse_1e-2": rec["estimated_relmse_1e-2"], "best_method": best["method"],
                         "best_relmse_1e-2": best["relmse_1e-2"], "ratio": ratio, "meets_rule": ratio <= 0.1}
    return checks


def fmt(v, digits=4):
    return f"{v:.{digits}g}" if isinstance(v, (int, float)) else ""


def write_csv(rows, path):
    cols = ["scene", "method", "status", "time_budget", "seconds", "preprocess_seconds", "render_seconds", "spp",
            "relmse_1e-2", "relmse_1e-3", "relmse_1e-2_trimmed", "relmse_1e-3_trimmed", "mse", "mean",
            "reference_mean", "speedup_1e-2", "speedup_1e-3", "reference_relmse_1e-2", "relmse_1e-2_net",
            "speedup_1e-2_net", "best_unguided", "speedup_best_unguided_1e-2",
            "speedup_best_unguided_1e-3", "branches_mean", "branches_p999", "branches_max",
            "pixel_estimate_seconds", "guided_distance", "guided_direction", "guided_surface",
            "guided_continuation", "training_stage", "note", "command"]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow(r)


def defaults_table(rows, scene):
    """The scene's first table (issue 55): guided_volpath's defaults against the best unguided method."""
    mine = next((r for r in rows if r["scene"] == scene and r["method"] == "guided_volpath" and r["status"] == "ok"),
                None)
    best = next((r for r in rows if r["scene"] == scene and r["method"] == r.get("best_unguided")
                 and r["status"] == "ok"), None)
    if not mine or not best:
        return []
    ratio = best["relmse_1e-2"] / mine["relmse_1e-2"]
    # The split (issue 59): per sample (relMSE x spp, assuming relMSE ~ 1/spp) and time per sample (the
    # render's, training excluded), derived from these equal-time runs.
    per_sample = ratio * best["spp"] / mine["spp"]
    time_ratio = (mine["render_seconds"] / mine["spp"]) / (best["render_seconds"] / best["spp"])
    guided = " / ".join(f"{100 * mine[f'guided_{k}']:.0f} %" if f"guided_{k}" in mine else "-"
                        for k in ("distance", "direction", "surface", "continuation"))
    stage = {0: "coarse", 1: "full", 2: "stopped"}.get(int(mine.get("training_stage", -1)), "")
    return ["| the defaults vs the best unguided | spp | relMSE (1e-2) | ratio (best / defaults) | per sample | "
            "time per sample | guided: distance / direction / surface / continuation | training |",
            "|---|---:|---:|---:|---:|---:|---|---|",
            f"| `guided_volpath` | {mine['spp']} | {fmt(mine['relmse_1e-2'])} | {fmt(ratio, 3)}x | "
            f"{fmt(per_sample, 3)}x | {fmt(time_ratio, 3)}x | {guided} | {stage} |",
            f"| `{best['method']}` | {best['spp']} | {fmt(best['relmse_1e-2'])} | 1x | 1x | 1x | | |", ""]


def table_markdown(rows, scenes, machine, args, checks):
    out = [f"# Equal-time benchmark, {args.time:g} s per render", "",
           f"- machine: {machine['cpu']}, {machine['cores']} cores, {machine['os']}",
           f"- commit: {machine['commit']}, date: {machine['date']}",
           f"- command: `{args.command_line}`",
           "- relMSE = mean over pixels and channels of (I - R)^2 / (R^2 + eps) against bench/references/; "
           "speed-up = relMSE(volpath) / relMSE(method) at equal time (eps 1e-2); "
           f"vs best unguided: relMSE(best of {', '.join(UNGUIDED_METHODS)}) / relMSE(method).", ""]
    for scene in scenes:
        out += [f"## {scene}", ""] + defaults_table(rows, scene)
        out += ["| method | spp | seconds | relMSE (1e-2) | relMSE (1e-3) | "
                "relMSE (1e-3, trimmed) | MSE | speed-up vs volpath | vs best unguided | "
                "relMSE (1e-2) net of the reference's | speed-up (net) | branches mean / p99.9 / max |",
                "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        skipped = []
        for r in rows:
            if r["scene"] != scene:
                continue
            if r["status"] != "ok":
                skipped.append(r)
                continue
            branches = (f"{r['branches_mean']:.3f} / {r['branches_p999']:.0f} / {r['branches_max']:.0f}"
                        if "branches_mean" in r else "")
            out.append(f"| `{r['method']}` | {r['spp']} | {r['seconds']:.1f} | {fmt(r['relmse_1e-2'])} | "
                       f"{fmt(r['relmse_1e-3'])} | {fmt(r['relmse_1e-3_trimmed'])} | {fmt(r['mse'])} | "
                       f"{fmt(r.get('speedup_1e-2'), 3)}x | {fmt(r.get('speedup_best_unguided_1e-2'), 3)}x | "
                       f"{fmt(r.get('relmse_1e-2_net'))} | {fmt(r.get('speedup_1e-2_net'), 3)}x | {branches} |")
        best = next((r["best_unguided"] for r in rows if r["scene"] == scene and "best_unguided" in r), None)
        if best:
            out += ["", f"Best unguided: `{best}`."]
        c = checks.get(scene)
        if c:
            out += ["", f"Reference: estimated relMSE(1e-2) {fmt(c['reference_relmse_1e-2'])} = "
                        f"{c['ratio']:.3f} x the best method's ({c['best_method']}): "
                        f"{'meets' if c['meets_rule'] else 'DOES NOT meet'} the 1/10 rule."]
        for r in skipped:
            out.append(f"- `{r['method']}`: {r['status']}: {r['note']}")
        out.append("")
    return "\n".join(out)


def plot_convergence(rows, scenes, out, checks=None):
    """relMSE vs time, log-log, one curve per method. Where the scene's reference misses the 1/10 rule
    (see check_references), dashed curves show each method's relMSE net of the reference's error
    (add_net_of_reference), down to where the net value stops being positive."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    paths = {}
    for scene in scenes:
        ok = [r for r in rows if r["scene"] == scene and r["status"] == "ok"]
        if not ok:
            continue
        fig, ax = plt.subplots(figsize=(6.4, 4.6), dpi=100)
        for r in ok:
            pts = [(p["seconds"], p["relmse_1e-2"]) for p in r["convergence"] if p["seconds"] > 0 and p["relmse_1e-2"] > 0]
            if pts:
                line, = ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker="o", markersize=3,
                                  label=r["method"])
                c = (checks or {}).get(scene)
                if c and not c["meets_rule"]:
                    ref = c["reference_relmse_1e-2"]
                    net = [(t, e - ref) for t, e in pts if e > ref]
                    if net:
                        ax.loglog([p[0] for p in net], [p[1] for p in net], linestyle="--",
                                  color=line.get_color(), linewidth=1)
        ax.set_xlabel("time (s, training included)")
        ax.set_ylabel("relMSE (eps 1e-2)")
        c = (checks or {}).get(scene)
        ax.set_title(scene + ("" if not c or c["meets_rule"] else
                              f" (dashed: net of the reference's {c['reference_relmse_1e-2']:.2g})"), fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6, loc="lower left")
        fig.tight_layout()
        path = os.path.join(out, "plots", scene + ".png")
        fig.savefig(path)
        plt.close(fig)
        paths[scene] = os.path.relpath(path, out)
    return paths


def crop_html(src, rect, label, zoom=3):
    x, y, w, h = rect
    return (f'<figure class="crop"><div style="width:{w * zoom}px;height:{h * zoom}px;overflow:hidden">'
            f'<img src="{html.escape(src)}" alt="{html.escape(label)}" style="width:{160 * zoom}px;'
            f'margin-left:-{x * zoom}px;margin-top:-{y * zoom}px;image-rendering:pixelated"></div></figure>')


def write_html(rows, scenes, plots, machine, args, checks, out):
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>volguide equal-time benchmark</title>",
             "<style>body{font-family:sans-serif;margin:1em}figure{display:inline-block;margin:4px;"
             "vertical-align:top}figcaption{font-size:12px;max-width:330px}img{display:block}"
             "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px;font-size:13px}"
             ".crop{margin:2px}</style>",
             "<script>var errors=[];window.addEventListener('error',function(e){errors.push(String(e.message||"
             "(e.target&&e.target.src)||'error'))},true);window.addEventListener('load',function(){var imgs="
             "document.images,broken=0;for(var i=0;i<imgs.length;i++){if(!imgs[i].complete||imgs[i].naturalWidth==0)"
             "broken++}var d=document.getElementById('check');d.setAttribute('data-images',imgs.length);"
             "d.setAttribute('data-broken',broken);d.setAttribute('data-errors',errors.length);"
             "d.setAttribute('data-status',(broken==0&&errors.length==0)?'ok':'bad');"
             "d.textContent='images: '+imgs.length+', broken: '+broken+', errors: '+errors.length})</script>",
             "</head><body>",
             f"<h1>volguide equal-time benchmark ({args.time:g} s per render)</h1>",
             f"<p>{html.escape(machine['cpu'])}, {machine['cores']} cores; commit {html.escape(machine['commit'])}; "
             f"{html.escape(machine['date'])}<br><code>{html.escape(args.command_line)}</code></p>",
             "<p id='check' data-status='pending'>checking images…</p>"]
    for scene in scenes:
        srows = [r for r in rows if r["scene"] == scene]
        ok = [r for r in srows if r["status"] == "ok"]
        parts.append(f"<h2 id='{scene}'>{scene}</h2><table><tr><th>method</th><th>spp</th><th>relMSE 1e-2</th>"
                     "<th>relMSE 1e-3</th><th>MSE</th><th>speed-up vs volpath</th><th>vs best unguided</th></tr>")
        for r in ok:
            parts.append(f"<tr><td>{html.escape(r['method'])}</td><td>{r['spp']}</td><td>{fmt(r['relmse_1e-2'])}</td>"
                         f"<td>{fmt(r['relmse_1e-3'])}</td><td>{fmt(r['mse'])}</td>"
                         f"<td>{fmt(r.get('speedup_1e-2'), 3)}x</td>"
                         f"<td>{fmt(r.get('speedup_best_unguided_1e-2'), 3)}x</td></tr>")
        parts.append("</table>")
        skipped = [r for r in srows if r["status"] != "ok"]
        if skipped:
            parts.append("<ul>" + "".join(f"<li>{html.escape(r['method'])}: {r['status']}: {html.escape(r['note'])}</li>"
                                          for r in skipped) + "</ul>")
        c = checks.get(scene)
        if c:
            parts.append(f"<p>Reference relMSE {fmt(c['reference_relmse_1e-2'])} = {c['ratio']:.3f} × best "
                         f"({html.escape(c['best_method'])}).</p>")
        ref_png = os.path.join("images", scene + "__reference.png")
        columns = [("reference", ref_png, None)] + [(r["method"], r["image"], r) for r in ok]
        parts.append("<div>")
        for label, src, r in columns:
            caption = html.escape(label) + (f"<br>{r['spp']} spp, relMSE {fmt(r['relmse_1e-2'], 3)}" if r else "")
            parts.append(f"<figure><img src='{html.escape(src)}' width='320' alt='{html.escape(label)}'>"
                         f"<figcaption>{caption}</figcaption>")
            for rect in CROPS.get(scene, []):
                parts.append(crop_html(src, rect, label + " crop", zoom=4))
            if r:
                parts.append(f"<img src='{html.escape(r['error_image'])}' width='320' alt='error {html.escape(label)}'>"
                             "<figcaption>per-pixel relMSE (log scale 1e-4 … 10)</figcaption>")
            parts.append("</figure>")
        parts.append("</div>")
        if scene in plots:
            parts.append(f"<img src='{html.escape(plots[scene])}' alt='convergence {scene}'>")
    parts.append("</body></html>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(parts))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time", type=float, default=None, help="seconds per render (default 60; 5 with --quick)")
    ap.add_argument("--quick", action="store_true", help="reduced budget for day-to-day use")
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--methods", default=",".join(METHODS), help="comma-separated method names")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=0, help="worker threads (default: all)")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build"))
    ap.add_argument("--openpgl08-build-dir", default=None,
                    help="a build configured with -DVOLGUIDE_OPENPGL_SOURCE=0.8: its volguide runs the VSPG "
                         "peer row 'openpgl_volpath vsp=true' (skipped without it)")
    ap.add_argument("--references", default=os.path.join(ROOT, "bench", "references"),
                    help="directory of <scene>.exr references and their <scene>.json records")
    ap.add_argument("--out", default=None, help="default bench/results/<date>[-quick]")
    ap.add_argument("--print-out-dir", default=None, help=argparse.SUPPRESS)  # for scripts/bench.sh
    args = ap.parse_args()
    if args.time is None:
        args.time = 5.0 if args.quick else 60.0
    if not args.time > 0:
        sys.exit("run_bench: --time must be positive")
    args.command_line = "python3 bench/run_bench.py " + " ".join(sys.argv[1:])
    scenes = args.scenes.split(",")
    methods = args.methods.split(",")
    for s in scenes:
        if s not in SCENES + HELD_OUT:
            sys.exit(f"run_bench: unknown scene '{s}' (known: {', '.join(SCENES + HELD_OUT)})")
        for ext in (".exr", ".json"):
            if not os.path.exists(os.path.join(args.references, s + ext)):
                sys.exit(f"run_bench: {os.path.join(args.references, s + ext)} is missing; "
                         "make it with bench/make_references.py")
    for m in methods:
        if m not in METHODS and m not in EXTRA_METHODS:
            sys.exit(f"run_bench: unknown method '{m}' (known: {', '.join(list(METHODS) + list(EXTRA_METHODS))})")
    volguide = os.path.join(args.build_dir, "volguide")
    if not os.access(volguide, os.X_OK):
        sys.exit(f"run_bench: {volguide} is missing; run `make build` first")
    if args.openpgl08_build_dir:
        args.openpgl08_build_dir = os.path.abspath(args.openpgl08_build_dir)
        if not os.access(os.path.join(args.openpgl08_build_dir, "volguide"), os.X_OK):
            sys.exit(f"run_bench: {args.openpgl08_build_dir}/volguide is missing; build it with "
                     "-DVOLGUIDE_OPENPGL_SOURCE=0.8 first")
    date = datetime.date.today().isoformat()
    # Absolute: generated integrator files are included from the scenes (paths relative to them).
    out = os.path.abspath(args.out) if args.out else os.path.join(ROOT, "bench", "results", date + ("-quick" if args.quick else ""))
    for sub in ("images", "stats", "plots", "integrators"):
        os.makedirs(os.path.join(out, sub), exist_ok=True)
    machine = machine_description()
    if args.print_out_dir:
        with open(args.print_out_dir, "w") as f:
            f.write(out)

    rows = []
    for scene in scenes:
        subprocess.run([volguide, "convert", os.path.join(args.references, scene + ".exr"),
                        os.path.join(out, "images", scene + "__reference.png")], check=True, capture_output=True)
        for method in methods:
            log(f"{scene}: {method} ({args.time:g} s)")
            row = run_method(volguide, scene, method, METHODS.get(method) or EXTRA_METHODS[method], args, out)
            if row["status"] == "ok":
                log(f"  {row['spp']} spp, relMSE(1e-2) {row['relmse_1e-2']:.4g}")
            else:
                log(f"  {row['status']}: {row['note']}")
            rows.append(row)
    add_speedups(rows)
    add_net_of_reference(rows, args.references)
    checks = check_references(rows, scenes, args.references)
    write_csv(rows, os.path.join(out, "results.csv"))
    with open(os.path.join(out, "table.md"), "w") as f:
        f.write(table_markdown(rows, scenes, machine, args, checks) + "\n")
    with open(os.path.join(out, "results.json"), "w") as f:
        json.dump({"machine": machine, "time_budget": args.time, "command": args.command_line, "rows": rows,
                   "reference_checks": checks}, f, indent=1)
    plots = plot_convergence(rows, scenes, out, checks)
    write_html(rows, scenes, plots, machine, args, checks, out)
    log(f"report: {os.path.relpath(out, ROOT)}/index.html, table.md, results.csv, plots/")
    failed = [r for r in rows if r["status"] == "failed"]
    for r in failed:
        log(f"FAILED {r['scene']} {r['method']}: {r['note']}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Renders the converged reference image of every benchmark scene (issue 5).

Each reference is the mean of CHUNKS independent renders (seeds 1001, 1002, ...) of SPP samples per
pixel with an unbiased method; the spread of the chunks gives the reference's own relMSE
(tools/average_renders.cpp), which must be at most 1/10 of the best method's relMSE at the benchmark
budget (checked by bench/run_bench.py, recorded in bench/references/README.md). The renders are
deterministic: the same command reproduces the same EXR bit for bit on the same build (an extended
reference: from the same earlier reference; made at once from all its chunks it is the same image to
float rounding, with an error estimated from every chunk's spread).

    python3 bench/make_references.py [--scenes shafts,cloud] [--build-dir build]

Writes bench/references/<scene>.exr and <scene>.json (how it was made and its estimated error).

    python3 bench/make_references.py --scenes shafts --extend

makes a committed reference longer: the configuration below asks for more chunks than its record lists,
and only the missing ones (the next seeds) are rendered; the reference is kept as the mean of its
recorded chunks (their images are not kept) and averaged with them, the error estimated from the new
chunks' spread. The record keeps what it was extended from and checks the new chunks' own mean against
the earlier reference: an excess over what their two errors predict (a change of method, a bias) above
MAX_EXTEND_EXCESS refuses the extension.
"""
import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# scene: (method -D overrides, spp per chunk, chunks). thin, aniso and cloud are sized so that the
# reference's own relMSE is about 1/16 of the best method's at the 60 s benchmark budget (2026-11-23
# run, Xeon VM, 2 cores; the method is the better of volpath and volpath+equiangular there, both
# unbiased), sss about 1/14; backlit and fogbox, from the first sizing, about 1/11. shafts and cloud
# were raised to 8 chunks on 2026-11-24, when guided methods made their best relMSE at 60 s 1.6x and
# 2.9x lower than volpath's (their 3- and 4-chunk references had fallen to 0.15 and 0.16 of it).
REFERENCES = {
    "shafts": (["integrator=volpath"], 4224, 8),
    "backlit": (["integrator=volpath"], 10752, 3),
    "thin": (["integrator=volpath", "equiangular=true"], 26560, 4),
    "sss": (["integrator=volpath"], 4400, 3),
    "aniso": (["integrator=volpath", "equiangular=true"], 7000, 4),
    "cloud": (["integrator=volpath"], 26500, 8),
    "fogbox": (["integrator=volpath"], 8064, 3),
    # Issue 21's dense back-lit sphere: volpath with the bounded roulette (unbiased like Mitsuba's rule,
    # and of finite variance here). 12 chunks on 2026-11-24 (0.119 of the best relMSE at 60 s, above
    # the 1/10 rule); 32 since 2026-11-25 (the first 12 are the same seeds, so the same bits).
    "densesphere": (["integrator=volpath", "rr_rule=bounded"], 512, 32),
    # Issue 38's dense medium behind a rough dielectric: volpath with the bounded roulette, as
    # densesphere (the strong unguided method in dense high-albedo media); 32 x 1024 spp is ~16x what
    # that method renders in the benchmark's 60 s (so about 1/16 of its relMSE).
    "glassfog": (["integrator=volpath", "rr_rule=bounded"], 1024, 32),
    # Issue 55's held-out scenes (not tuned on): a rough dielectric globe of dense medium under an analytic
    # sky, and a Cornell box with a sphere of moderate fog; volpath with the bounded roulette. Sized as
    # glassfog (32 chunks); the run that made them is recorded in bench/references/README.md.
    "skyglobe": (["integrator=volpath", "rr_rule=bounded"], 512, 32),
    "fogcornell": (["integrator=volpath", "rr_rule=bounded"], 1024, 32),
    # Issue 62's held-out scenes: fog lit only through a door ajar, and a beam from a lantern's hole;
    # volpath with the bounded roulette.
    "door": (["integrator=volpath", "rr_rule=bounded"], 4096, 4),
    "keyhole": (["integrator=volpath", "rr_rule=bounded"], 2048, 4),
}

# Issue 22: where the full guided system made the best relMSE at 60 s so small that the volpath
# references no longer met the 1/10 rule (shafts 0.136, backlit 0.137, aniso 0.47 of it), the reference
# is rendered by that system (bench/references/guided_volpath.xml: guided_volpath's defaults, 50 M
# photons; unbiased, each chunk trains its own field from its own seed) and cross-checked against the
# volpath reference it replaces, kept as bench/references/volpath/<scene>.exr: their relMSE against
# each other must be what their two estimated errors predict (a bias of either shows as an excess).
GUIDED = ["integrator_xml=bench/references/guided_volpath.xml"]
REFERENCES.update({
    "shafts": (GUIDED, 1024, 32),
    "cloud": (GUIDED, 8192, 32),
    "backlit": (GUIDED, 1536, 8),
    "aniso": (GUIDED, 640, 8),
})
CROSS_CHECK_DIR = "volpath"  # under --out-dir: the volpath references the guided ones replaced


def resolve_define(define):
    """integrator_xml paths are relative to the repository (the scenes include them by absolute path)."""
    name, _, value = define.partition("=")
    if name == "integrator_xml" and not os.path.isabs(value):
        return f"{name}={os.path.join(ROOT, value)}"
    return define


def cross_check_reference(out_dir, scene):
    """The volpath reference a guided one is checked against; exits naming it when it is missing."""
    other = os.path.join(out_dir, CROSS_CHECK_DIR, scene + ".exr")
    if not (os.path.exists(other) and os.path.exists(other[:-4] + ".json")):
        sys.exit(f"make_references: {scene}: the guided reference needs {other} and its .json to be "
                 "checked against (move the volpath reference there first)")
    return other


def earlier_reference(out_dir, scene, defines, spp, chunks):
    """The record of the reference --extend makes longer; exits naming what does not fit."""
    path = os.path.join(out_dir, scene + ".json")
    if not (os.path.exists(path) and os.path.exists(path[:-5] + ".exr")):
        sys.exit(f"make_references: --extend: {scene} has no reference to extend ({path[:-5]}.exr and its .json)")
    with open(path) as f:
        record = json.load(f)
    n = record.get("chunks", 0)
    if record.get("defines") != defines or record.get("spp_per_chunk") != spp:
        sys.exit(f"make_references: --extend: {path} was made with {record.get('defines')} at "
                 f"{record.get('spp_per_chunk')} spp per chunk, the configuration asks for {defines} at {spp}: "
                 "only a reference of the same method and chunk size can be made longer")
    if record.get("seeds") != [1001 + k for k in range(n)]:
        sys.exit(f"make_references: --extend: {path} does not list seeds 1001..{1000 + n}")
    if chunks - n < 2:
        sys.exit(f"make_references: --extend: {path} has {n} chunks and the configuration {chunks}: "
                 "at least 2 new chunks are needed to estimate the error from their spread")
    return record


def earlier_check(volguide, average, work_dir, scene, earlier_ref, earlier_record, new_chunks):
    """The new chunks' own mean against the reference they extend: relMSE measured and predicted."""
    tmp = os.path.join(work_dir, f"{scene}-new-chunks-mean.exr")
    new = json.loads(subprocess.run([average, tmp] + new_chunks, check=True, capture_output=True,
                                    text=True).stdout)
    diff = json.loads(subprocess.run([volguide, "diff", "--json", tmp, earlier_ref], check=True,
                                     capture_output=True, text=True).stdout)
    predicted = new["relmse_1e-2"] + earlier_record["estimated_relmse_1e-2"]
    return {
        "new_chunks": len(new_chunks),
        "new_chunks_estimated_relmse_1e-2": new["relmse_1e-2"],
        "relmse_1e-2": diff["relmse_1e-2"],
        "predicted_relmse_1e-2": predicted,
        "excess": diff["relmse_1e-2"] / predicted,
        "mean_ratio": diff["ratio"],
    }


def cross_check(volguide, ref, record, other):
    """relMSE of the new reference against the volpath one it replaced, and what the two errors predict."""
    other_json = other[:-4] + ".json"
    res = subprocess.run([volguide, "diff", "--json", ref, other], check=True, capture_output=True, text=True)
    diff = json.loads(res.stdout)
    with open(other_json) as f:
        other_error = json.load(f)["estimated_relmse_1e-2"]
    predicted = record["estimated_relmse_1e-2"] + other_error
    return {
        "against": os.path.relpath(other, ROOT),
        "relmse_1e-2": diff["relmse_1e-2"],
        "predicted_relmse_1e-2": predicted,
        "excess": diff["relmse_1e-2"] / predicted,
        "mean_ratio": diff["ratio"],
    }


# An extension whose new chunks disagree with the earlier reference by more than this factor of what
# their two estimated errors predict is refused (a changed method or a bias; independent unbiased
# means stay near 1).
MAX_EXTEND_EXCESS = 3.0


def plan(args, scene):
    """What to render for one scene, every check made before anything renders."""
    if scene not in REFERENCES:
        sys.exit(f"make_references: unknown scene '{scene}' (known: {', '.join(REFERENCES)})")
    defines, spp, chunks = REFERENCES[scene]
    if args.spp > 0:
        spp = args.spp
    if args.chunks > 0:
        if args.chunks < 2:
            sys.exit("make_references: --chunks must be >= 2 (the error estimate needs a spread)")
        chunks = args.chunks
    # A guided reference cannot be finished without its cross-check.
    check_against = cross_check_reference(args.out_dir, scene) if defines == GUIDED else None
    earlier = earlier_reference(args.out_dir, scene, defines, spp, chunks) if args.extend else None
    return defines, spp, chunks, check_against, earlier


def render_chunks(args, volguide, scene, defines, spp, first, chunks):
    """Renders the chunks first..chunks-1 that the work dir lacks; their files and summed render time."""
    xml = os.path.join(ROOT, "bench", "scenes", scene + ".xml")
    chunk_files, seconds = [], 0.0
    for k in range(first, chunks):
        seed = 1001 + k
        out = os.path.join(args.work_dir, f"{scene}-{spp}spp-{seed}.exr")
        stats = out[:-4] + ".json"
        if not (os.path.exists(out) and os.path.exists(stats)):
            cmd = [volguide, "render", xml, "-o", out, "--spp", str(spp), "--seed", str(seed),
                   "--stats", stats, "--quiet"]
            for d in defines:
                cmd += ["-D", resolve_define(d)]
            print(f"[{time.strftime('%H:%M:%S')}] {scene}: chunk {k + 1}/{chunks} ({spp} spp, seed {seed})",
                  file=sys.stderr, flush=True)
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        with open(stats) as f:
            seconds += json.load(f)["time"]["total_with_load"]
        chunk_files.append(out)
    return chunk_files, seconds


def make_reference(args, volguide, average, scene, defines, spp, chunks, check_against, earlier):
    first = earlier["chunks"] if earlier else 0
    chunk_files, seconds = render_chunks(args, volguide, scene, defines, spp, first, chunks)
    os.makedirs(args.out_dir, exist_ok=True)
    ref = os.path.join(args.out_dir, scene + ".exr")
    # The new image and record are written beside the old ones and replace them together once both are
    # complete: a failed run leaves the reference and its record as they were (an EXR that no longer
    # matched its record would make a later --extend count chunks twice).
    new_ref = os.path.join(args.out_dir, scene + ".new.exr")
    new_json = new_ref[:-4] + ".json"
    average_cmd = [average, new_ref]
    if earlier:
        check = earlier_check(volguide, average, args.work_dir, scene, ref, earlier, chunk_files)
        print(f"{scene}: the {check['new_chunks']} new chunks' mean against the earlier reference: relMSE(1e-2) "
              f"{check['relmse_1e-2']:.3g}, predicted {check['predicted_relmse_1e-2']:.3g} "
              f"({check['excess']:.2f}x), mean ratio {check['mean_ratio']:.5f}", flush=True)
        if not check["excess"] <= MAX_EXTEND_EXCESS:
            sys.exit(f"make_references: --extend: {scene}'s new chunks disagree with {ref} by {check['excess']:.2f}x "
                     f"what their errors predict (> {MAX_EXTEND_EXCESS}): not the same method, or one is biased; "
                     "the reference is left as it was")
        average_cmd += ["--earlier", ref, str(earlier["chunks"])]
    res = subprocess.run(average_cmd + chunk_files, check=True, capture_output=True, text=True)
    estimate = json.loads(res.stdout)
    record = {
        "scene": f"bench/scenes/{scene}.xml",
        "defines": defines,
        "spp": spp * chunks,
        "chunks": chunks,
        "spp_per_chunk": spp,
        "seeds": [1001 + k for k in range(chunks)],
        "render_seconds": round(seconds + (earlier["render_seconds"] if earlier else 0.0), 1),
        "estimated_relmse_1e-2": estimate["relmse_1e-2"],
        "estimated_relmse_1e-3": estimate["relmse_1e-3"],
        "estimated_mse": estimate["mse"],
        "command": f"python3 bench/make_references.py --scenes {scene}" +
                   (f" --spp {args.spp}" if args.spp > 0 else "") +
                   (f" --chunks {args.chunks}" if args.chunks > 0 else "") +
                   (" --extend" if earlier else ""),
    }
    if earlier:
        # What it was made longer from (its own history included; the cross-check is redone below).
        record["extended_from"] = {k: v for k, v in earlier.items() if k != "cross_check"}
        record["error_from_seeds"] = [1001 + k for k in range(first, chunks)]
        record["new_chunks_against_earlier"] = check
    if check_against:
        record["cross_check"] = cross_check(volguide, new_ref, record, check_against)
        c = record["cross_check"]
        print(f"{scene}: against {c['against']}: relMSE(1e-2) {c['relmse_1e-2']:.3g}, predicted by the two "
              f"estimated errors {c['predicted_relmse_1e-2']:.3g} ({c['excess']:.2f}x), mean ratio "
              f"{c['mean_ratio']:.5f}", flush=True)
    with open(new_json, "w") as f:
        json.dump(record, f, indent=2)
        f.write("\n")
    os.replace(new_ref, ref)
    os.replace(new_json, ref[:-4] + ".json")
    print(f"{scene}: {spp * chunks} spp in {record['render_seconds']:.0f} s, estimated relMSE(1e-2) "
          f"{estimate['relmse_1e-2']:.3g}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default=",".join(REFERENCES), help="comma-separated scene names")
    ap.add_argument("--build-dir", default=os.path.join(ROOT, "build"))
    ap.add_argument("--work-dir", default=os.path.join(ROOT, "bench", "references", "chunks"),
                    help="where the chunk renders go (kept, so an interrupted run resumes)")
    ap.add_argument("--out-dir", default=os.path.join(ROOT, "bench", "references"),
                    help="where <scene>.exr and <scene>.json go")
    ap.add_argument("--spp", type=int, default=0, help="override the spp per chunk (tests, previews)")
    ap.add_argument("--chunks", type=int, default=0, help="override the number of chunks (tests, previews; >= 2)")
    ap.add_argument("--extend", action="store_true",
                    help="make the existing reference longer: render only the chunks its record lacks")
    args = ap.parse_args()
    volguide = os.path.join(args.build_dir, "volguide")
    average = os.path.join(args.build_dir, "average_renders")
    for tool in (volguide, average):
        if not os.access(tool, os.X_OK):
            sys.exit(f"make_references: {tool} is missing; run `make build` first")
    # Every scene is checked before any renders (a refusal must not come after hours of chunks).
    plans = [(scene, plan(args, scene)) for scene in args.scenes.split(",")]
    os.makedirs(args.work_dir, exist_ok=True)
    for scene, p in plans:
        make_reference(args, volguide, average, scene, *p)


if __name__ == "__main__":
    main()

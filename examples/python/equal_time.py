#!/usr/bin/env python3
"""Equal-time comparison: volpath and the guided system (guided_volpath) render the same scene for the
same time budget (the guided budget includes its training); their relMSE against a reference is
plotted against time (the render's convergence curve at 1, 2, 4, ... spp), next to the final images.

    PYTHONPATH=build/python python3 examples/python/equal_time.py --time 30 --out equal_time.png

With the default scene (bench/scenes/shafts.xml at 160 x 120) the reference is
bench/references/shafts.exr; another scene or size renders its own reference with volpath for
--reference-time seconds (a noisy reference flattens the curves at its own error).
"""
import argparse
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import volguide  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def parse_parameters(text):
    """'k=v k=v' -> dict with ints, floats and booleans typed as the XML would type them."""
    params = {}
    for item in text.split():
        key, _, value = item.partition("=")
        if value in ("true", "false"):
            params[key] = value == "true"
            continue
        for cast in (int, float):
            try:
                params[key] = cast(value)
                break
            except ValueError:
                pass
        else:
            params[key] = value
    return params


def tonemap(image):
    return np.clip(image / (1 + image), 0, 1) ** (1 / 2.2)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=str(ROOT / "bench/scenes/shafts.xml"))
    ap.add_argument("--width", type=int, help="film width (-D width); default: the scene's")
    ap.add_argument("--height", type=int, help="film height (-D height)")
    ap.add_argument("--time", type=float, default=30.0, help="seconds per method (default 30)")
    ap.add_argument("--reference", help="reference EXR (default: bench/references/<scene>.exr if its size fits)")
    ap.add_argument("--reference-time", type=float, default=120.0,
                    help="seconds of volpath for a reference rendered here (default 120)")
    ap.add_argument("--guided", default="distance=incremental direction=product rrs=grrs",
                    help="guided_volpath parameters, 'k=v k=v' (default: %(default)s)")
    ap.add_argument("--threads", type=int, help="threads (default: all)")
    ap.add_argument("--out", default="equal_time.png")
    args = ap.parse_args(argv)

    defines = {k: v for k, v in (("width", args.width), ("height", args.height)) if v}
    scene = volguide.load_scene(args.scene, **defines)
    reference_file = pathlib.Path(args.reference) if args.reference else (
        ROOT / "bench/references" / (pathlib.Path(args.scene).stem + ".exr"))
    reference = volguide.read_image(str(reference_file)) if reference_file.exists() else None
    if reference is None or reference.shape[:2] != (scene.height, scene.width):
        if args.reference:
            sys.exit(f"{args.reference}: size differs from the film's {scene.width}x{scene.height}")
        print(f"rendering a volpath reference for {args.reference_time:g} s ...", flush=True)
        reference, _ = volguide.render(scene, time=args.reference_time, seed=99991, threads=args.threads,
                                       integrator=volguide.create_integrator("volpath", max_depth=64))

    methods = {
        "volpath": volguide.create_integrator("volpath", max_depth=64),
        "guided_volpath " + args.guided: volguide.create_integrator("guided_volpath", max_depth=64,
                                                                    **parse_parameters(args.guided)),
    }
    results = {}
    for name, integrator in methods.items():
        image, stats = volguide.render(scene, time=args.time, seed=1, threads=args.threads,
                                       integrator=integrator, reference=reference)
        results[name] = (image, stats)
        print(f"{name}: {stats['spp']} spp in {stats['time']['total']:.2f} s "
              f"(preprocess {stats['time']['preprocess']:.2f} s), relMSE {stats['reference']['relmse_1e-2']:.4g}")

    fig, axes = plt.subplots(1, 1 + len(results), figsize=(5 + 4 * len(results), 3.8))
    curves = axes[0]
    for name, (image, stats) in results.items():
        points = stats["convergence"]
        curves.loglog([p["seconds"] for p in points], [p["relmse_1e-2"] for p in points], "o-", label=name.replace(" ", "\n", 1))
    curves.set_xlabel("time [s] (training included)")
    curves.set_ylabel("relMSE (eps 1e-2)")
    curves.set_title(pathlib.Path(args.scene).stem + f", {args.time:g} s each")
    curves.grid(True, which="both", alpha=0.3)
    curves.legend(fontsize=7)
    for ax, (name, (image, stats)) in zip(axes[1:], results.items()):
        ax.imshow(tonemap(image))
        ax.set_title(f"{name.split()[0]}: {stats['spp']} spp, relMSE {stats['reference']['relmse_1e-2']:.3g}",
                     fontsize=8)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

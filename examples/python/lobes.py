#!/usr/bin/env python3
"""A guiding-field leaf seen from a point: its incident radiance L~(x, w) and the product guide
(V_L x the phase function, what guided direction sampling draws from) at a medium vertex, each next
to a converged reference computed with volpath's radiance along the same directions.

    PYTHONPATH=build/python python3 examples/python/lobes.py --out lobes.png

Maps are equirectangular over the sphere of directions w (towards the light; columns: azimuth
atan2(w.z, w.x) from -pi to pi, rows: polar angle from +y). The reference of the product is
f_HG(-d, w) L(x, w) normalised to a pdf, d the travel direction at the vertex.

The scene must take the HG mean cosine as the define `g` (the default, scenes/hg_fog.xml, does), so
that the field's product and the reference use the medium's own phase function. volguide.radiance
starts its paths in the camera's medium, as camera rays do: the point must lie in that medium (in
hg_fog the camera sits in the fog). Lights must not be delta lights (a directional or spot light never
shows up in a reference traced towards it).
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import volguide  # noqa: E402

def vector(text):
    v = np.array([float(x) for x in text.split(",")], np.float32)
    if v.shape != (3,):
        raise argparse.ArgumentTypeError("expected x,y,z")
    return v


def directions(theta, phi):
    """Unit vectors for polar angle theta (from +y) and azimuth phi."""
    s = np.sin(theta)
    return np.stack([s * np.cos(phi), np.cos(theta), s * np.sin(phi)], axis=-1)


def pixel_grid(rows):
    """Centres of an equirectangular map of rows x 2 rows pixels and each pixel's solid angle."""
    theta = (np.arange(rows) + 0.5) * np.pi / rows
    phi = -np.pi + (np.arange(2 * rows) + 0.5) * np.pi / rows
    t, p = np.meshgrid(theta, phi, indexing="ij")
    return t, p, np.sin(t) * (np.pi / rows) ** 2


def reference_radiance(scene, point, rows, spp, threads):
    """L(x, w) averaged over each pixel: spp jittered directions per pixel, one volpath path each."""
    rng = np.random.default_rng(7)
    t, p, _ = pixel_grid(rows)
    total = np.zeros(t.shape + (3,))
    step = np.pi / rows
    for k in range(spp):
        jt = t + (rng.random(t.shape) - 0.5) * step
        jp = p + (rng.random(p.shape) - 0.5) * step
        dirs = directions(jt, jp).reshape(-1, 3).astype(np.float32)
        total += volguide.radiance(scene, point, dirs, spp=1, seed=k, threads=threads).reshape(total.shape)
    return total / spp


def hg(g, cos_theta):
    return (1 - g * g) / (4 * np.pi * (1 + g * g - 2 * g * cos_theta) ** 1.5)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=str(pathlib.Path(__file__).resolve().parent / "scenes/hg_fog.xml"))
    ap.add_argument("--point", type=vector, default=vector("0.3,-0.2,0.2"), help="x,y,z (default: in the fog)")
    ap.add_argument("--direction", type=vector, default=vector("0,0,-1"),
                    help="travel direction d at the vertex (default: along the camera's view, -z)")
    ap.add_argument("--g", type=float, default=0.6, help="the fog's HG mean cosine, passed as -D g (default 0.6)")
    ap.add_argument("--photons", type=int, default=1000000, help="training photons (default 1 M)")
    ap.add_argument("--field", help="load this saved field instead of training")
    ap.add_argument("--rows", type=int, default=64, help="map height in pixels (width 2 x rows)")
    ap.add_argument("--reference-spp", type=int, default=256, help="reference paths per map pixel")
    ap.add_argument("--threads", type=int)
    ap.add_argument("--out", default="lobes.png")
    args = ap.parse_args(argv)

    scene = volguide.load_scene(args.scene, g=args.g)
    if args.field:
        field = volguide.Field.load(args.field, scene)
    else:
        field = volguide.train(scene, threads=args.threads,
                               integrator=volguide.create_integrator("guided_volpath", photons=args.photons))
    leaf = int(field.leaf_at(args.point)[0])
    if leaf < 0:
        raise SystemExit(f"the point {args.point} is outside the field's bounds {field.bounds}")
    leaves = field.leaves()
    d = args.direction / np.linalg.norm(args.direction)

    t, p, solid_angle = pixel_grid(args.rows)
    dirs = directions(t, p).reshape(-1, 3).astype(np.float32)
    shape = t.shape
    incident = field.incident(args.point, dirs).mean(axis=1).reshape(shape)
    product = field.direction_pdf(args.point, d, args.g, dirs, mode="product", phase_prob=0.0).reshape(shape)
    reference = reference_radiance(scene, args.point, args.rows, args.reference_spp, args.threads).mean(axis=2)
    target = hg(args.g, directions(t, p) @ d) * reference
    target_pdf = target / max(np.sum(target * solid_angle), 1e-30)

    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), constrained_layout=True)
    extent = (-180, 180, 180, 0)
    rows = [("incident radiance L~(x, w) (field)", incident, "reference L(x, w) (volpath)", reference),
            ("product guide pdf V_L x phase (field)", product, "reference f_HG L, normalised", target_pdf)]
    for r, (title_a, a, title_b, b) in enumerate(rows):
        positive = np.concatenate([a[a > 0], b[b > 0]])
        top = positive.max() if positive.size else 1.0
        norm = mcolors.LogNorm(vmin=top * 1e-4, vmax=top)
        for c, (title, data) in enumerate(((title_a, a), (title_b, b))):
            im = axes[r, c].imshow(np.maximum(data, top * 1e-4), extent=extent, norm=norm, cmap="inferno",
                                   aspect="auto")
            axes[r, c].set_title(title, fontsize=9)
            axes[r, c].set_xlabel("azimuth [deg]", fontsize=8)
            axes[r, c].set_ylabel("polar angle from +y [deg]", fontsize=8)
        fig.colorbar(im, ax=axes[r, :].tolist(), shrink=0.9)
    fig.suptitle(f"{pathlib.Path(args.scene).stem}: x = {tuple(np.round(args.point, 3))}, leaf {leaf} "
                 f"({leaves['samples'][leaf]} samples, {leaves['lobes'][leaf]} lobes, "
                 f"{'valid' if leaves['valid'][leaf] else 'invalid'}), d = {tuple(np.round(d, 3))}, g = {args.g}",
                 fontsize=10)
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

"""The guiding field from Python: training, the leaves as arrays, L~ and L~_i, the guided direction
pdf, save/load, the pixel estimate. Expected values are computed here with numpy from the leaves'
own lobes, independently of the library's evaluation."""
import numpy as np
import pytest

import volguide


def vmf_mixture_pdf(weights, mu, kappa, w):
    """sum_k w_k kappa_k / (4 pi sinh kappa_k) exp(kappa_k mu_k . w) for one direction w."""
    w = np.asarray(w, np.float64) / np.linalg.norm(w)
    total = 0.0
    for wk, mk, kk in zip(weights, mu, kappa):
        if wk == 0:
            continue
        if kk < 1e-4:
            total += wk / (4 * np.pi)
        else:  # exp(k (cos - 1)) k / (2 pi (1 - exp(-2k))), stable for large kappa
            total += wk * kk / (2 * np.pi * (1 - np.exp(-2 * kk))) * np.exp(kk * (np.dot(mk, w) - 1))
    return total


@pytest.fixture
def trained(fogbox, guided):
    return volguide.train(fogbox, integrator=guided, threads=2)


def test_leaves_are_consistent_arrays(trained):
    leaves = trained.leaves()
    n = trained.leaf_count
    assert n > 1
    assert leaves["lo"].shape == (n, 3) and leaves["fluence"].shape == (n, 3)
    assert (leaves["lo"] <= leaves["hi"]).all()
    k = leaves["weights"].shape[1]
    assert leaves["mu"].shape == (n, k, 3) and leaves["kappa"].shape == (n, k)
    valid = leaves["valid"]
    assert valid.any()
    np.testing.assert_allclose(leaves["weights"][valid].sum(axis=1), 1.0, rtol=1e-5)
    assert (leaves["samples"][valid] > 0).all()
    # A trained field's medium fractions are measured (guided_volpath measures them once per field).
    fraction = leaves["medium_fraction"]
    assert fraction.shape == (n,) and ((fraction >= 0) & (fraction <= 1)).all()
    # Lobes beyond each leaf's count are zero.
    for i in range(n):
        assert not leaves["weights"][i, leaves["lobes"][i]:].any()
    # The leaves tile the field: each centre lies in its own leaf.
    centres = 0.5 * (leaves["lo"] + leaves["hi"])
    assert np.array_equal(trained.leaf_at(centres), np.arange(n))
    assert trained.leaf_at([100.0, 100.0, 100.0])[0] == -1


def test_incident_is_fluence_times_the_leaf_vmm(trained):
    leaves = trained.leaves()
    centres = 0.5 * (leaves["lo"] + leaves["hi"])
    rng = np.random.default_rng(1)
    for i in np.flatnonzero(leaves["valid"])[:10]:
        w = rng.normal(size=3)
        w /= np.linalg.norm(w)
        expected = leaves["fluence"][i] * vmf_mixture_pdf(leaves["weights"][i], leaves["mu"][i], leaves["kappa"][i], w)
        np.testing.assert_allclose(trained.incident(centres[i], w)[0], expected, rtol=2e-3, atol=1e-7)
    assert np.array_equal(trained.incident([100.0, 0.0, 0.0], [0.0, 1.0, 0.0]), np.zeros((1, 3)))


def test_isotropic_inscattered_radiance_is_fluence_over_4pi(trained):
    leaves = trained.leaves()
    valid = leaves["valid"]
    centres = 0.5 * (leaves["lo"] + leaves["hi"])[valid]
    for mode in ("exact", "a3"):
        np.testing.assert_allclose(trained.inscattered(centres, [0.3, 0.4, 0.5], 0.0, mode=mode),
                                   leaves["fluence"][valid] / (4 * np.pi), rtol=1e-3)
    # A forward-peaked phase function moves L~_i towards L~ along the travel direction.
    forward = trained.inscattered(centres[0], [0.0, 1.0, 0.0], 0.9)
    assert np.isfinite(forward).all() and (forward >= 0).all()
    with pytest.raises(ValueError):
        trained.inscattered(centres, [0.0, 1.0, 0.0], 0.0, mode="nope")


def sphere_grid(n):
    """Midpoint quadrature on the sphere: directions (n*2n, 3) and their solid angles."""
    theta = (np.arange(n) + 0.5) * np.pi / n
    phi = (np.arange(2 * n) + 0.5) * np.pi / n
    t, p = np.meshgrid(theta, phi, indexing="ij")
    dirs = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1).reshape(-1, 3)
    area = (np.sin(t) * (np.pi / n) ** 2).reshape(-1)
    return dirs, area


def test_direction_pdfs_integrate_to_one(trained):
    dirs, area = sphere_grid(200)
    point, direction = [0.0, -0.5, 0.0], [0.0, 1.0, 0.0]
    for mode in ("product", "incident"):
        for phase_prob in (0.0, 0.5):
            pdf = trained.direction_pdf(point, direction, 0.5, dirs, mode=mode, phase_prob=phase_prob)
            assert np.sum(pdf * area) == pytest.approx(1.0, abs=1e-2)
    lobes = trained.product_lobes(point, direction, 0.5)
    assert lobes["guided"] and lobes["integral"] > 0
    np.testing.assert_allclose(lobes["weights"].sum(), 1.0, rtol=1e-4)


def test_save_and_load_roundtrip(trained, tmp_path):
    path = str(tmp_path / "field.vgf")
    trained.save(path)
    loaded = volguide.Field.load(path)
    a, b = trained.leaves(), loaded.leaves()
    for key in a:
        assert np.array_equal(a[key], b[key]), key
    (tmp_path / "junk.vgf").write_bytes(b"not a field")
    with pytest.raises(volguide.FieldError):
        volguide.Field.load(str(tmp_path / "junk.vgf"))


def test_render_keeps_the_trained_field_and_pixel_estimate(fogbox, guided):
    image, stats = volguide.render(fogbox, spp=2, integrator=guided, threads=2)
    assert np.isfinite(image).all()
    # 2 spp are the training's coarse stage: a quarter of the photons (training_stage.h)
    assert stats["integrator"]["training_stage"] == 0
    assert stats["integrator"]["photons_traced"] == 20000 // 4
    field = guided.field
    assert field is not None and field.leaf_count > 1
    estimate = guided.pixel_estimate
    assert estimate.shape == (24, 32, 3) and np.isfinite(estimate).all() and estimate.mean() > 0
    # The module's own raymarch of the same field, same settings and seed, is the same estimate.
    again = volguide.pixel_estimate(fogbox, field, rays_per_pixel=4, seed=0, threads=2)
    np.testing.assert_allclose(again, estimate, rtol=1e-5, atol=1e-7)
    assert volguide.create_integrator("volpath").field is None


def test_train_needs_a_guided_integrator(fogbox):
    with pytest.raises(ValueError, match="guided_volpath"):
        volguide.train(fogbox)

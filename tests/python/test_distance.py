"""The guided distance pdf along a ray (Field.distance_pdf): a distribution over (0, t_end) plus
the mass of reaching t_end; pure transmittance sampling (c_T = 1) is the exponential of the fog's
extinction; the segment stops at the first surface; the bins tile it."""
import numpy as np
import pytest

import volguide
from conftest import SCENES, TINY

# fogbox: thin grey fog (sigma_t 0.25) around the camera; the glass sphere (centre (0, 0.25, 0),
# radius 0.3) is the first surface a ray from (0, 0, 3) along -z meets, at z = sqrt(0.3^2 - 0.25^2).
ORIGIN, DIRECTION = [0.0, 0.0, 3.0], [0.0, 0.0, -1.0]
T_SPHERE = 3.0 - np.sqrt(0.3 ** 2 - 0.25 ** 2)


@pytest.fixture
def trained(fogbox, guided):
    return volguide.train(fogbox, integrator=guided, threads=2)


@pytest.mark.parametrize("sampler", ["tabulated", "incremental"])
def test_distance_pdf_is_a_distribution(trained, sampler):
    r = trained.distance_pdf(ORIGIN, DIRECTION, 10.0, sampler=sampler, n=4000)
    assert r["t_end"] == pytest.approx(T_SPHERE, abs=1e-3)
    assert r["g"] == 0.0
    assert (r["pdf"] >= 0).all() and 0.0 <= r["surface_probability"] <= 1.0
    integral = r["pdf"].mean() * r["t_end"]  # midpoint rule over (0, t_end)
    assert integral + r["surface_probability"] == pytest.approx(1.0, abs=1e-2)
    bins = r["bins"]
    assert bins["t0"][0] == 0.0 and bins["t1"][-1] == pytest.approx(r["t_end"], rel=1e-5)
    assert np.array_equal(bins["t0"][1:], bins["t1"][:-1])
    np.testing.assert_allclose(bins["sigma_t"], 0.25, rtol=1e-6)
    assert bins["valid"].any() and (bins["inscattered"][bins["valid"]] > 0).all()


def test_transmittance_only_is_the_exponential(trained):
    r = trained.distance_pdf(ORIGIN, DIRECTION, 2.0, c_T=1.0, t=np.linspace(0.01, 1.99, 50))
    assert r["t_end"] == pytest.approx(2.0)
    np.testing.assert_allclose(r["pdf"], 0.25 * np.exp(-0.25 * r["t"]), rtol=1e-4)
    assert r["surface_probability"] == pytest.approx(np.exp(-0.25 * 2.0), rel=1e-4)


def test_distance_pdf_needs_a_medium_and_a_scene(trained, tmp_path):
    thin = volguide.load_scene(str(SCENES / "thin.xml"), **TINY)  # camera in vacuum
    with pytest.raises(ValueError, match="vacuum"):
        trained.distance_pdf([0.0, 0.0, 4.5], [0.0, 0.0, 1.0], 1.0, scene=thin)
    path = str(tmp_path / "field.vgf")
    trained.save(path)
    with pytest.raises(ValueError, match="scene"):
        volguide.Field.load(path).distance_pdf(ORIGIN, DIRECTION, 1.0)
    loaded = volguide.Field.load(path, trained.scene)
    a = loaded.distance_pdf(ORIGIN, DIRECTION, 10.0)
    b = trained.distance_pdf(ORIGIN, DIRECTION, 10.0)
    assert np.array_equal(a["pdf"], b["pdf"])


def test_distance_regions_are_a_distribution_over_fewer_bins(trained):
    leaves = trained.distance_pdf(ORIGIN, DIRECTION, 10.0, sampler="incremental", n=4000)
    merged = trained.distance_pdf(ORIGIN, DIRECTION, 10.0, sampler="incremental", n=4000, distance_merge=1.0)
    assert len(leaves["bins"]["t0"]) > 1
    assert len(merged["bins"]["t0"]) < len(leaves["bins"]["t0"])  # tolerance 1: one leaf group crossed
    integral = merged["pdf"].mean() * merged["t_end"]
    assert integral + merged["surface_probability"] == pytest.approx(1.0, abs=1e-2)
    with pytest.raises(ValueError, match="distance_merge"):
        trained.distance_pdf(ORIGIN, DIRECTION, 10.0, distance_merge=-1.0)

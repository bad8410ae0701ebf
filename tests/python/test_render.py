"""Rendering into arrays, the stats dict, images and relMSE, scene errors."""
import numpy as np
import pytest

import volguide
from conftest import SCENES, TINY


def test_render_returns_float32_image_and_stats(fogbox):
    image, stats = volguide.render(fogbox, spp=4, threads=2)
    assert image.shape == (24, 32, 3) and image.dtype == np.float32
    assert np.isfinite(image).all() and image.mean() > 0
    assert stats["spp"] == 4 and stats["width"] == 32 and stats["height"] == 24
    assert stats["samples"] == 32 * 24 * 4
    assert not stats["cancelled"] and not stats["time_limited"]
    assert set(stats["time"]) == {"load", "preprocess", "render", "total", "total_with_load"}
    # volpath's counters are the work it counted (volpath/work.h), one camera sample per sample drawn
    assert stats["integrator"] and all(k.startswith("work_") for k in stats["integrator"])
    assert stats["integrator"]["work_camera_samples"] == 32 * 24 * 4


def test_render_is_deterministic_for_a_seed_and_any_thread_count(fogbox):
    a, _ = volguide.render(fogbox, spp=4, seed=3, threads=1)
    b, _ = volguide.render(fogbox, spp=4, seed=3, threads=2)
    c, _ = volguide.render(fogbox, spp=4, seed=4, threads=2)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_time_budget_stops_the_render(fogbox):
    _, stats = volguide.render(fogbox, time=0.3, threads=2)
    assert stats["time_limited"] and stats["spp"] > 0
    assert stats["time"]["total"] < 3.0


def test_create_integrator_renders_like_the_scenes_own(fogbox):
    own, _ = volguide.render(fogbox, spp=2, seed=1)
    same = volguide.create_integrator("volpath", max_depth=64, equiangular=False)
    other = volguide.create_integrator("volpath", max_depth=1)
    assert np.array_equal(own, volguide.render(fogbox, spp=2, seed=1, integrator=same)[0])
    assert not np.array_equal(own, volguide.render(fogbox, spp=2, seed=1, integrator=other)[0])


def test_defines_reach_the_scene():
    scene = volguide.load_scene(str(SCENES / "thin.xml"), width=20, height=10, spp=1, equiangular=True)
    assert (scene.width, scene.height) == (20, 10)
    assert scene.defines["equiangular"] == "true"
    assert "equiangular=true" in repr(scene.integrator)


def test_bad_arguments_raise_value_error(fogbox):
    for kwargs in ({"spp": 0}, {"time": -1.0}, {"threads": 0}):
        with pytest.raises(ValueError):
            volguide.render(fogbox, **kwargs)


def test_image_roundtrip_and_relmse(fogbox, tmp_path):
    image, _ = volguide.render(fogbox, spp=2, seed=1)
    reference, _ = volguide.render(fogbox, spp=16, seed=2)
    path = str(tmp_path / "image.exr")
    volguide.write_image(path, image)
    assert np.array_equal(volguide.read_image(path), image)
    # relMSE by numpy from its definition, and as the CLI's `diff` computes it.
    expected = np.mean((image.astype(np.float64) - reference) ** 2 / (reference.astype(np.float64) ** 2 + 1e-2))
    assert volguide.relmse(image, reference) == pytest.approx(expected, rel=1e-6)
    assert volguide.compare_images(image, reference)["relmse_1e-2"] == pytest.approx(expected, rel=1e-6)
    assert volguide.relmse(reference, reference) == 0.0
    with pytest.raises(ValueError):
        volguide.relmse(image, reference[:10])
    volguide.write_image(str(tmp_path / "preview.png"), image)
    assert volguide.read_image(str(tmp_path / "preview.png")).shape == image.shape


def test_scene_error_carries_file_and_line(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<scene version="3.0.0">\n'
                   '  <integrator type="volpath"/>\n'
                   '  <shape type="sphere"><float name="radius" value="abc"/></shape>\n'
                   '</scene>\n')
    with pytest.raises(volguide.SceneError) as info:
        volguide.load_scene(str(bad))
    error = info.value
    assert isinstance(error, ValueError)
    assert error.file.endswith("bad.xml") and error.line == 3
    assert f"bad.xml:3:" in str(error) and error.message in str(error)


def test_unknown_define_and_integrator_parameter_are_scene_errors():
    with pytest.raises(volguide.SceneError, match="nosuch"):
        volguide.load_scene(str(SCENES / "fogbox.xml"), nosuch=1)
    with pytest.raises(volguide.SceneError, match="no_such_parameter"):
        volguide.create_integrator("volpath", no_such_parameter=3)
    with pytest.raises(volguide.SceneError):
        volguide.create_integrator("no_such_integrator")


def test_radiance_sees_the_light_and_nothing_else():
    # thin.xml: a 400 W/m^2/sr rectangle at x = 2.5 facing -x, centred at (2.5, 0.5, 0); vacuum
    # outside the unit sphere of fog at the origin, no environment.
    scene = volguide.load_scene(str(SCENES / "thin.xml"), **TINY)
    values = volguide.radiance(scene, [[1.5, 0.5, 0.0], [1.5, 0.5, 0.0], [0.0, 0.0, 4.5]],
                               [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], spp=4)
    assert values.shape == (3, 3)
    np.testing.assert_allclose(values[0], [400.0, 400.0, 400.0], rtol=1e-6)
    assert np.array_equal(values[1:], np.zeros((2, 3)))
    with pytest.raises(ValueError):
        volguide.radiance(scene, np.zeros((2, 3)), np.ones((3, 3)))


def test_reference_gives_the_convergence_curve(fogbox):
    reference, _ = volguide.render(fogbox, spp=32, seed=7)
    image, stats = volguide.render(fogbox, spp=16, seed=1, reference=reference)
    curve = stats["convergence"]
    assert [p["spp"] for p in curve] == [1, 2, 4, 8, 16]
    assert all(a["seconds"] <= b["seconds"] for a, b in zip(curve, curve[1:]))
    assert stats["reference"]["relmse_1e-2"] == pytest.approx(volguide.relmse(image, reference), rel=1e-6)
    assert curve[-1]["relmse_1e-2"] == stats["reference"]["relmse_1e-2"]
    assert curve[-1]["relmse_1e-2"] < curve[0]["relmse_1e-2"]
    with pytest.raises(ValueError):
        volguide.render(fogbox, spp=1, reference=reference[:5])

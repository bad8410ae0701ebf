"""Shared fixtures of the Python module's tests (run by CTest as `python_module`, PYTHONPATH set to
build/python). Scenes are the benchmark scenes at tiny sizes so that the suite takes seconds."""
import os
import pathlib

import pytest

import volguide

SOURCE_DIR = pathlib.Path(os.environ.get("VOLGUIDE_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE_DIR / "bench" / "scenes"
TINY = dict(width=32, height=24, spp=4)


@pytest.fixture
def fogbox():
    return volguide.load_scene(str(SCENES / "fogbox.xml"), **TINY)


@pytest.fixture
def guided():
    """A guided_volpath integrator that trains in well under a second."""
    return volguide.create_integrator("guided_volpath", photons=20000, distance="incremental",
                                      direction="product", rrs="grrs")

"""volguide: zero-variance-based volume path guiding, from Python.

Render into numpy arrays, sweep parameters, and look inside the guiding field. See docs/python.md.
"""
from ._core import *  # noqa: F401,F403
from ._core import __doc__ as _core_doc  # noqa: F401

__all__ = [
    "SceneError", "FieldError", "Scene", "Integrator", "Field",
    "load_scene", "create_integrator", "render", "train", "radiance", "pixel_estimate",
    "read_image", "write_image", "relmse", "compare_images",
]

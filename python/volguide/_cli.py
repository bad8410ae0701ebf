"""The `volguide` console script of a pip install: runs the CLI executable installed with the package."""
import os
import sys


def main():
    exe = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "volguide")
    if not os.path.exists(exe):
        sys.exit(f"volguide: {exe} is missing: this volguide package was not installed by pip (docs/python.md); "
                 "run the CLI from the build directory instead")
    os.execv(exe, [exe] + sys.argv[1:])

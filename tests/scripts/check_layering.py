#!/usr/bin/env python3
"""The layering rules of src/volguide (docs/architecture.md, "Layers"), checked over #include lines.

Every file belongs to a module: the first folder under src/volguide/, except that integrators/ is four
modules (integrators/ itself: the interface, render loop and the simple integrators; integrators/volpath;
integrators/guided; integrators/openpgl), and integrators/guided/ five (the integrator itself and its
walk/, estimates/, training/ and prepass/). A module may include itself and the modules listed in ALLOWED;
any other `#include "volguide/..."` fails the test with its file:line, unless EXCEPTIONS names that file
and header with the reason it stands. An exception that no longer occurs fails too, so the list stays true.

  check_layering.py SOURCE_DIR      exit 0: the layers hold; exit 1: violations printed one per line
"""
import os
import re
import sys

# module -> the modules it may include (besides itself). Lower layers first.
ALLOWED = {
    "core": set(),
    "vmm": {"core"},
    "guiding": {"core", "vmm"},
    "geometry": {"core"},
    "media": {"core", "geometry"},
    "render": {"core", "geometry", "media"},
    "integrators": {"core", "vmm", "guiding", "geometry", "media", "render"},
    "integrators/volpath": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators"},
    # guided_volpath's parts: what it learns and estimates (estimates/), the photon pre-pass and the
    # refinement schedule (training/), the pre-pass as bytes (prepass/), the decisions in the walk
    # (walk/: they read estimates/' learned selection, ears' snapshot and the leaf beside a surface);
    # the integrator itself assembles them all.
    "integrators/guided/estimates": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators",
                                     "integrators/volpath"},
    "integrators/guided/training": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators",
                                    "integrators/volpath"},
    "integrators/guided/prepass": {"core", "vmm", "guiding", "geometry", "media", "render",
                                   "integrators/guided/estimates"},
    "integrators/guided/walk": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators",
                                "integrators/volpath", "integrators/guided/estimates"},
    "integrators/guided": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators",
                           "integrators/volpath", "integrators/guided/estimates", "integrators/guided/training",
                           "integrators/guided/prepass", "integrators/guided/walk"},
    "integrators/openpgl": {"core", "geometry", "media", "render", "integrators", "integrators/volpath"},
    "scene": {"core", "vmm", "guiding", "geometry", "media", "render", "integrators",
              "integrators/volpath", "integrators/guided", "integrators/openpgl"},
}

# (including file relative to src/volguide, or a regular expression over it; included header) -> why.
EXCEPTIONS = {
    # The installed guiding library (cmake/guiding_library.cmake) ships these two header-only files
    # of media/ with it: the phase function interface its direction decisions take, and the guided
    # scatter probability that media/tracking.cpp's null-collision walk and guiding/ share.
    ("guiding/guided_direction.h", "media/phase.h"):
        "the direction decisions take a PhaseFunction; header-only, installed with the guiding library",
    ("guiding/guided_collision.h", "media/guided_tracking.h"):
        "the tentative collision the guided scatter probability reads; header-only, installed",
    # A shape owns its BSDF, emitter and media (as Mitsuba 3's Shape does) and reads them from its
    # <bsdf>, <emitter> and interior/exterior children: shape.h declares them incomplete, only the
    # constructor that casts the children needs their definitions.
    ("geometry/shape.cpp", "render/bsdf.h"): "a shape reads its <bsdf> child",
    ("geometry/shape.cpp", "render/emitter.h"): "a shape reads its <emitter> child",
    ("geometry/shape.cpp", "media/medium.h"): "a shape reads its interior/exterior media",
    # Mitsuba 3's sdfgrid reads its signed distances from a one-channel .vol file: one reader of the
    # format (media/vol_file.cpp, bounded and fuzzed), not a second copy in geometry/.
    ("geometry/shapes/sdfgrid.cpp", "media/grid_data.h"):
        "the sdfgrid shape reads its .vol file with the media's reader",
    # One factory function per XML tag is declared in scene/factories.h and implemented beside the
    # plugins it creates (docs/architecture.md, "Plugins and the factory table"); the integrators'
    # factory creates every integrator, the subfolders' included.
    (r"re:.*_factory\.cpp", "scene/factories.h"): "a plugin family implements its factory declaration",
    (r"re:integrators/integrator_factory\.cpp", r"re:integrators/(volpath|guided|openpgl)/[^/]*"):
        "the integrators' factory creates every integrator",
    # Issue 37's VSPG peer row applies Open PGL's scatter probability with the same segment samplers
    # as distance="vsp", so the comparison measures where P comes from, not a second sampler.
    ("integrators/openpgl/openpgl_vsp_distance.cpp", "integrators/guided/walk/vsp_distance.h"):
        "the VSPG peer row uses volguide's segment decision with Open PGL's VSP",
}


def module_of(rel):
    parts = rel.split("/")
    if parts[:2] == ["integrators", "guided"] and len(parts) > 3:
        return "integrators/guided/" + parts[2]
    if parts[0] == "integrators" and len(parts) > 2 and parts[1] in ("volpath", "guided", "openpgl"):
        return "integrators/" + parts[1]
    return parts[0]


def matches(pattern, text):
    if pattern.startswith("re:"):
        return re.fullmatch(pattern[3:], text) is not None
    return pattern == text


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    root = os.path.join(sys.argv[1], "src", "volguide")
    include = re.compile(r'\s*#\s*include\s+"volguide/([^"]+)"')
    violations, used = [], set()
    for folder, _, files in sorted(os.walk(root)):
        for name in sorted(files):
            if not name.endswith((".h", ".cpp")):
                continue
            path = os.path.join(folder, name)
            rel = os.path.relpath(path, root)
            module = module_of(rel)
            if module not in ALLOWED:
                violations.append(f"{path}:1: module '{module}' has no row in ALLOWED ({__file__})")
                continue
            with open(path, encoding="utf-8", errors="replace") as f:
                for number, line in enumerate(f, 1):
                    m = include.match(line)
                    if not m:
                        continue
                    header = m.group(1)
                    target = module_of(header)
                    if target == module or target in ALLOWED[module]:
                        continue
                    keys = [k for k in EXCEPTIONS if matches(k[0], rel) and matches(k[1], header)]
                    if keys:
                        used.update(keys)
                        continue
                    violations.append(f"{path}:{number}: {module}/ must not include {header} "
                                      f"(allowed: {', '.join(sorted(ALLOWED[module])) or 'nothing'})")
    for key in EXCEPTIONS:
        if key not in used:
            violations.append(f"{__file__}:1: the exception {key} no longer occurs: remove it")
    for v in violations:
        print(v)
    if violations:
        print(f"{len(violations)} layering violation(s)")
        return 1
    print("layers hold")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""guided_volpath's parameters against their table in docs/scene-format.md (issue 48).

The parameters the integrator reads are taken from the readers' source (every get_*, read_choice,
int_in, unit_interval or finite_at_least call with a literal name in guided_volpath_settings.cpp, and
in the volpath and path settings it reads first); the documented ones from the first column of the
tables under the "guided_volpath" heading. Every parameter read must have a row, every row must name
a parameter read, and there are at most MAX_PARAMETERS of them.

  check_parameter_table.py SOURCE_DIR      exit 0: they agree; exit 1: the differences, one per line
"""
import os
import re
import sys

MAX_PARAMETERS = 47
READERS = [
    ("src/volguide/integrators/guided/guided_volpath_settings.cpp", None),
    ("src/volguide/integrators/volpath/volpath.cpp", None),
    ("src/volguide/integrators/path.cpp", "PathSettings PathSettings::from"),
]
CALL = re.compile(r'(?:get_(?:int|float|bool|string|color|vec3)|read_choice<[^>]*>|int_in|unit_interval|'
                  r'finite_at_least)\(\s*(?:props\s*,\s*)?"([A-Za-z_0-9]+)"')


def function_body(text, signature):
    start = text.index(signature)
    depth, i = 0, text.index("{", start)
    for j in range(i, len(text)):
        depth += {"{": 1, "}": -1}.get(text[j], 0)
        if depth == 0:
            return text[i:j + 1]
    return text[i:]


def read_parameters(root):
    names = set()
    for path, signature in READERS:
        with open(os.path.join(root, path), encoding="utf-8") as f:
            text = f.read()
        if signature:
            text = function_body(text, signature)
        names.update(CALL.findall(text))
    return names


def documented_parameters(root):
    with open(os.path.join(root, "docs", "scene-format.md"), encoding="utf-8") as f:
        text = f.read()
    start = text.index("## `guided_volpath`")
    end = text.index("\n## ", start + 1)
    names = set()
    for line in text[start:end].splitlines():
        if not line.startswith("| `"):
            continue
        first = line.split("|")[1]
        names.update(re.findall(r"`([A-Za-z_0-9]+)`", first))
    return names


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    root = sys.argv[1]
    read, documented = read_parameters(root), documented_parameters(root)
    problems = [f"docs/scene-format.md: `{n}` is read by guided_volpath but has no row" for n in sorted(read - documented)]
    problems += [f"docs/scene-format.md: the row `{n}` names no parameter guided_volpath reads"
                 for n in sorted(documented - read)]
    if len(read) > MAX_PARAMETERS:
        problems.append(f"guided_volpath reads {len(read)} parameters, more than {MAX_PARAMETERS}")
    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"{len(read)} parameters, each with its row")
    return 0


if __name__ == "__main__":
    sys.exit(main())

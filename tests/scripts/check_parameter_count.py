#!/usr/bin/env python3
"""No function or constructor in src/volguide/integrators/ declared with more than LIMIT parameters
(issue 54: what a decision is asked travels in a query struct, not in a long list).

A heuristic over the text, not a C++ parser: comments, literals and preprocessor lines are blanked
(check_function_length.blank), then every parenthesised list after a name is split at its top-level
commas; it is a declaration's parameter list (of a function, a constructor or a lambda) when every
entry, its default argument removed, reads as a type with an optional name (`const Ray& ray`,
`Sampler&`, `std::vector<float>& out`, `int n`) and at least one has a type and a name or ends in `&`
or `*`. Calls (`f(a, b)`, `q.ray`, `x + 1`) and variables built from arguments do not read so.

  check_parameter_count.py SOURCE_DIR [LIMIT]   exit 0: none over LIMIT; exit 1: the offenders,
                                                one per line as file:line
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_function_length import blank, check  # noqa: E402

LIMIT = 6
FOLDER = os.path.join("src", "volguide", "integrators")

TYPE = r"(?:(?:const|volatile|struct|class|typename|unsigned|signed|long|short)\s+)*[A-Za-z_][\w:]*(?:<.*>)?"
PARAMETER = re.compile(r"^" + TYPE + r"(?:\s*(?:const\b|\*|&&?))*\s*(?P<name>[A-Za-z_]\w*)?(?:\[\w*\])?$", re.S)
KEYWORDS = {"return", "new", "delete", "throw", "sizeof", "case", "co_return", "else", "do", "goto"}
OPEN, CLOSE = "([{<", ")]}>"


def split_top(text):
    """text split at the commas outside brackets (angle brackets included)."""
    parts, depth, current = [], 0, []
    for c in text:
        if c in OPEN:
            depth += 1
        elif c in CLOSE:
            depth = max(0, depth - 1)
        if c == "," and depth == 0:
            parts.append("".join(current))
            current = []
        else:
            current.append(c)
    parts.append("".join(current))
    return [p.strip() for p in parts]


def without_default(parameter):
    """A parameter without its default argument (`= ...` at the top level)."""
    depth = 0
    for i, c in enumerate(parameter):
        if c in OPEN:
            depth += 1
        elif c in CLOSE:
            depth = max(0, depth - 1)
        elif c == "=" and depth == 0 and parameter[i + 1 : i + 2] != "=" and parameter[i - 1 : i] not in "=!<>":
            return parameter[:i].strip()
    return parameter


def is_parameter_list(parameters):
    named = False
    for p in parameters:
        p = without_default(p)
        m = PARAMETER.match(p)
        if not m or p.split()[0] in KEYWORDS:
            return False
        if m.group("name") and m.group("name") != p or p.endswith(("&", "*")):
            named = True
    return named


def matching(src, open_at):
    """Index of the `)` closing the `(` at open_at (-1: none)."""
    depth = 0
    for i in range(open_at, len(src)):
        if src[i] == "(":
            depth += 1
        elif src[i] == ")":
            depth -= 1
            if depth == 0:
                return i
    return -1


def declarations(path):
    """(line, name, parameter count) of every parameter list declared in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        src = blank(f.read())
    found = []
    for m in re.finditer(r"([A-Za-z_~][\w:]*|\])\s*\(", src):
        if m.group(1) in KEYWORDS or m.group(1) in ("if", "for", "while", "switch", "catch", "decltype"):
            continue
        close = matching(src, m.end() - 1)
        inner = src[m.end() : close].strip() if close > 0 else ""
        if not inner or inner == "void":
            continue
        parameters = split_top(inner)
        if is_parameter_list(parameters):
            found.append((src.count("\n", 0, m.start()) + 1, m.group(1), len(parameters)))
    return found


def main():
    return check(__doc__.strip().splitlines()[-2].strip(), FOLDER, LIMIT, declarations, lambda d: d[2],
                 lambda path, d, limit: f"{path}:{d[0]}: {d[1]}: {d[2]} parameters (limit {limit})",
                 ("declaration(s)", "parameter lists", "parameters"))


if __name__ == "__main__":
    sys.exit(main())

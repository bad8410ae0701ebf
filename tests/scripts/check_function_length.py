#!/usr/bin/env python3
"""No function in src/ longer than LIMIT lines (the project's rule: small functions with one job).

A heuristic over the text, not a C++ parser: comments, string and character literals and preprocessor
lines are blanked (keeping the line count), then every `{` whose preceding code since the last `;`, `{`
or `}` ends like a signature (`)` followed only by const, noexcept, override, final, mutable, a
trailing return type, a requires clause, or a constructor's initializer list) opens a function body,
unless it sits inside another function body: lambdas, local classes and control statements count
towards the function around them. Functions at namespace scope and member functions defined inside
classes (at any depth of namespaces and classes) are found. A function's length is the lines from its
opening to its closing brace.

  check_function_length.py SOURCE_DIR [LIMIT]   exit 0: every function fits; exit 1: the offenders,
                                                one per line as file:line (where the signature starts)
"""
import os
import re
import sys

LIMIT = 80

CONTROL = re.compile(r"\b(if|for|while|switch|catch)\s*\(")
# The tail of a signature: the parameter list's `)` then qualifiers or a trailing return type.
SIGNATURE_END = re.compile(r"\)\s*(?:(?:const|override|noexcept|final|mutable|&|&&)\s*|->[^;{}]*|requires\b[^;{}]*)*$")
# A constructor's initializer list, complete (`) : a_(x), b_{y}`) or open at a member's brace (`) : b_`).
INITIALIZERS = re.compile(r"\)\s*(?:noexcept\s*)?:(?!:)[^;]*[)}]$", re.S)
INITIALIZER_OPEN = re.compile(r"\)\s*(?:noexcept\s*)?:(?!:)[^;]*[\w>]$", re.S)


def blank(src):
    """Comments, literals and preprocessor lines replaced by spaces; newlines kept."""
    keep_lines = lambda m: re.sub(r"[^\n]", " ", m.group(0))
    src = re.sub(r"/\*.*?\*/", keep_lines, src, flags=re.S)
    src = re.sub(r"//[^\n]*", "", src)
    src = re.sub(r'R"([^(\s]*)\((?:.|\n)*?\)\1"', lambda m: '""' + "\n" * m.group(0).count("\n"), src)
    src = re.sub(r'"(?:\\.|[^"\\\n])*"', '""', src)
    src = re.sub(r"(?<![0-9A-Fa-f])'(?:\\.|[^'\\\n])*'", "''", src)  # not digit separators (1'000)
    src = re.sub(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", "", src, flags=re.M)
    return src


def opens_function(code):
    """Whether the code between the last `;` or brace and a `{` is a function's signature."""
    if not code or CONTROL.search(code.split("\n")[-1]):
        return False
    if re.match(r"(namespace|struct|class|union|enum|extern)\b", code) and "(" not in code:
        return False
    return bool(SIGNATURE_END.search(code) or INITIALIZERS.search(code))


def functions(path):
    """(first line of the signature, lines of the body, signature) of every function in the file."""
    with open(path, encoding="utf-8", errors="replace") as f:
        src = blank(f.read())
    found, stack = [], []  # stack: (is_function, line of `{`, first line of the signature, signature)
    line, last, last_line = 1, 0, 1
    carry = None  # (start line, code) of a constructor's initializer list interrupted by a member's `{...}`
    for i, c in enumerate(src):
        if c == "\n":
            line += 1
        elif c == "{":
            pre = src[last:i]
            start = last_line + (pre[: len(pre) - len(pre.lstrip())]).count("\n")
            code = pre.strip()
            if carry is not None:
                start, code = carry[0], (carry[1] + " " + code).strip()
                carry = None
            in_function = any(entry[0] for entry in stack)
            is_function = not in_function and opens_function(code)
            stack.append((is_function, line, start, " ".join(code.split())))
            last, last_line = i + 1, line
        elif c == "}":
            if stack:
                is_function, opened, start, code = stack.pop()
                if is_function:
                    found.append((start, line - opened + 1, code))
                elif not any(entry[0] for entry in stack) and INITIALIZER_OPEN.search(code):
                    carry = (start, code + "{}")
            last, last_line = i + 1, line
        elif c == ";":
            last, last_line, carry = i + 1, line, None
    return found


def sources(root):
    """Every C++ source and header below root, in a stable order."""
    for folder, _, files in sorted(os.walk(root)):
        for name in sorted(files):
            if name.endswith((".h", ".cpp")):
                yield os.path.join(folder, name)


def verdict(offenders, failed, passed):
    """Prints the offenders and `failed`, or `passed`; the exit status."""
    print("\n".join(offenders + [failed]) if offenders else passed)
    return 1 if offenders else 0


def check(usage, folder, default_limit, items_of, size, describe, nouns):
    """The source checks' main: `SOURCE_DIR [LIMIT]` from argv; every item (items_of(path)) of every
    source below SOURCE_DIR/folder whose size(item) exceeds the limit is an offender, described by
    describe(path, item, limit); nouns: (offenders, items, unit) for the summary line."""
    if len(sys.argv) not in (2, 3):
        print(usage)
        return 2
    limit = int(sys.argv[2]) if len(sys.argv) == 3 else default_limit
    found = [(path, item) for path in sources(os.path.join(sys.argv[1], folder)) for item in items_of(path)]
    offenders = [describe(path, item, limit) for path, item in found if size(item) > limit]
    many, items, unit = nouns
    return verdict(offenders, f"{len(offenders)} {many} over {limit} {unit}",
                   f"{len(found)} {items}, none over {limit} {unit}")


def main():
    return check(__doc__.strip().splitlines()[-2].strip(), "src", LIMIT, functions, lambda f: f[1],
                 lambda path, f, limit: f"{path}:{f[0]}: {f[1]} lines (limit {limit}): {f[2][:100]}",
                 ("function(s)", "functions", "lines"))


if __name__ == "__main__":
    sys.exit(main())

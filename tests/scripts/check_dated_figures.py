#!/usr/bin/env python3
"""No dated figure in the comments of src/ and tests/ (the project's rule: measured numbers live in
bench/RESULTS.md with the command that reproduces them, not in code comments, where they go stale).

A comment that carries a calendar date (a year, month and day as YYYY-MM-DD, 2000-2099) is taken
for a dated measurement. Comments are `//` and `/* */` in C and C++ files (.h, .hpp, .cpp, .c, .cu)
and `#` in Python, shell and CMake files; string literals are not comments.

  check_dated_figures.py SOURCE_DIR   exit 0: none; exit 1: the offenders, one per line as file:line
"""
import os
import re
import sys

DATE = re.compile(r"\b20\d\d-(?:0[1-9]|1[0-2])-(?:0[1-9]|[12]\d|3[01])\b")
C_LIKE = (".h", ".hpp", ".cpp", ".c", ".cu", ".cuh")
HASH = (".py", ".sh", ".cmake", ".txt")
FOLDERS = ("src", "tests")


def c_comments(text):
    """(line, comment text) of every // and /* */ comment, string and character literals skipped."""
    found, i, line, n = [], 0, 1, len(text)
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
        elif text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            found.append((line, text[i:end]))
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            found.append((line, text[i:end]))
            line += text.count("\n", i, end)
            i = end
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            i = j + 1
        else:
            i += 1
    return found


def hash_comments(text):
    """(line, comment text) of every # comment (after code or alone on its line)."""
    found = []
    for number, row in enumerate(text.split("\n"), 1):
        m = re.search(r"(?:^|\s)#(?!!)(.*)$", row)
        if m:
            found.append((number, m.group(0)))
    return found


def offenders(root):
    out = []
    for top in FOLDERS:
        for folder, _, files in sorted(os.walk(os.path.join(root, top))):
            for name in sorted(files):
                path = os.path.join(folder, name)
                if name.endswith(C_LIKE):
                    comments = c_comments
                elif name.endswith(HASH):
                    comments = hash_comments
                else:
                    continue
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = f.read()
                for line, comment in comments(text):
                    for m in DATE.finditer(comment):
                        row = line + comment.count("\n", 0, m.start())
                        out.append(f"{path}:{row}: a dated figure ({m.group(0)}): measured numbers go in bench/RESULTS.md")
    return out


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1].strip())
        return 2
    found = offenders(sys.argv[1])
    if found:
        print("\n".join(found + [f"{len(found)} dated figure(s) in comments"]))
        return 1
    print("no dated figures in the comments of src/ and tests/")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Every file of the project has its line in docs/architecture.md (issue 48), and every line names a file.

A file is listed when some backticked name in docs/architecture.md's "The tree" section is a suffix of
its path, with or without the extension (`walk/guided_vertex` lists both guided_vertex.h and .cpp of
that folder; a name ending in "/" lists a whole folder of data). Generated data (the fuzz corpora, the
benchmark's results and references) is listed by its folder.

  check_architecture_files.py SOURCE_DIR      exit 0: every file listed; exit 1: the missing, one per line
"""
import os
import re
import subprocess
import sys

FOLDERS = ("src", "apps", "python", "tools", "bench", "scripts", "tests", "cmake", "examples", "scenes")


def tracked_files(root):
    try:
        # Tracked files and new ones git does not ignore.
        out = subprocess.run(["git", "-C", root, "ls-files", "--cached", "--others", "--exclude-standard", *FOLDERS],
                             capture_output=True, text=True, check=True)
        files = out.stdout.split()
    except (OSError, subprocess.CalledProcessError):  # not a checkout: every file below the folders
        files = [os.path.relpath(os.path.join(d, f), root) for top in FOLDERS
                 for d, _, fs in os.walk(os.path.join(root, top)) for f in fs]
    return sorted(f for f in files if os.path.exists(os.path.join(root, f)))


def listed_names(root):
    with open(os.path.join(root, "docs", "architecture.md"), encoding="utf-8") as f:
        text = f.read()
    start = text.index("## The tree")
    end = text.index("\n## ", start + 1)
    names = set()
    for line in text[start:end].splitlines():
        if line.startswith("- "):
            names.update(re.findall(r"`([^`\s]+)`", line.split(" — ")[0]))
    return names


def is_listed(path, names):
    stem = os.path.splitext(path)[0]
    for n in names:
        if n.endswith("/"):
            if ("/" + n) in ("/" + path) or path.startswith(n):
                return True
        elif path.endswith("/" + n) or path == n or stem.endswith("/" + n) or stem == n:
            return True
    return False


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    root = sys.argv[1]
    names = listed_names(root)
    files = tracked_files(root)
    missing = [f for f in files if not is_listed(f, names)]
    stale = [n for n in sorted(names) if not any(is_listed(f, {n}) for f in files)]
    for f in missing:
        print(f"docs/architecture.md: no line lists {f}")
    for n in stale:
        print(f"docs/architecture.md: `{n}` names no file")
    if missing or stale:
        print(f"{len(missing)} file(s) without a line, {len(stale)} line(s) without a file")
        return 1
    print("every file has its line")
    return 0


if __name__ == "__main__":
    sys.exit(main())

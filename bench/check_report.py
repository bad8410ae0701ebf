#!/usr/bin/env python3
"""Opens a benchmark report (index.html) in headless Chromium and checks that the page loaded without
script errors and that every image was found and decoded. The page's own script counts the images
and errors into <p id="check">; this reads it back from the rendered DOM.

    python3 bench/check_report.py bench/results/<date>/index.html

Exit status 0 when the page is complete, 1 otherwise (with the reason).
"""
import os
import re
import shutil
import subprocess
import sys


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: check_report.py INDEX.html")
    page = os.path.abspath(sys.argv[1])
    if not os.path.exists(page):
        sys.exit(f"check_report: {page} does not exist")
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if not browser:
        sys.exit("check_report: chromium is not installed (Debian package `chromium`; `make bench` installs it)")
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--allow-file-access-from-files",
           "--virtual-time-budget=20000", "--dump-dom", "file://" + page]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=180)
    if res.returncode != 0:
        sys.exit(f"check_report: chromium failed (exit {res.returncode}): {res.stderr.strip()[-500:]}")
    m = re.search(r'<p id="check"([^>]*)>([^<]*)</p>', res.stdout)
    if not m:
        sys.exit("check_report: the page's check element is missing from the rendered DOM")
    attrs = dict(re.findall(r'data-([a-z]+)="([^"]*)"', m.group(1)))
    with open(page) as f:
        expected = len(re.findall(r"<img ", f.read()))
    status, images = attrs.get("status"), int(attrs.get("images", "0"))
    if status != "ok" or images != expected or images == 0:
        sys.exit(f"check_report: {page}: status {status}, {images} of {expected} images counted, "
                 f"{attrs.get('broken')} broken, {attrs.get('errors')} script errors ({m.group(2)})")
    print(f"check_report: {os.path.relpath(page)}: all {images} images shown, no script errors")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""A PNG of the HTML report of the paper's A1 counterexample, taken by headless Chromium.

Run: `.venv/bin/python benchmarks/report_screenshot.py [OUT.png] [-a NAME]...` (default
`report_A1.png` and assertion A1; `-a all` for every assertion). Checks the IntelliWelder example
with the paper's realistic ranges (its Table 2, where A1 is violated), writes the report beside the
PNG, and screenshots it at 1400x1800; look at the PNG to judge the layout.  Needs `chromium`
(Debian: `apt-get install chromium`).  The tests use `headless` below for their DOM checks.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from tockbmc import __version__, load
from tockbmc.check import check
from tockbmc.model.ranges import Range, Ranges
from tockbmc.report.html import write_report

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "intelliwelder"
# The paper's realistic case: --range core_int=-1..1 --range core_real=-1..1.
RANGES = Ranges({"core_int": Range(-1, 1), "core_real": Range(-1, 1)}, {})
# Quiet, offline, no first-run work: nothing reaches the network, the profile is thrown away.
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-extensions", "--hide-scrollbars", "--mute-audio")


def chromium() -> str | None:
    """The Chromium executable on PATH, if any."""
    return next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome")) if p), None)


def headless(browser: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """Run headless Chromium with a throw-away profile and `args` (e.g. `--dump-dom URL`)."""
    with tempfile.TemporaryDirectory(prefix="tockbmc-chromium-") as profile:
        return subprocess.run([browser, *FLAGS, f"--user-data-dir={profile}", *args], capture_output=True,
                              text=True, timeout=timeout, check=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="report_A1.png", type=Path)
    parser.add_argument("-a", dest="names", action="append", help="assertion to check (default A1; 'all')")
    args = parser.parse_args()
    browser = chromium()
    if browser is None:
        print("report_screenshot: no chromium on PATH (apt-get install chromium)", file=sys.stderr)
        return 2
    names = args.names or ["A1"]
    results = check(load(EXAMPLE), None if "all" in names else names, ranges=RANGES)
    page = args.out.resolve().with_suffix(".html")
    write_report(page, results, title=f"{EXAMPLE.name} (core_int=-1..1, core_real=-1..1)", version=__version__)
    headless(browser, f"--screenshot={args.out.resolve()}", "--window-size=1400,1800", page.as_uri())
    print(f"{page}\n{args.out.resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Tolerance audit of the Fortran unit suites (issue 13, item 7; tests/TOLERANCES.md).

Runs each suite executable with FFRF_TEST_AUDIT=1, where check_close (tests/unit/testing.f90)
prints every measured difference beside its tolerance, and summarises per test: the number of
check_close calls, and the loosest one (largest tolerance / measured). A check is flagged when
its tolerance exceeds 10 times what it measures and 1e-8 of the expected value (tighter ones
are round-off bounds of checks exact in exact arithmetic); a flagged check needs a comment in
the test giving the method's error bound, or a tighter tolerance. Assertions made with `check`
(a logical) are not seen here.

    python3 tests/tolerance_audit.py BUILD_DIR [SUITE ...] [--flagged FILE] > audit.md

The environment of ctest is set (FFRF_INPUT_DIR, FFRF_MESH_DIR, FFRF_TEST_DATA_DIR); the meshes
must exist (run the suites once through ctest first).
"""
import argparse
import math
import os
import re
import subprocess
import sys
from pathlib import Path

AUDIT = re.compile(r"^\s+audit: (.*) \| measured (\S+) \| tolerance (\S+) \| expected (\S+)$")
RESULT = re.compile(r"^\s+(ok|FAIL)\s+(\S+)")


def number(text):
    try:
        return float(text.replace("D", "E"))
    except ValueError:
        return math.nan


def loose(measured, tolerance, expected):
    """Tolerance above 10 x measured and above round-off: 1e-8 of the expected value (or 1e-8
    itself against an expected 0, the quantities being normalised)."""
    if tolerance <= 1e-8 * (abs(expected) if expected != 0.0 else 1.0):
        return False
    return tolerance > 10.0 * measured


def audit_suite(executable, env):
    out = subprocess.run([str(executable)], capture_output=True, text=True, env=env,
                         cwd=executable.parent.parent)
    rows, pending = [], []
    for line in out.stdout.splitlines():
        m = AUDIT.match(line)
        if m:
            pending.append((m.group(1), number(m.group(2)), number(m.group(3)),
                            number(m.group(4))))
            continue
        m = RESULT.match(line)
        if m:
            rows.append((m.group(2), m.group(1), pending))
            pending = []
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", type=Path, help="build folder (tests/test_* executables)")
    parser.add_argument("suites", nargs="*", help="suite executables (default: all)")
    parser.add_argument("--flagged", type=Path, help="also write every flagged check here")
    args = parser.parse_args()
    build = args.build.resolve()
    source = Path(__file__).resolve().parent.parent
    suites = args.suites or sorted(p.name for p in (build / "tests").glob("test_*")
                                   if p.is_file() and os.access(p, os.X_OK)
                                   and not p.name.endswith("_checked"))
    env = dict(os.environ, FFRF_TEST_AUDIT="1", OPENBLAS_NUM_THREADS="1",
               FFRF_INPUT_DIR=str(source / "input"), FFRF_MESH_DIR=str(build / "meshes"),
               FFRF_TEST_DATA_DIR=str(source / "tests" / "data"))
    flagged_lines = []
    print("| test | checks | loosest check: measured / tolerance | ratio | flagged |")
    print("|---|---:|---|---:|---:|")
    for suite in suites:
        for name, status, checks in audit_suite(build / "tests" / suite, env):
            if not checks:
                print(f"| {name} ({status}) | 0 | (logical checks only) | | |")
                continue

            def ratio(c):
                return c[2] / c[1] if c[1] > 0 else math.inf
            flagged = [c for c in checks if loose(c[1], c[2], c[3])]
            flagged_lines += [f"{name}: {c[0]}: measured {c[1]:.3g}, tolerance {c[2]:.3g}, "
                              f"expected {c[3]:.3g}" for c in flagged]
            worst = max(flagged or checks, key=ratio)
            what = worst[0][:70].replace("|", "\\|")
            print(f"| {name} ({status}) | {len(checks)} | {what}: {worst[1]:.2g} / "
                  f"{worst[2]:.2g} | {ratio(worst):.3g} | {len(flagged) or ''} |")
    if args.flagged:
        args.flagged.write_text("\n".join(flagged_lines) + "\n")


if __name__ == "__main__":
    main()

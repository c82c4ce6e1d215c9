#!/usr/bin/env python3
"""One ffrf run under valgrind's memcheck (ctest label memcheck): fails on any memcheck error
that tests/memcheck.supp does not suppress (that file holds library internals only: MUMPS,
OpenBLAS, OpenMPI, each entry with its reason), and when the run itself fails; exits 77 (ctest
SKIP_RETURN_CODE) when valgrind is not installed.

usage: memcheck_run.py DRIVER CASE MESH_DIR WORK_DIR SUPPRESSIONS [driver arguments...]

Memcheck runs with --track-origins=yes (each error names where the value came from) and
--error-exitcode; leaks are not counted here (capi_bad_calls_valgrind checks the API's). The
driver runs with one BLAS thread (threads add nothing to the check and slow valgrind down).
"""
import os
import re
import shutil
import subprocess
import sys

ERROR_EXIT = 99


def main():
    if len(sys.argv) < 6:
        sys.exit(__doc__)
    driver, case, mesh_dir, work, suppressions = sys.argv[1:6]
    valgrind = shutil.which("valgrind")
    if valgrind is None:
        print("valgrind is not installed: memcheck test skipped")
        return 77
    os.makedirs(work, exist_ok=True)
    command = [valgrind, "--tool=memcheck", f"--error-exitcode={ERROR_EXIT}",
               "--track-origins=yes", "--num-callers=30", "--leak-check=no",
               f"--suppressions={suppressions}", driver, case, "--mesh-dir", mesh_dir,
               "--output-dir", work, "--threads", "1", "--quiet"] + sys.argv[6:]
    print(" ".join(command), flush=True)
    done = subprocess.run(command, capture_output=True, text=True,
                          env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    report = [line for line in done.stderr.splitlines() if line.startswith("==")]
    summary = [line for line in report if "ERROR SUMMARY" in line]
    errors = -1
    suppressed = 0
    if summary:
        match = re.search(r"ERROR SUMMARY: (\d+) errors from \d+ contexts \(suppressed: (\d+)",
                          summary[-1])
        if match:
            errors, suppressed = int(match.group(1)), int(match.group(2))
    print(f"memcheck: {errors} errors, {suppressed} suppressed (tests/memcheck.supp); "
          f"exit code {done.returncode}")
    if errors == 0 and done.returncode == 0:
        verdict = "ok: no memcheck error in the run"
    elif done.returncode == ERROR_EXIT or errors > 0:
        verdict = "FAIL: memcheck errors outside the suppressed library internals"
    else:
        verdict = f"FAIL: the run ended with exit code {done.returncode}"
    if not verdict.startswith("ok"):
        # the whole report and the run's own messages, for the log
        print(done.stderr)
    print(verdict)
    return 0 if verdict.startswith("ok") else 1


if __name__ == "__main__":
    sys.exit(main())

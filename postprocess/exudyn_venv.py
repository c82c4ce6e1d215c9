#!/usr/bin/env python3
"""Make a virtual environment with Exudyn for the peer computation of the engine (issue 30;
peer_exudyn_engine.py): `python3 -m venv --system-site-packages DIR` (Debian's numpy, scipy, h5py
stay visible) and `pip install exudyn==VERSION` from PyPI. Nothing is done when DIR's interpreter
already imports that version.

    exudyn_venv.py DIR [--version 1.13.6]

Exit 0: DIR/bin/python imports exudyn. Exit 77 (ctest's skip code here) when it cannot be made
(no venv module: Debian's python3-venv; no network; no wheel for this Python), saying why.
"""
import argparse
import os
import subprocess
import sys

SKIP = 77


def imports(python, version):
    probe = f"import exudyn, sys; sys.exit(0 if exudyn.__version__ == {version!r} else 1)"
    try:
        return subprocess.call([python, "-c", probe], stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL) == 0
    except OSError:
        return False


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dir")
    parser.add_argument("--version", default="1.13.6")
    args = parser.parse_args()
    python = os.path.join(args.dir, "bin", "python")
    if imports(python, args.version):
        print(f"exudyn_venv: {args.dir}: exudyn {args.version} present")
        return 0
    steps = [[sys.executable, "-m", "venv", "--system-site-packages", args.dir],
             [python, "-m", "pip", "install", "--disable-pip-version-check", "--quiet",
              f"exudyn=={args.version}"]]
    for command in steps:
        status = subprocess.call(command)
        if status != 0:
            print(f"exudyn_venv: '{' '.join(command)}' exited {status}: no Exudyn, the peer "
                  "computation is skipped (Debian: python3-venv; PyPI must be reachable)",
                  file=sys.stderr)
            return SKIP
    if not imports(python, args.version):
        print(f"exudyn_venv: {python} does not import exudyn {args.version} after the install",
              file=sys.stderr)
        return SKIP
    print(f"exudyn_venv: {args.dir}: exudyn {args.version} installed")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""Run postprocess/plot_modes.py on the sample files and check the picture it writes.

Checks: exit status 0; the PNG exists and decodes; its size follows the layout (3 columns x 2
rows at --dpi 100: (3.6*3 + 0.8) x (3.0*2 + 0.6) inches = 1160 x 660 pixels); it is not blank
(more than 5% of the pixels differ from white, and several distinct colours appear); a failed
run makes the script exit non-zero with the status in its message. Whether the picture is
right is for a person to see: open plot_modes_sample.png.
"""
import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--script", required=True, help="postprocess/plot_modes.py")
    parser.add_argument("folder", help="folder with the sample files")
    args = parser.parse_args()
    checks, failures = [], []

    def expect(what, condition):
        print(("ok   " if condition else "FAIL ") + what)
        checks.append(what)
        if not condition:
            failures.append(what)

    files = [os.path.join(args.folder, f"sample_rc{k}.h5") for k in (1, 2, 3)]
    png = os.path.join(args.folder, "plot_modes_sample.png")
    if os.path.exists(png):
        os.remove(png)
    run = subprocess.run([sys.executable, args.script, *files, "-o", png, "--modes", "2",
                          "--body", "box", "--dpi", "100"], capture_output=True, text=True)
    expect(f"plot_modes.py exits 0 (stderr: {run.stderr.strip()[-500:]})", run.returncode == 0)
    expect("the PNG exists", os.path.isfile(png))
    if not failures:
        image = mpimg.imread(png)
        height, width = image.shape[:2]
        expect(f"PNG is 1160 x 660 pixels: {width} x {height}", (width, height) == (1160, 660))
        rgb = image[:, :, :3]
        coloured = np.mean(np.any(rgb < 0.95, axis=2))
        expect(f"{100 * coloured:.1f}% of the pixels are not white (> 5%)", coloured > 0.05)
        colours = len(np.unique((rgb.reshape(-1, 3) * 255).astype(np.uint8), axis=0))
        expect(f"{colours} distinct colours (> 50)", colours > 50)

    failed = subprocess.run([sys.executable, args.script,
                             os.path.join(args.folder, "sample_failed.h5"), "-o",
                             os.path.join(args.folder, "failed.png")],
                            capture_output=True, text=True)
    expect(f"a failed run gives a non-zero exit and its status: {failed.stderr.strip()}",
           failed.returncode != 0 and "ARPACK did not converge" in failed.stderr)
    print(f"{len(checks) - len(failures)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

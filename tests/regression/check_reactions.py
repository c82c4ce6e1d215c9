#!/usr/bin/env python3
"""Reactions of near-redundant joints (issue 30, part 4): an engine whose conrod keeps two
in-plane modes (and the crank four, on lc 10 mm: what the automatic model kept before its
joint-free candidates) closes its out-of-plane loop (main bearings, crank pin, piston pin,
cylinder) through modes that barely move along it; its pin-axis reactions reached 2.5e8 N in
0.3 s (1e10 N in 2 s with the automatic model) before the minimum-norm rule
(ffrf_mbs_reaction_split). Checks one run of it against the same engine with every body rigid:

    check_reactions.py FLEXIBLE.h5 RIGID.h5 [--out-of-plane-max F] [--in-plane-rtol R]

1. bounded: |F_z| of piston_pin, crank_pin and cylinder (the pin axis) at most
   --out-of-plane-max times the peak conrod force (the largest in-plane |F_xy| of the piston
   pin: the engine's force scale);
2. the in-plane forces unchanged by the rule and right: |F_xy(t) - F_xy,rigid(t)| (the rigid
   run interpolated to the flexible run's times) at most --in-plane-rtol times the largest
   in-plane force of the rigid run, for the pins and the cylinder's lateral force;
3. the piston's lateral balance, a closed form independent of the reference: the piston does not
   move across the cylinder, so the lateral (x) and pin-axis (z) forces on it from the piston pin
   and the cylinder cancel (1e-6 of the in-plane peak: round-off of the multipliers);
4. the flags: /joints/<joint>/reaction_min_norm has the reaction's shape and 0/1 entries, the
   pin-axis component is flagged at some step, and the in-plane force components of the pins
   never are (the rule keeps them);
5. the rigid run flags nothing (every redundant equation is dropped there).
Exit status 0 when all hold, 1 otherwise, each failure on one line.
"""
import argparse
import sys

import h5py
import numpy as np

# Reaction rows: force and moment on body 1 (0-5), on body 2 (6-11)
FX2, FY2, FZ2 = 6, 7, 8
PINS = ("piston_pin", "crank_pin")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("flexible")
    parser.add_argument("rigid")
    parser.add_argument("--out-of-plane-max", type=float, default=0.1)
    parser.add_argument("--in-plane-rtol", type=float, default=1e-3)
    args = parser.parse_args()
    failures = []

    def check(ok, message):
        if not ok:
            failures.append(message)

    with h5py.File(args.flexible, "r") as flex, h5py.File(args.rigid, "r") as rigid:
        check(flex.attrs["status"] in (b"complete", "complete"), "flexible run not complete")
        t = flex["/time/t"][()]
        t_rigid = rigid["/time/t"][()]
        check(t[-1] <= t_rigid[-1] * (1 + 1e-9), "the rigid run ends before the flexible one")
        reaction = {j: flex["/joints/%s/reaction" % j][()] for j in flex["/joints"]}
        reaction_rigid = {j: rigid["/joints/%s/reaction" % j][()] for j in rigid["/joints"]}

        pin = reaction["piston_pin"]
        conrod_peak = np.hypot(pin[:, FX2], pin[:, FY2]).max()
        for joint in PINS + ("cylinder",):
            r = reaction[joint]
            out_of_plane = np.abs(r[:, FZ2]).max()
            print("%-10s pin-axis peak %.4g N, %.3g x the peak conrod force %.4g N (median "
                  "%.4g N)" % (joint, out_of_plane, out_of_plane / conrod_peak, conrod_peak,
                               np.median(np.abs(r[:, FZ2]))))
            check(out_of_plane <= args.out_of_plane_max * conrod_peak,
                  "%s: pin-axis force %.4g N above %g x the peak conrod force %.4g N"
                  % (joint, out_of_plane, args.out_of_plane_max, conrod_peak))

        for joint, components in (("piston_pin", (FX2, FY2)), ("crank_pin", (FX2, FY2)),
                                  ("cylinder", (FX2,))):
            r, rr = reaction[joint], reaction_rigid[joint]
            scale = np.hypot(rr[:, FX2], rr[:, FY2]).max()
            for c in components:
                ref = np.interp(t, t_rigid, rr[:, c])
                worst = np.abs(r[:, c] - ref).max() / scale
                print("%-10s component %d: largest difference to the rigid engine %.3g of "
                      "its in-plane peak %.4g N" % (joint, c, worst, scale))
                check(worst <= args.in_plane_rtol,
                      "%s component %d: differs from the rigid engine by %.3g of its "
                      "in-plane peak (tolerance %g)" % (joint, c, worst, args.in_plane_rtol))

        pin, cylinder = reaction["piston_pin"], reaction["cylinder"]
        peak = np.hypot(pin[:, FX2], pin[:, FY2]).max()
        for c, name in ((FX2, "lateral"), (FZ2, "pin-axis")):
            imbalance = np.abs(pin[:, c] + cylinder[:, c]).max()
            print("piston %s balance: largest |pin + cylinder| %.3g N" % (name, imbalance))
            check(imbalance <= 1e-6 * peak, "piston %s forces do not balance: %.4g N"
                  % (name, imbalance))

        for joint in PINS + ("cylinder",):
            flags = flex["/joints/%s/reaction_min_norm" % joint][()]
            check(flags.shape == reaction[joint].shape,
                  "%s: reaction_min_norm shape %s, reaction %s"
                  % (joint, flags.shape, reaction[joint].shape))
            check(np.all((flags == 0) | (flags == 1)), "%s: flags other than 0/1" % joint)
            check(flags[:, FZ2].any(), "%s: pin-axis force never flagged min-norm" % joint)
            if joint in PINS:
                check(not flags[:, [FX2, FY2]].any(),
                      "%s: in-plane force flagged min-norm" % joint)
        for joint in rigid["/joints"]:
            check(not rigid["/joints/%s/reaction_min_norm" % joint][()].any(),
                  "rigid run: %s flagged" % joint)

    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

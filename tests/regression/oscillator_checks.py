"""Shared measurements of the oscillator checks (check_springs.py, check_torsion_springs.py,
check_bushings.py): periods from zero crossings, logarithmic decrements of the peaks and the
running trapezoid integral."""
import numpy as np


def crossing_period(t, u, skip_first=False):
    """Twice the mean spacing of the zero crossings of u(t) (linear interpolation between the
    samples) and their number; skip_first leaves out a crossing at the first sample."""
    start = 1 if skip_first else 0
    crossings = [t[i] - u[i] * (t[i + 1] - t[i]) / (u[i + 1] - u[i])
                 for i in range(start, len(u) - 1) if u[i] * u[i + 1] < 0.0]
    return 2.0 * np.mean(np.diff(crossings)), len(crossings)


def log_decrement(u):
    """Logarithmic decrement per half period of the peaks of |u| (first to last)."""
    peaks = [abs(u[i]) for i in range(1, len(u) - 1)
             if abs(u[i]) >= abs(u[i - 1]) and abs(u[i]) >= abs(u[i + 1])]
    return np.log(peaks[0] / peaks[-1]) / (len(peaks) - 1)


def cumulative_trapezoid(t, y):
    """int_0^t y dt by the trapezoid rule over the samples, from 0."""
    return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))])

#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/plot_modes.py (read its help)."""
import sys

from ffrf_results import plot_modes

if __name__ == "__main__":
    sys.exit(plot_modes.main())
sys.modules[__name__] = plot_modes  # `import plot_modes` gets the package module

#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/plot_sensors.py (read its help)."""
import sys

from ffrf_results import plot_sensors

if __name__ == "__main__":
    sys.exit(plot_sensors.main())
sys.modules[__name__] = plot_sensors  # `import plot_sensors` gets the package module

#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/plot_engine.py (read its help)."""
import sys

from ffrf_results import plot_engine

if __name__ == "__main__":
    sys.exit(plot_engine.main())
sys.modules[__name__] = plot_engine  # `import plot_engine` gets the package module

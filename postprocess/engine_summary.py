#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/engine_summary.py (read its help)."""
import sys

from ffrf_results import engine_summary

if __name__ == "__main__":
    sys.exit(engine_summary.main())
sys.modules[__name__] = engine_summary  # `import engine_summary` gets the package module

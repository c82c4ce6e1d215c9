#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/gather_results.py (read its help)."""
import sys

from ffrf_results import gather_results

if __name__ == "__main__":
    sys.exit(gather_results.main())
sys.modules[__name__] = gather_results  # `import gather_results` gets the package module

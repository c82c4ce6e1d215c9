#!/usr/bin/python3
"""Thin entry point: the code is ffrf_results/frequency_table.py (read its help)."""
import sys

from ffrf_results import frequency_table

if __name__ == "__main__":
    sys.exit(frequency_table.main())
sys.modules[__name__] = frequency_table  # `import frequency_table` gets the package module

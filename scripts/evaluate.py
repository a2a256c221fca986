#!/usr/bin/python3
"""The step-size evaluation: the entry point of the package scripts/evaluation/ (`--help`, or
scripts/evaluation/cli.py, says what it does)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from evaluation.cli import main  # noqa: E402

if __name__ == "__main__":
    main()

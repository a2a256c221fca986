"""The step-size evaluation behind scripts/evaluate.py: cases, runs, measures, figures and the page."""

"""The step-size evaluation behind scripts/evaluate.py: plan (cases and runs), run, metrics, figures and the page (report)."""

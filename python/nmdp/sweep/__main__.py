"""`python3 -m nmdp.sweep ARGS`, which `nmdp sweep ARGS` runs (see main.py)."""
import sys

from .main import main

sys.exit(main())

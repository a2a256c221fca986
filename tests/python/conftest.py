"""Shared fixtures of the Python tests: where the sources, the shared robots and the nmdp executable
are (ctest sets NMDP_SOURCE_DIR, NMDP_SHARED_DIR and NMDP_BINARY; run by hand, they default to this
checkout, ../shared and build/nmdp)."""
import os

import pytest

SOURCE_DIR = os.environ.get("NMDP_SOURCE_DIR") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SHARED_DIR = os.environ.get("NMDP_SHARED_DIR") or os.path.join(SOURCE_DIR, "..", "shared")
NMDP_BINARY = os.environ.get("NMDP_BINARY") or os.path.join(SOURCE_DIR, "build", "nmdp")


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def nmdp_binary():
    return NMDP_BINARY


def scene_path(name):
    """A scene under models/scenes, e.g. scene_path("quadruped_trot_sand.json")."""
    return os.path.join(SOURCE_DIR, "models", "scenes", name)


def shared_or_skip(*parts):
    """A file under ../shared, or a skip saying it is absent."""
    path = os.path.join(SHARED_DIR, *parts)
    if not os.path.exists(path):
        pytest.skip(f"{path} is absent (../shared is read in place)")
    return path

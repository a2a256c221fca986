"""nmdp.Scene: Scene.load(path, overrides) reads a scene as `nmdp simulate path --set ...` does."""
import pathlib

import pytest

import nmdp
from conftest import scene_path


def test_overrides_take_python_values():
    scene = nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), {
        "integrator.dt": 0.02,                                        # a number
        "integrator.method": "ne-zopgm",                              # a plain string, as on the command line
        "robot.initial.velocity.base_linear": [0.5, 0, 0],            # a list
        "contacts.model": {"type": "coulomb", "mu": 0.4},             # an object
        "duration": 1,
    })
    resolved = scene.to_dict()
    assert scene.dt == 0.02 and scene.duration == 1.0
    assert resolved["integrator"]["dt"] == 0.02
    assert resolved["integrator"]["method"] == "ne-zopgm"
    assert resolved["robot"]["initial"]["velocity"]["base_linear"] == [0.5, 0, 0]
    assert resolved["contacts"]["model"]["mu"] == 0.4


def test_overrides_as_set_strings_equal_the_dict():
    as_dict = nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), {"integrator.dt": 0.02, "integrator.method": "ne-zopgm"})
    as_list = nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), ["integrator.dt=0.02", "integrator.method=ne-zopgm"])
    assert as_dict.to_dict() == as_list.to_dict()


def test_overrides_apply_in_order():
    scene = nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), ["duration=3", "duration=2"])
    assert scene.duration == 2.0


def test_path_may_be_a_pathlib_path_and_is_kept_as_given():
    scene = nmdp.Scene.load(pathlib.Path(scene_path("quadruped_stand_flat.json")))
    assert scene.path == scene_path("quadruped_stand_flat.json")
    assert scene.to_dict()["duration"] == 5.0


def test_a_string_that_looks_like_json_stays_a_string():
    # "0.02" is text in Python, so it reaches the scene as the JSON string "0.02", which dt refuses:
    # the command line's --set integrator.dt=0.02 would have been the number.
    with pytest.raises(ValueError, match=r"integrator\.dt"):
        nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), {"integrator.dt": "0.02"})


@pytest.mark.parametrize("value", [float("nan"), float("inf"), {1, 2}, object()])
def test_values_without_a_json_form_are_value_errors(value):
    with pytest.raises(ValueError, match=r"quadruped_stand_flat\.json: --set integrator\.dt"):
        nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), {"integrator.dt": value})


def test_overrides_of_the_wrong_kind_are_value_errors():
    with pytest.raises(ValueError, match="overrides: expected a dict"):
        nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), "integrator.dt=0.02")
    with pytest.raises(ValueError, match="overrides: keys are scene key paths"):
        nmdp.Scene.load(scene_path("quadruped_stand_flat.json"), {1: 2})

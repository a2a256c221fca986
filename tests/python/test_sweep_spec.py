"""The sweep file (nmdp.sweep.spec): its expansion into runs and the messages for bad files; the
keys checked by the executable before anything runs (nmdp.sweep.check); `nmdp sweep`'s exit 1 for
bad input with nothing written."""
import json
import subprocess

import pytest

from conftest import NMDP_BINARY, scene_path
from nmdp.sweep import check, spec

SCENE = scene_path("quadruped_trot_sand.json")


def write(tmp_path, content, name="sweep.json"):
    path = tmp_path / name
    path.write_text(content if isinstance(content, str) else json.dumps(content))
    return str(path)


def load(tmp_path, content):
    return spec.load(write(tmp_path, content))


def error(tmp_path, content):
    path = write(tmp_path, content)
    with pytest.raises(spec.SweepError) as e:
        spec.load(path)
    assert str(e.value).startswith(path + ": "), str(e.value)
    return str(e.value)[len(path) + 2:]


def test_grid_combinations_in_key_order_then_listed_runs_each_over_the_base(tmp_path):
    s = load(tmp_path, {"scene": SCENE, "base": {"duration": 0.2, "integrator.dt": 0.05},
                        "grid": {"integrator.dt": [0.01, 0.02], "controller.kd": [1, 3, 5]},
                        "runs": [{"integrator.method": "ne-pgm"}, {}]})
    got = [r.overrides for r in s.runs]
    assert got[:6] == [{"duration": 0.2, "integrator.dt": dt, "controller.kd": kd} for dt in (0.01, 0.02) for kd in (1, 3, 5)]
    assert got[6:] == [{"duration": 0.2, "integrator.dt": 0.05, "integrator.method": "ne-pgm"},
                       {"duration": 0.2, "integrator.dt": 0.05}]
    assert s.keys() == ["duration", "integrator.dt", "controller.kd", "integrator.method"]
    assert all(r.scene == SCENE for r in s.runs)


def test_a_runs_key_applies_after_the_base_so_it_may_set_inside_an_object_the_base_replaces(tmp_path):
    s = load(tmp_path, {"scene": SCENE, "base": {"controller.gait.period": 0.4, "controller.gait": {"type": "trot"}},
                        "runs": [{"controller.gait.period": 0.6}]})
    assert list(s.runs[0].overrides.items()) == [("controller.gait", {"type": "trot"}), ("controller.gait.period", 0.6)]


def test_the_scene_is_relative_to_the_sweep_file(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "scene.json").write_text("{}")
    s = spec.load(write(tmp_path, {"scene": "sub/scene.json", "runs": [{}]}))
    assert s.scene == str(tmp_path / "sub" / "scene.json")


def test_ids_are_stable_and_depend_on_the_scene_and_the_overrides_not_their_order(tmp_path):
    a = spec.Run(SCENE, {"integrator.dt": 0.01, "duration": 1})
    assert a.id == spec.Run(SCENE, {"duration": 1, "integrator.dt": 0.01}).id
    assert a.id == spec.run_id(SCENE, {"duration": 1, "integrator.dt": 0.01})
    assert len(a.id) == 12 and int(a.id, 16) >= 0
    assert a.id != spec.Run(SCENE, {"integrator.dt": 0.02, "duration": 1}).id
    assert a.id != spec.Run(scene_path("quadruped_trot_flat.json"), {"integrator.dt": 0.01, "duration": 1}).id
    # 1 and 1.0 are one value to the scene but two texts; they stay two runs (a sweep never merges them).
    assert spec.Run(SCENE, {"duration": 1}).id != spec.Run(SCENE, {"duration": 1.0}).id


def test_values_go_to_set_as_json_so_a_string_stays_a_string(tmp_path):
    r = spec.Run(SCENE, {"integrator.method": "ne-pgm", "integrator.dt": 0.02, "x.name": "1",
                         "controller.kp": {"FL_hip": 100}, "integrator.adaptive": False})
    assert r.sets() == ['integrator.method="ne-pgm"', "integrator.dt=0.02", 'x.name="1"',
                        'controller.kp={"FL_hip":100}', "integrator.adaptive=false"]


@pytest.mark.parametrize("content, message", [
    ({"scene": SCENE, "runs": [{}], "grids": {}}, "unknown key 'grids' (a sweep file has scene, base, grid, runs)"),
    ({"scene": SCENE, "grid": {"integrator.dt": 0.01}}, "grid.integrator.dt: a non-empty list of values expected"),
    ({"scene": SCENE, "grid": {"integrator.dt": []}}, "grid.integrator.dt: a non-empty list of values expected"),
    ({"scene": SCENE, "grid": [0.01]}, "grid: an object of key: [values] expected"),
    ({"scene": SCENE, "runs": {"duration": 1}}, "runs: a list of objects expected"),
    ({"scene": SCENE, "runs": [{"duration": 1}, 3]}, "runs[1]: an object of key: value expected, got 3"),
    ({"scene": SCENE, "base": [1]}, "base: an object of key: value expected, got [1]"),
    ({"scene": SCENE}, "no runs: give a grid or runs"),
    ({"scene": SCENE, "grid": {}, "runs": []}, "no runs: give a grid or runs"),
    ({"scene": SCENE, "grid": {"duration": [1, 2]}, "runs": [{"duration": 2}]},
     "runs[0] is the same run as grid combination 2: {\"duration\":2}"),
    ({"scene": SCENE, "base": {"duration": 2}, "runs": [{}, {"duration": 2}]},
     "runs[1] is the same run as runs[0]: {\"duration\":2}"),
    ({"runs": [{}]}, "scene: the scene file's path expected (relative to the sweep file)"),
    ({"scene": "absent.json", "runs": [{}]}, "scene: "),
    ({"scene": SCENE, "runs": [{"integrator.dt=0.1": 1}]}, "runs[0]: 'integrator.dt=0.1' is not a scene key"),
    ({"scene": SCENE, "grid": {"": [1]}}, "grid: '' is not a scene key"),
    ([1, 2], "an object with scene, base, grid and runs expected"),
    ('{"scene": "s.json", "runs": [{"duration": NaN}]}', "NaN is not JSON (a number must be finite)"),
    ('{"scene": "s.json", "runs": [{"duration": 1e999}]}', "1e999 is out of range (a number must be finite)"),
    ('{"scene": "s.json", "runs": [{"duration": 1, "duration": 2}]}', "key 'duration' appears twice in one object"),
    ('{"scene": "s.json", "runs": [{}]', "not valid JSON"),
    ("\xff\xfe", "not valid JSON"),
])
def test_bad_sweep_files_name_the_file_and_the_key(tmp_path, content, message):
    assert message in error(tmp_path, content)


def test_a_grid_beyond_the_limit_is_refused_before_it_is_expanded(tmp_path):
    grid = {f"k{i}": list(range(10)) for i in range(6)}  # 10^6 combinations
    assert f"grid: more than {spec.MAX_RUNS} combinations" in error(tmp_path, {"scene": SCENE, "grid": grid})


def test_a_missing_sweep_file_or_a_folder_is_one_message(tmp_path):
    with pytest.raises(spec.SweepError, match="absent.json: No such file"):
        spec.load(str(tmp_path / "absent.json"))
    with pytest.raises(spec.SweepError, match="not a regular file"):
        spec.load(str(tmp_path))


def test_the_executable_checks_the_first_run_and_each_run_that_adds_a_key():
    runs = [spec.Run(SCENE, {"duration": 1, "integrator.dt": d}) for d in (0.01, 0.02)]
    runs += [spec.Run(SCENE, {"duration": 1, "controller.kd": 2}), spec.Run(SCENE, {"controller.kd": 3})]
    assert check.runs_to_check(runs) == [runs[0], runs[2]]


def test_a_misspelt_key_is_the_executables_message_naming_the_run(tmp_path):
    runs = [spec.Run(SCENE, {"duration": 0.1}), spec.Run(SCENE, {"integrator.dtt": 0.01})]
    with pytest.raises(spec.SweepError) as e:
        check.check(NMDP_BINARY, "sweep.json", runs, lambda r: f"run {r.id}")
    assert str(e.value).startswith(f"sweep.json: run {runs[1].id}: ")
    assert "integrator.dtt: unknown key (did you mean 'dt'?)" in str(e.value)
    check.check(NMDP_BINARY, "sweep.json", runs[:1], lambda r: r.id)  # a good run passes


def sweep_command(*args):
    return subprocess.run([NMDP_BINARY, "sweep", *args], capture_output=True, text=True, timeout=60)


def test_nmdp_sweep_exits_1_with_one_message_and_writes_nothing_for_bad_input(tmp_path):
    out = tmp_path / "out"
    bad_value_type = write(tmp_path, {"scene": SCENE, "grid": {"integrator.dt": 0.01}})
    p = sweep_command(bad_value_type, "--out", str(out))
    assert p.returncode == 1, p.stderr
    assert p.stderr.strip() == f"nmdp sweep: error: {bad_value_type}: grid.integrator.dt: a non-empty list of values expected"
    misspelt = write(tmp_path, {"scene": SCENE, "base": {"duration": 0.05}, "runs": [{"controler.kd": 1}]}, "b.json")
    p = sweep_command(misspelt, "--out", str(out))
    assert p.returncode == 1 and "controler: unknown key" in p.stderr and p.stderr.count("\n") == 1, p.stderr
    p = sweep_command(misspelt, "--workers", "0", "--out", str(out))
    assert p.returncode == 1 and "--workers 0: at least 1" in p.stderr, p.stderr
    p = sweep_command(misspelt)
    assert p.returncode == 1 and "the following arguments are required: --out" in p.stderr, p.stderr
    assert not out.exists()


def test_nmdp_sweep_help_names_the_options():
    p = sweep_command("--help")
    assert p.returncode == 0
    for option in ("--out", "--scheduler", "--workers", "--quiet", "grid", "runs", "base"):
        assert option in p.stdout


def test_nmdp_sweep_says_so_when_its_python_package_is_missing(tmp_path):
    binary = tmp_path / "nmdp"  # a copy (a link would resolve to the build's folder): no python/ beside it
    binary.write_bytes(open(NMDP_BINARY, "rb").read())
    binary.chmod(0o755)
    p = subprocess.run([str(binary), "sweep", "x.json", "--out", str(tmp_path / "o")], capture_output=True, text=True)
    assert p.returncode == 1
    assert f"the Python package nmdp.sweep is not in {tmp_path}/python" in p.stderr, p.stderr

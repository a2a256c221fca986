"""nmdp.fit: the same model file as `nmdp fit --out` (every dataset and attribute; only the wall time
differs), the same model from a dict of arrays as from the path, a model usable at once that equals
the one loaded from the file bit for bit, the report as nmdp fit stores it, and bad input as
ValueError with the CLI's message."""
import json
import os
import re
import subprocess
import threading
import time

import h5py
import numpy as np
import pytest

import nmdp
from conftest import NMDP_BINARY, SOURCE_DIR

SAMPLES = os.path.join(SOURCE_DIR, "data", "granular", "rft_quadruped_samples")
FIT_CONFIG = os.path.join(SOURCE_DIR, "data", "granular", "rft_quadruped_fit.json")
TINY_MLP = {"mlp": {"max_epochs": 4, "width": 8, "validation_fraction": 0.2, "patience": 0}}


def cli_fit(model, config, out):
    subprocess.run([NMDP_BINARY, "fit", "--data", SAMPLES, "--model", model, "--config", json.dumps(config),
                    "--out", out, "--quiet"], check=True, capture_output=True)


def cli_error(args):
    run = subprocess.run([NMDP_BINARY] + args, capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    return run.stderr.strip().split(": error: ", 1)[1]


def without_time(text):
    """A report without its wall time ("fit time 0.78 ms", "training time 1.2 s")."""
    return re.sub(r"time [0-9.e+-]+ m?s", "time T", text.decode() if isinstance(text, bytes) else text)


def contents(path, skip_attributes=()):
    """Every dataset and attribute of an HDF5 file, by "group@attribute" or dataset name."""
    out = {}
    with h5py.File(path) as f:
        def visit(name, obj):
            for key, value in obj.attrs.items():
                out[name + "@" + key] = value
            if isinstance(obj, h5py.Dataset):
                out[name] = obj[()]
        visit("", f)
        f.visititems(visit)
    for key in skip_attributes:
        out.pop(key)
    return out


def assert_same_file(a, b):
    ca, cb = contents(a, ["fit@seconds"]), contents(b, ["fit@seconds"])
    assert sorted(ca) == sorted(cb)
    for key in ca:
        if key == "fit@report":
            assert without_time(ca[key]) == without_time(cb[key])
        else:
            assert np.array_equal(ca[key], cb[key]), key


def samples_dict():
    """The CSV folder as a dict of arrays (as importSandSamplesCsv reads it)."""
    s = np.genfromtxt(os.path.join(SAMPLES, "wrench_samples.csv"), delimiter=",", names=True)
    scalars = dict(line.split() for line in open(os.path.join(SAMPLES, "scalars.txt")))
    return {"features": np.stack([s["depth"], s["theta"]], axis=1), "vertex": s["vel_index"].astype(int),
            "wrench": np.stack([s["fx"], s["fz"], s["wy"]], axis=1), "torque_centre": float(scalars["cT"])}


GRID = (np.linspace(-0.08, 0.005, 35)[:, None], np.linspace(-1.3, 1.3, 27)[None, :])


def test_rbf_fit_writes_the_cli_file_and_returns_its_model(tmp_path):
    config = json.load(open(FIT_CONFIG))
    cli_out, py_out = str(tmp_path / "cli.h5"), str(tmp_path / "py.h5")
    cli_fit("rbf", config, cli_out)
    model, report = nmdp.fit(SAMPLES, "rbf", config, out=py_out)
    assert_same_file(cli_out, py_out)
    assert model.configuration()["file"] == py_out
    with h5py.File(cli_out) as f:
        assert np.array_equal(report["loo_relative"], f["fit/loo_relative"][()])
        assert np.array_equal(report["points"], f["fit/points"][()])
        assert report["loo_rms"] == f["fit"].attrs["loo_rms"]
        assert without_time(report["text"]) == without_time(f["fit"].attrs["report"])
    assert report["model"] == "rbf" and report["loo_relative"].shape == (99, 13)
    assert report["settings"]["rbf"]["scaling"] == [20.0, 1.0]
    # Without out the model is built in memory, equal bit for bit to the file's.
    memory, _ = nmdp.fit(SAMPLES, "rbf", FIT_CONFIG)  # the configuration as a file, as --config FILE
    assert memory.configuration() is None
    from_file = nmdp.ContactModel.from_config({"type": "rbf", "file": cli_out})
    V, dV = memory.vertices(*GRID, with_derivatives=True)
    file_V, file_dV = from_file.vertices(*GRID, with_derivatives=True)
    assert np.array_equal(V, file_V) and np.array_equal(dV, file_dV)
    assert np.abs(V).max() > 10.0


def test_dict_dataset_gives_the_model_of_the_path(tmp_path):
    config = json.load(open(FIT_CONFIG))
    from_path, path_report = nmdp.fit(SAMPLES, "rbf", config, out=str(tmp_path / "a.h5"))
    from_dict, dict_report = nmdp.fit(samples_dict(), "rbf", config, out=str(tmp_path / "b.h5"))
    assert dict_report["data"] == "data"
    assert np.array_equal(from_path.vertices(*GRID), from_dict.vertices(*GRID))
    assert np.array_equal(path_report["loo_relative"], dict_report["loo_relative"])
    a, b = contents(tmp_path / "a.h5"), contents(tmp_path / "b.h5")
    for key in a:
        if key.startswith("rbf") or key.startswith("@") or key in ("fit/loo_error", "fit/values", "fit/origin"):
            assert np.array_equal(a[key], b[key]), key


def test_mlp_fit_writes_the_cli_file_and_reports_validation(tmp_path):
    cli_out, py_out = str(tmp_path / "cli.h5"), str(tmp_path / "py.h5")
    cli_fit("mlp", TINY_MLP, cli_out)
    model, report = nmdp.fit(SAMPLES, model="mlp", config=TINY_MLP, out=py_out)
    assert_same_file(cli_out, py_out)
    assert report["model"] == "mlp" and report["epochs"] == 4 and report["history"].shape == (4, 2)
    assert report["validation"].dtype == bool and 0 < report["validation"].sum() < len(report["validation"])
    assert report["relative_error"].shape == (len(report["validation"]), 13)
    assert np.isfinite(report["validation_loss"])
    memory, _ = nmdp.fit(SAMPLES, "mlp", TINY_MLP)
    assert np.array_equal(memory.vertices(*GRID), model.vertices(*GRID))


def test_bad_input_is_value_error_with_the_cli_message(tmp_path):
    out = str(tmp_path / "m.h5")
    for config in ({"rbf": {"kernal": "thin_plate"}}, {"rbf": {"ridge": -1}}, {"augmentation": {"mirror": "yes"}}):
        with pytest.raises(ValueError) as raised:
            nmdp.fit(SAMPLES, "rbf", config)
        expected = cli_error(["fit", "--data", SAMPLES, "--model", "rbf", "--config", json.dumps(config), "--out", out])
        assert str(raised.value) == expected
    missing = str(tmp_path / "nothing")
    with pytest.raises(ValueError) as raised:
        nmdp.fit(missing, "rbf")
    assert str(raised.value) == cli_error(["fit", "--data", missing, "--model", "rbf", "--out", out])
    with pytest.raises(ValueError) as raised:
        nmdp.fit(SAMPLES, "spline")
    assert str(raised.value) == cli_error(["fit", "--data", SAMPLES, "--model", "spline", "--out", out])
    # The output replaces no input.
    target = os.path.join(SAMPLES, "features.csv")
    with pytest.raises(ValueError) as raised:
        nmdp.fit(SAMPLES, "rbf", out=target)
    assert str(raised.value) == cli_error(["fit", "--data", SAMPLES, "--model", "rbf", "--out", target])
    assert not os.path.exists(out)
    with pytest.raises(ValueError, match="data: expected a path .* a list is not accepted"):
        nmdp.fit([1, 2], "rbf")
    with pytest.raises(ValueError, match="config: expected a dict .* a int is not accepted"):
        nmdp.fit(SAMPLES, "rbf", config=3)


def test_fit_releases_the_gil():
    """A Python thread keeps running while another fits: the longest pause between its steps is a
    small part of the fit's duration (with the GIL held it would wait for the whole fit)."""
    config = {"mlp": {"max_epochs": 1000, "width": 32, "validation_fraction": 0, "patience": 0}}
    worker = threading.Thread(target=nmdp.fit, args=(SAMPLES, "mlp", config))
    start = time.perf_counter()
    worker.start()
    stamps = [start]
    while worker.is_alive():
        stamps.append(time.perf_counter())
        time.sleep(0.001)
    duration = time.perf_counter() - start
    assert duration > 0.3, f"the fit took {duration:.3f} s: too short to tell"
    assert max(np.diff(stamps)) < 0.25 * duration


@pytest.mark.parametrize("change,message", [
    (lambda d: d.pop("wrench"), r"data\['wrench'\]: missing"),
    (lambda d: d.update(features=d["features"][:, 0]), r"data\['features'\]: expected N x F"),
    (lambda d: d.update(vertex=d["vertex"][:-1]), "data: features, vertex and wrench have"),
    (lambda d: d.update(vertex=d["vertex"] + 0.5), r"data\['vertex'\]\[0\]: 0.500000 is not a vertex index"),
    (lambda d: d["wrench"].__setitem__((5, 1), np.nan), "data: dataset '/wrench'"),
    (lambda d: d.update(colour=1), "data: unknown key 'colour'"),
    (lambda d: d.pop("torque_centre"), "^data: .*torque"),
])
def test_bad_dict_dataset_names_the_key(change, message):
    data = samples_dict()
    change(data)
    with pytest.raises(ValueError, match=message):
        nmdp.fit(data, "rbf")

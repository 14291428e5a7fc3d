"""``idkit validate MODEL DATA`` and ``idkit fit auto SET``: exit statuses, outputs, bad input."""

import functools

import pytest

import idkit.fit.auto as auto
from idkit.cli.main import main
from idkit.io import write_measurement_set
from idkit.models import IwanModel, load_model_document, save_model
from idkit.synth.devices import DEVICES, device_records, earthquake_history, sine_history

DEVICE = DEVICES["jenkin"]


@pytest.fixture(scope="module")
def device_set(tmp_path_factory):
    """Four training sines and one held-out earthquake-like record of the Jenkin device."""
    folder = tmp_path_factory.mktemp("device")
    sines = {f"sine_{1e3 * a:g}mm": sine_history(a, 0.5, cycles=2, sample_rate_hz=100.0) for a in (3e-3, 6e-3, 12e-3)}
    records = device_records(DEVICE, sines, force_noise=3.0, seed=1, isolator="damper")
    records += device_records(DEVICE, {"quake": earthquake_history(10e-3, duration=12.0, dominant_hz=0.5,
                                                                   sample_rate_hz=100.0, seed=1)},
                              force_noise=3.0, seed=1, split="validation", isolator="damper")
    write_measurement_set(folder, records, name="jenkin device")
    return folder


def model_file(folder, name, **change):
    parts = dict(g1=DEVICE.parallel_stiffness, k=list(DEVICE.stiffness), fc=list(DEVICE.slip_force)) | change
    return save_model(IwanModel(**parts), folder / name)


def test_validate_exit_statuses_table_and_plots(device_set, tmp_path, capsys):
    right = model_file(tmp_path, "right.json")
    assert main(["validate", str(right), str(device_set), "-o", str(tmp_path / "t.csv"),
                 "--plots", str(tmp_path / "plots")]) == 0
    printed = capsys.readouterr().out
    assert "force histories" in printed and "PASS" in printed and "quake" in printed
    # the simple baselines, fitted on the set's fit split, printed beside the model's error
    assert "baseline Jenkin element" in printed and "better than every baseline" in printed
    assert (tmp_path / "t.csv").read_text().startswith("record,")
    assert (tmp_path / "plots" / "history_quake.png").stat().st_size > 1000
    wrong = model_file(tmp_path, "wrong.json", fc=[180.0, 600.0])
    assert main(["validate", str(wrong), str(device_set)]) == 1
    assert "FAIL" in capsys.readouterr().err
    assert main(["validate", str(right), str(device_set), "--plots", str(tmp_path / "plots")]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main(["validate", str(right), str(tmp_path / "missing")]) == 2


def test_fit_auto_writes_the_chosen_model_with_its_table(device_set, tmp_path, capsys, monkeypatch):
    """The command's wiring, with the one cheap family (the choice itself: tests/fit/test_auto.py)."""
    cheap = auto.Family("iwan", functools.partial(auto.fit_plain_iwan, orders=(2,), points_per_set=100), "order 2")
    monkeypatch.setattr(auto, "FAMILIES", [cheap])
    output = tmp_path / "auto.json"
    status = main(["fit", "auto", str(device_set), "-o", str(output)])
    captured = capsys.readouterr()
    assert "Model choice by prediction" in captured.out and "cv_error_percent" in captured.out
    document = load_model_document(output)
    assert document["model"]["kind"] == "iwan" and document["provenance"]["family"] == "iwan"
    assert status == (0 if document["provenance"]["success"] else 1)
    assert [fold["records"] for fold in document["provenance"]["folds"]] == [["sine_3mm"], ["sine_6mm"], ["sine_12mm"]]
    assert main(["fit", "auto", str(device_set), "-o", str(output)]) == 2  # never overwritten

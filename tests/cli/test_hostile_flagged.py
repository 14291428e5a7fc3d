"""Inputs that are valid but give a result that must not pass as a success: written, flagged, non-zero."""

import json

import numpy as np
import pandas as pd
import pytest

from tests.cli.hostile import check, run_main
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set


def _loops(amplitudes, samples=1500):
    phase = np.linspace(0, 2 * np.pi * len(amplitudes), samples)
    envelope = np.repeat(amplitudes, samples // len(amplitudes))
    envelope = np.concatenate([envelope, np.full(samples - envelope.size, amplitudes[-1])])
    return envelope * np.sin(phase)


@pytest.fixture(scope="module")
def loop_sets(tmp_path_factory):
    """Two quasi-static sets: a linear spring (nothing slips) and a pure friction damper (no spring)."""
    folders = {}
    for name, law in (("linear", lambda x: 2e4 * x), ("friction", lambda x: 30.0 * np.sign(np.gradient(x)))):
        measurements = []
        for kind, amplitudes in (("small", [4e-3, 2e-3, 1e-3]), ("large", [12e-3, 8e-3])):
            x = _loops(np.array(amplitudes))
            info = MeasurementInfo(id=f"qs_{kind}", isolator="wire_rope", repetition=1, split="fit",
                                   sample_rate_hz=50.0)
            measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=law(x),
                                                       info=info))
        folder = tmp_path_factory.mktemp(name) / "set"
        write_measurement_set(folder, measurements, name=name)
        folders[name] = folder
    return folders


@pytest.mark.parametrize("name", ["linear", "friction"])
def test_a_fit_that_is_not_a_success_is_written_with_its_reasons_and_exits_1(loop_sets, tmp_path, name):
    output = tmp_path / "model.json"
    outcome = run_main(["fit", "iwan", loop_sets[name], "-o", output], inputs=[loop_sets[name]])
    check(outcome, "flagged", ["not a success"], case=f"fit iwan on a {name} set")
    assert outcome.status == 1
    provenance = json.loads(output.read_text())["provenance"]
    assert provenance["success"] is False and provenance["reasons"]


@pytest.mark.parametrize("command, options", [
    # 4e100 m/s at impact, a 1e120 m base amplitude (the cubic spring's y^3 overflows; 1e300 m is refused
    # before simulating: forces above 1.34e154 N, MAX_FORCE_SCALE): no step converges, the row is NaN
    ("drop", ["--mass", "8", "--height", "0.05", "1e200"]),
    ("harmonic", ["--mass", "8", "--freq", "10", "--amplitude", "1e-3", "1e120", "--quiet"]),
])
def test_a_simulated_point_that_is_not_valid_is_written_and_exits_1(tmp_path, command, options):
    from idkit.models import library, save_model

    model, output = tmp_path / "wire_rope.json", tmp_path / "table.csv"
    save_model(library.get("table_7_1_wire_rope"), model)
    outcome = run_main(["simulate", command, model, *options, "-o", output], inputs=[model])
    check(outcome, "flagged", ["1 of 2", "not valid", "did not converge"], case=f"simulate {command} invalid point")
    assert outcome.status == 1
    status = pd.read_csv(output)["status"].tolist()
    assert status[0] == "ok" and status[1] != "ok"  # the valid point is kept as computed

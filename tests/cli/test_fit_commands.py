"""``idkit fit ...`` end to end on a small synthetic set written with idkit.io; plots of fits; bad input."""

import json

import numpy as np
import pytest

from idkit.cli.main import main
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set
from idkit.models import load_model_document
from tests.fit.small_set import sine_loops, write_small_set


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    return write_small_set(tmp_path_factory.mktemp("set"))


def test_cli_fit_iwan_writes_model_plots_and_refuses_overwrite(dataset, tmp_path, capsys):
    output = tmp_path / "wr.json"
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "-o", str(output), "--plots", str(tmp_path / "plots")]) == 0
    printed = capsys.readouterr().out
    assert "Iwan fit, order 2" in printed and "qs_small_1" in printed
    document = load_model_document(output)
    assert document["model"]["kind"] == "iwan"
    assert set(document["provenance"]["data"]["files"]) == {f"quasi_static/qs_{k}_{r}.csv" for k in ("small", "large")
                                                            for r in (1, 2)}
    assert (tmp_path / "plots" / "iwan_loops.png").stat().st_size > 1000
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "-o", str(output)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    other = tmp_path / "wr2.json"
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "-o", str(other), "--plots", str(tmp_path / "plots")]) == 2
    assert not other.exists()  # stopped before fitting


@pytest.mark.slow
def test_cli_fit_maxwell_and_boucwen(dataset, tmp_path, capsys):
    output = tmp_path / "el.json"
    assert main(["fit", "maxwell", str(dataset), "--order", "2", "--cross-check", "-o", str(output),
                 "--plots", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert "global cross-check" in printed and "k0 =" in printed
    params = load_model_document(output)["model"]["params"]
    assert params["k_1"] > 0 and params["rate_2"] > params["rate_1"]
    for name in ("maxwell_frf.png", "maxwell_complex_stiffness.png", "maxwell_landscape.png"):
        assert (tmp_path / name).exists()
    bw = tmp_path / "bw.json"
    # a Bouc-Wen law on loops of an Iwan truth: about 3 % error, more than 2 points above the
    # loops' noise floor, so the fit is flagged (exit 1) with the model file written
    assert main(["fit", "boucwen", str(dataset), "--isolator", "wire_rope", "-o", str(bw), "--global-evals", "200", "--compare"]) == 1
    printed = capsys.readouterr().out
    assert "Bouc-Wen fit" in printed and "[[Summary]]" in printed and "above the noise floor" in printed
    assert json.loads(bw.read_text())["model"]["kind"] == "bouc_wen"


def test_cli_fit_maxwell_order_auto_keeps_the_recommended_order(dataset, tmp_path, capsys):
    """The set's white noise comes from the order-2 Table 7.3 elastomer: the rule keeps 2."""
    output = tmp_path / "auto.json"
    assert main(["fit", "maxwell", str(dataset), "--order", "auto", "-o", str(output)]) == 0
    printed = capsys.readouterr().out
    assert "[[Order selection (rule: lowest successful order within 10 % of the best error)]]" in printed
    params = load_model_document(output)["model"]["params"]
    assert sorted(name for name in params if name.startswith("rate_")) == ["rate_1", "rate_2"]


@pytest.mark.parametrize("argv, message", [
    (["fit", "iwan", "{missing}", "-o", "{out}"], "(not found), expected a measurement set"),
    (["fit", "iwan", "{set}", "--order", "0", "-o", "{out}"], "--order"),
    # the set holds wire-rope and elastomer loops: the default isolator is not guessed
    (["fit", "iwan", "{set}", "-o", "{out}"], "found quasi_static records of 2 isolators (elastomer, wire_rope); "
                                              "expected one, or the isolator named: choose it with --isolator "
                                              "elastomer"),
    (["fit", "maxwell", "{set}", "--isolator", "hybrid", "-o", "{out}"], "found none"),
    (["fit", "iwan", "{set}", "--isolator", "wire_rope", "--small-threshold", "0.1", "-o", "{out}"],
     "no large-loop record"),
])
def test_cli_bad_input_exits_with_code_2(dataset, tmp_path, capsys, argv, message):
    values = {"missing": str(tmp_path / "nothing"), "out": str(tmp_path / "m.json"), "set": str(dataset)}
    try:
        status = main([a.format(**values) for a in argv])
    except SystemExit as stop:  # argparse refuses a bad option value itself (exit 2)
        status = stop.code
    assert status == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "m.json").exists()


def test_cli_fit_iwan_valid_range(dataset, tmp_path):
    output = tmp_path / "bounded.json"
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "-o", str(output), "--valid-range", "-0.05", "0.05"]) == 0
    document = load_model_document(output)
    assert document["provenance"]["settings"]["valid_range"] == [-0.05, 0.05]
    from idkit.models import load_model

    lower, upper = load_model(output).valid_deflection_range()
    assert lower <= -0.05 and upper >= 0.05


def test_cli_fit_that_is_not_a_success_is_written_flagged_and_exits_1(tmp_path, capsys):
    """A linear spring measured as loops: no element ever slips, so no slip force is determined."""
    from idkit.io import load_measurement_set

    measurements = []
    for kind, amplitudes in (("small", [4e-3, 2e-3, 1e-3]), ("large", [12e-3, 8e-3])):
        x = sine_loops(np.array(amplitudes))
        info = MeasurementInfo(id=f"qs_{kind}", isolator="wire_rope", repetition=1, split="fit",
                               sample_rate_hz=50.0)
        measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=2e4 * x,
                                                   info=info))
    folder = tmp_path / "linear"
    write_measurement_set(folder, measurements, name="linear spring")
    output = tmp_path / "linear.json"
    assert main(["fit", "iwan", str(folder), "-o", str(output)]) == 1
    assert "not a success" in capsys.readouterr().err
    provenance = load_model_document(output)["provenance"]
    assert provenance["success"] is False and any("never slips" in r for r in provenance["reasons"])
    assert set(provenance["start_states"].values()) == {"virgin"}  # the records start unloaded
    assert load_measurement_set(folder).measurements  # the input is still readable


def test_cli_fit_iwan_order_auto_picks_the_generating_order(dataset, tmp_path, capsys):
    """The loops come from an order-2 rope: the order rule keeps 2 and the table is recorded."""
    output = tmp_path / "auto.json"
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "--order", "auto", "-o", str(output)]) == 0
    assert "Iwan order table" in capsys.readouterr().out
    document = load_model_document(output)
    assert sum(name.startswith("k_") for name in document["model"]["params"]) == 2
    table = document["provenance"]["order_table"]
    assert [row["order"] for row in table] == [1, 2, 3, 4, 5, 6]
    assert [row["order"] for row in table if row["recommended"]] == [2]




def test_cli_fit_maxwell_k0_method_is_recorded(dataset, tmp_path, capsys):
    # the small set's elastomer loops are a pure spring plus noise: both methods read its k0,
    # and the model file says which one was used and what the secant read
    documents = {}
    for method in ("relaxation", "secant"):
        output = tmp_path / f"el_{method}.json"
        assert main(["fit", "maxwell", str(dataset), "--order", "1", "--k0-method", method, "-o", str(output)]) in (0, 1)
        documents[method] = json.loads(output.read_text())
        k0 = documents[method]["provenance"]["k0"]
        assert k0["method"] == method and documents[method]["provenance"]["options"]["k0_method"] == method
    printed = capsys.readouterr().out
    assert "relaxation of the loops fitted" in printed and "secant slope;" in printed
    relaxed, secant = (documents[m]["provenance"]["k0"]["value_N_per_m"] for m in ("relaxation", "secant"))
    assert relaxed == pytest.approx(secant, rel=2e-3)
    assert documents["relaxation"]["provenance"]["k0"]["secant_N_per_m"] == pytest.approx(secant)
    with pytest.raises(SystemExit) as stopped:  # argparse names the option and the choices
        main(["fit", "maxwell", str(dataset), "--k0-method", "tangent", "-o", str(tmp_path / "x.json")])
    assert stopped.value.code == 2 and "--k0-method" in capsys.readouterr().err


def test_cli_fit_iwan_names_the_records_a_set_holds_for_another_isolator(dataset, tmp_path, capsys):
    """A set of another isolator (``--isolator`` default wire_rope) is named with what it holds,
    not with the valid range's Python arguments."""
    output = tmp_path / "wr.json"
    assert main(["fit", "iwan", str(dataset), "--isolator", "wire_rope", "--isolator", "mr_damper", "-o", str(output)]) == 2
    error = capsys.readouterr().err
    assert "--isolator mr_damper" in error and "available (kind, isolator, split)" in error
    assert "valid_range=None" not in error and not output.exists()

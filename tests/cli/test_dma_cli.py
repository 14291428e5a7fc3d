"""``idkit fit maxwell TABLE.csv`` and ``idkit inspect TABLE.csv`` on DMA / complex modulus tables."""

import json

import numpy as np
import pytest

from idkit.io.complex_stiffness import ComplexStiffnessTable, write_complex_stiffness
from idkit.io.provenance import Source
from idkit.models import GeneralizedMaxwell, load_model
from idkit.signal.shift_factors import wlf_log_shift
from tests.cli.hostile import check, run_main

MATERIAL = GeneralizedMaxwell(k0=1.0e6, k=np.full(12, 4.0e6), rate=np.logspace(-4, 7, 12), quantity="modulus")


def _isotherms(temperatures):
    freq = np.logspace(-1, 2, 16)
    rows = [(freq, MATERIAL.complex_modulus(freq * 10.0 ** wlf_log_shift(t, c1=9.0, c2_k=120.0,
                                                                           reference_temperature_k=290.0)),
             np.full(freq.size, t)) for t in temperatures]
    freq, value, temp = (np.concatenate(c) for c in zip(*rows))
    return ComplexStiffnessTable(freq=freq, storage=value.real, loss=value.imag, quantity="modulus",
                                 temperature=temp, source=Source())


@pytest.fixture
def dma_file(tmp_path):
    return write_complex_stiffness(_isotherms(np.arange(260.0, 321.0, 10.0)), tmp_path / "dma.csv")


@pytest.mark.parametrize("options", [["--k0-method", "secant"], ["--band", "2", "3"], ["--isolator", "pad"],
                                     ["--split", "validation"], ["--k0", "1e5"]])
def test_fit_maxwell_on_a_dma_table_refuses_the_set_options(dma_file, tmp_path, options):
    """Options of a measurement set are named, not accepted and ignored, for a DMA table."""
    out = tmp_path / "material.json"
    outcome = run_main(["fit", "maxwell", dma_file, "-o", out, "--order", "2", *options], inputs=[dma_file])
    check(outcome, "error", [options[0], "measurement sets"], case=f"dma-table{options[0]}")
    assert not out.exists()


def test_fit_maxwell_on_a_dma_table_writes_a_modulus_model(dma_file, tmp_path):
    out = tmp_path / "material.json"
    plots = tmp_path / "plots"
    outcome = run_main(["fit", "maxwell", dma_file, "-o", out, "--order", "6", "--reference-temperature", "16.85",
                        "--plots", plots], inputs=[dma_file])
    assert outcome.status in (0, 1), outcome.stderr
    assert sorted(p.name for p in plots.iterdir()) == ["maxwell_master_curve.png", "maxwell_shift_factors.png"]
    again = tmp_path / "again.json"  # figures are never overwritten: refused before fitting
    refused = run_main(["fit", "maxwell", dma_file, "-o", again, "--plots", plots], inputs=[dma_file, plots],
                       must_not_exist=[again])
    check(refused, "error", ["refusing to overwrite existing plot(s)", "maxwell_master_curve.png"])
    assert "isotherms" in outcome.stdout and "wlf: C1 = " in outcome.stdout
    document = json.loads(out.read_text())
    assert document["model"]["units"]["k0"] == "Pa"
    assert document["provenance"]["shift_factors"]["reference_temperature_K"] == pytest.approx(290.0)
    model = load_model(out)
    assert model.quantity == "modulus" and model.order == 6
    # the success flag the command's exit status reports is the one in the file
    assert (outcome.status == 0) == document["provenance"]["success"]


def test_inspect_a_dma_table_prints_isotherms_and_shift_factors(dma_file, tmp_path):
    plots = tmp_path / "plots"
    outcome = run_main(["inspect", dma_file, "--plots", plots], inputs=[dma_file])
    check(outcome, "ok", ["table_isotherms.png"])
    assert (plots / "table_isotherms.png").read_bytes()[:4] == b"\x89PNG"
    check(run_main(["inspect", dma_file, "--plots", plots], inputs=[dma_file, plots]), "error",
          ["refusing to overwrite", "--force"])
    check(run_main(["inspect", dma_file, "--plots", plots, "--force"], inputs=[dma_file]), "ok")
    assert "7 isotherms" in outcome.stdout and "modulus in Pa" in outcome.stdout
    assert "log_aT stderr" in outcome.stdout


def test_hostile_dma_tables_are_refused_by_name(tmp_path):
    one = write_complex_stiffness(_isotherms([290.0]), tmp_path / "one.csv")
    outcome = run_main(["fit", "maxwell", one, "-o", tmp_path / "m.json", "--order", "3"], inputs=[one],
                       must_not_exist=[tmp_path / "m.json"])
    check(outcome, "error", ["one.csv", "one isotherm", "at least two temperatures"], case="dma-one-isotherm")
    units = tmp_path / "units.csv"
    units.write_text("frequency [Hz],storage [atm],loss [atm]\n1,2,0.1\n2,3,0.2\n")
    outcome = run_main(["fit", "maxwell", units, "-o", tmp_path / "m.json"], inputs=[units],
                       must_not_exist=[tmp_path / "m.json"])
    check(outcome, "error", ["units.csv", "atm"], case="dma-unknown-unit")
    nofreq = tmp_path / "nofreq.csv"
    nofreq.write_text("time [s],storage [MPa],loss [MPa]\n1,2,0.1\n")
    outcome = run_main(["fit", "maxwell", nofreq, "-o", tmp_path / "m.json"], inputs=[nofreq],
                       must_not_exist=[tmp_path / "m.json"])
    check(outcome, "error", ["nofreq.csv", "frequency [Hz]"], case="dma-no-frequency-column")
    shift = tmp_path / "shift.csv"
    outcome = run_main(["fit", "maxwell", units, "-o", tmp_path / "m.json", "--use-given-shift-factors"],
                       inputs=[units], must_not_exist=[tmp_path / "m.json"])
    check(outcome, "error", ["--use-given-shift-factors", "--shift-factors"], case="dma-use-given-without-file")
    assert not shift.exists()


def test_fit_iwan_on_one_loop_file(tmp_path):
    # a lone loop record (no manifest beside it): its kind from the header, every record in it
    # fitted as a one-amplitude test
    from pathlib import Path
    import shutil

    source = Path(__file__).resolve().parents[2] / "data" / "wire_rope" / "quasi_static" / "qs_wr_large_1.csv.gz"
    lone = tmp_path / source.name
    shutil.copyfile(source, lone)
    out = tmp_path / "rope.json"
    # the bundled rope's slip changes with the deflection: the plain family stays more than 2
    # points above the record's noise floor, flagged, and the model file says why
    plain = run_main(["fit", "iwan", lone, "--family", "plain", "-o", out], inputs=[lone])
    check(plain, "flagged", ["above the noise floor"])
    assert "one-amplitude test" in plain.stdout
    assert load_model(out).kind == "iwan"
    # the family rule brings in the slip-modulated model, which reaches the floor
    modulated = tmp_path / "rope_modulated.json"
    outcome = run_main(["fit", "iwan", lone, "-o", modulated], inputs=[lone])
    check(outcome, "ok", ["Slip-modulated Iwan fit"])
    assert load_model(modulated).kind == "iwan_modulated"
    missing = run_main(["fit", "iwan", tmp_path / "nothing.csv", "-o", tmp_path / "x.json"],
                       must_not_exist=[tmp_path / "x.json"])
    check(missing, "error", ["nothing.csv", "(not found)"], case="fit-missing-file")


def test_report_of_a_table_takes_the_order_as_fit_does(dma_file, tmp_path):
    out = tmp_path / "report"
    outcome = run_main(["report", dma_file, "--order", "4", "-o", out, "--quiet"], inputs=[dma_file])
    assert outcome.status in (0, 1), outcome.stderr
    assert load_model(out / "model.json").order == 4
    refused = tmp_path / "refused"
    for order, words in (("41", ["--order", "found '41'", "1 to 40", "Prony terms of a table"]),
                         ("two", ["--order", "found 'two'"])):
        outcome = run_main(["report", dma_file, "--order", order, "-o", refused], inputs=[dma_file],
                           must_not_exist=[refused])
        check(outcome, "error", words, case=f"report-order-{order}")
    folder = tmp_path / "folder"
    folder.mkdir()
    outcome = run_main(["report", folder, "--order", "2", "-o", refused], must_not_exist=[refused])
    check(outcome, "error", ["--order", "applies to the report of one data file"], case="report-order-folder")

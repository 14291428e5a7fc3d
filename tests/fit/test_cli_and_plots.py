"""idkit fit ... end to end on a small synthetic set written with idkit.io; plots of fits; bad input."""

import json

import numpy as np
import pytest

from idkit.cli.main import main
from idkit.errors import DataError, FitError
from idkit.fit import (
    fit_iwan_measurements,
    fit_maxwell_measurements,
    loop_sets,
    maxwell_error_landscape,
    transmissibility_sets,
)
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, WhiteNoiseMeasurement, write_measurement_set
from idkit.models import IwanModel, library, load_model_document

TRUTH_IWAN = IwanModel(g1=3e3, g2=4e4, g3=3e5, k=[3e3, 3e3], fc=[8.3, 14.6])
ELASTOMER = library.get("table_7_3_elastomer")


def _loops(amplitudes, samples=1500):
    phase = np.linspace(0, 2 * np.pi * len(amplitudes), samples)
    envelope = np.repeat(amplitudes, samples // len(amplitudes))
    envelope = np.concatenate([envelope, np.full(samples - envelope.size, amplitudes[-1])])
    return envelope * np.sin(phase)


def _white_noise(mass, repetition, rng, fs=1000.0, n=16384):
    from scipy.signal import lfilter

    base = rng.standard_normal(n)
    freq = np.fft.rfftfreq(n, 1 / fs)
    stiffness = ELASTOMER.complex_stiffness(np.maximum(freq, 1e-3))
    h = stiffness / (stiffness - (mass + ELASTOMER.m_eff) * (2 * np.pi * freq) ** 2)
    top = np.fft.irfft(np.fft.rfft(base) * h, n)
    del lfilter
    time = np.arange(n) / fs
    info = MeasurementInfo(id=f"wn_{mass:.2f}_{repetition}", isolator="elastomer", top_mass_kg=mass,
                           repetition=repetition, split="fit", sample_rate_hz=fs)
    return WhiteNoiseMeasurement(time=time, v_base=base, v_top=top, info=info)


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    rng = np.random.default_rng(8)
    measurements = []
    for repetition in (1, 2):
        for kind, amplitudes in (("small", [4e-3, 2e-3, 1e-3, 0.3e-3]), ("large", [12e-3, 8e-3, 4e-3])):
            x = _loops(np.array(amplitudes))
            force = TRUTH_IWAN.force(x) + 0.05 * rng.standard_normal(x.size)
            info = MeasurementInfo(id=f"qs_{kind}_{repetition}", isolator="wire_rope", repetition=repetition,
                                   split="fit", sample_rate_hz=50.0)
            measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=force,
                                                       info=info))
        x = _loops(np.array([1e-3, 2e-3]), 800)
        info = MeasurementInfo(id=f"qs_el_{repetition}", isolator="elastomer", repetition=repetition, split="fit",
                               sample_rate_hz=50.0)
        measurements.append(QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x,
                                                   force=ELASTOMER.k0 * x + 0.01 * rng.standard_normal(x.size),
                                                   info=info))
        for mass in (0.99, 3.0, 6.4):
            measurements.append(_white_noise(mass, repetition, rng))
    folder = tmp_path_factory.mktemp("set")
    write_measurement_set(folder, measurements, name="cli test")
    return folder


def test_cli_fit_iwan_writes_model_plots_and_refuses_overwrite(dataset, tmp_path, capsys):
    output = tmp_path / "wr.json"
    assert main(["fit", "iwan", str(dataset), "-o", str(output), "--plots", str(tmp_path / "plots")]) == 0
    printed = capsys.readouterr().out
    assert "Iwan fit, order 2" in printed and "qs_small_1" in printed
    document = load_model_document(output)
    assert document["model"]["kind"] == "iwan"
    assert set(document["provenance"]["data"]["files"]) == {f"quasi_static/qs_{k}_{r}.csv" for k in ("small", "large")
                                                            for r in (1, 2)}
    assert (tmp_path / "plots" / "iwan_loops.png").stat().st_size > 1000
    assert main(["fit", "iwan", str(dataset), "-o", str(output)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    other = tmp_path / "wr2.json"
    assert main(["fit", "iwan", str(dataset), "-o", str(other), "--plots", str(tmp_path / "plots")]) == 2
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
    assert main(["fit", "boucwen", str(dataset), "-o", str(bw), "--global-evals", "200", "--compare"]) == 0
    printed = capsys.readouterr().out
    assert "Bouc-Wen fit" in printed and "[[Summary]]" in printed
    assert json.loads(bw.read_text())["model"]["kind"] == "bouc_wen"


@pytest.mark.parametrize("argv, message", [
    (["fit", "iwan", "{missing}", "-o", "{out}"], "not a folder"),
    (["fit", "iwan", "{set}", "--order", "0", "-o", "{out}"], "--order"),
    (["fit", "maxwell", "{set}", "--isolator", "hybrid", "-o", "{out}"], "found none"),
    (["fit", "iwan", "{set}", "--small-threshold", "0.1", "-o", "{out}"], "no large-loop record"),
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


def test_measurement_level_results_on_the_small_set(dataset):
    from idkit.io import load_measurement_set

    data = load_measurement_set(dataset)
    loops = loop_sets(data)
    assert [s.name for s in loops.small] == ["qs_small_1", "qs_small_2"]
    assert loops.small_repetitions == (1, 2)
    fit = fit_iwan_measurements(data, order=2)
    # the records change amplitude mid-cycle, so the cycled start state is approximate (errors of a few %);
    # the parameters themselves come back: noise 0.05 N on loops of ~100 N
    for name in ("g1", "k_1", "k_2"):
        assert fit.model.params()[name] == pytest.approx(TRUTH_IWAN.params()[name], rel=0.02)
    for name in ("fc_1", "fc_2"):  # slip forces absorb the start-state mismatch
        assert fit.model.params()[name] == pytest.approx(TRUTH_IWAN.params()[name], rel=0.20)
    assert fit.result.error_large < 0.10
    maxwell = fit_maxwell_measurements(data)
    assert maxwell.k0.k0 == pytest.approx(ELASTOMER.k0, rel=1e-3)
    assert maxwell.result.error < 0.02
    assert maxwell.model.k[1] == pytest.approx(ELASTOMER.k[1], rel=0.05)
    assert maxwell.result.parameters["k0"].stderr == maxwell.k0.stderr


def test_bad_frfs_and_orders_raise_fit_error(dataset):
    from idkit.io import load_measurement_set
    from idkit.fit import TransmissibilitySet, fit_maxwell

    frfs, _ = transmissibility_sets(load_measurement_set(dataset))
    broken = [TransmissibilitySet(f.mass, f.freq, np.where(f.freq > 50, 0, f.transmissibility), f.name)
              for f in frfs]
    with pytest.raises(FitError, match="found 0 at"):
        fit_maxwell(broken, k0=1e4)
    nan = [TransmissibilitySet(f.mass, f.freq, np.where(f.freq > 50, np.nan, f.transmissibility), f.name)
           for f in frfs]
    with pytest.raises(FitError, match="finite"):
        fit_maxwell(nan, k0=1e4)
    with pytest.raises(FitError, match="order"):
        fit_maxwell(frfs, k0=1e4, order=0)
    with pytest.raises(FitError, match="order"):
        fit_iwan_measurements(load_measurement_set(dataset), order=0)
    with pytest.raises(DataError, match="split"):  # the selection is io's (idkit.io.provenance): a data error
        loop_sets(load_measurement_set(dataset), split="train")


def test_plots_draw_and_return_artists(dataset):
    from idkit.io import load_measurement_set
    from idkit.plot.fits import plot_storage_loss, plot_error_landscape, plot_frf_fit, plot_loop_fit

    data = load_measurement_set(dataset)
    iwan = fit_iwan_measurements(data)
    lines = plot_loop_fit(iwan.model, iwan.data.small, iwan.data.large)
    assert len(lines) == len(iwan.data.small) + len(iwan.data.large)
    frfs, _ = transmissibility_sets(data)
    assert len(plot_frf_fit(ELASTOMER, frfs)) == 3  # one model line per mass
    storage, loss, eta = plot_storage_loss(ELASTOMER)
    assert np.all(eta.get_ydata() > 0)
    landscape = maxwell_error_landscape(frfs, k0=ELASTOMER.k0, points=15)
    assert landscape.error.shape == (15, 15) and landscape.feasible.any()
    assert plot_error_landscape(landscape) is not None
    for artist in (lines[0], storage):
        artist.figure.clear()


def test_cli_fit_iwan_valid_range(dataset, tmp_path):
    output = tmp_path / "bounded.json"
    assert main(["fit", "iwan", str(dataset), "-o", str(output), "--valid-range", "-0.05", "0.05"]) == 0
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
        x = _loops(np.array(amplitudes))
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


def test_a_model_invalid_inside_the_data_sets_deflections_is_not_a_success():
    """The spring of TRUTH-like g3 < 0 turns negative at -x0; records reaching beyond fail the check."""
    from types import SimpleNamespace

    from idkit.fit.measurements import _valid_over_the_data

    model = IwanModel(g1=3e3, g2=0.0, g3=-3e7, k=[3e3], fc=[8.0])  # g1 + 3 g3 x^2 < 0 beyond 5.77 mm
    lower, upper = model.valid_deflection_range()

    def record(low, high, isolator="wire_rope"):
        return SimpleNamespace(deflection=np.array([low, 0.0, high]), info=SimpleNamespace(isolator=isolator))

    inside = [record(0.9 * lower, 0.9 * upper)]
    assert _valid_over_the_data(model, inside, "wire_rope") == ()
    beyond = inside + [record(1.1 * lower, 0.0)]  # a drop compressing past the root
    (reason,) = _valid_over_the_data(model, beyond, "wire_rope")
    assert "negative-stiff" in reason and f"{1e3 * 1.1 * lower:.4g}" in reason
    other_isolator = inside + [record(2 * lower, 0.0, isolator="elastomer")]
    assert _valid_over_the_data(model, other_isolator, "wire_rope") == ()


def test_a_model_that_cannot_simulate_the_highest_drop_is_not_a_success():
    """The data set's most severe drop is simulated; a flagged run is a reason, a clean one is not."""
    from types import SimpleNamespace

    from idkit.fit.measurements import _survives_the_largest_drops

    def drop(height, mass=5.0):
        info = SimpleNamespace(drop_height_m=height, top_mass_kg=mass, isolator="wire_rope")
        return SimpleNamespace(kind="drop", info=info)

    softening = IwanModel(g1=3e3, g3=-3e7, k=[3e3], fc=[8.0])  # negative-stiff beyond 5.8 mm
    hardening = IwanModel(g1=3e3, g3=3e7, k=[3e3], fc=[8.0])
    records = [drop(0.01), drop(0.2)]  # 0.2 m compresses far beyond 5.8 mm
    (reason,) = _survives_the_largest_drops(softening, records, "wire_rope")
    assert "highest drop (0.2 m on 5 kg)" in reason and "negative local stiffness" in reason
    assert _survives_the_largest_drops(hardening, records, "wire_rope") == ()
    assert _survives_the_largest_drops(softening, [drop(0.2)], "elastomer") == ()  # another isolator's drops


def test_cli_fit_iwan_order_auto_picks_the_generating_order(dataset, tmp_path, capsys):
    """The loops come from an order-2 rope: the order rule keeps 2 and the table is recorded."""
    output = tmp_path / "auto.json"
    assert main(["fit", "iwan", str(dataset), "--order", "auto", "-o", str(output)]) == 0
    assert "Iwan order table" in capsys.readouterr().out
    document = load_model_document(output)
    assert sum(name.startswith("k_") for name in document["model"]["params"]) == 2
    table = document["provenance"]["order_table"]
    assert [row["order"] for row in table] == [1, 2, 3, 4, 5, 6]
    assert [row["order"] for row in table if row["recommended"]] == [2]


def test_sweeps_without_a_resonance_inside_leave_c_visc_0_and_say_why(monkeypatch):
    """A failed damping identification does not fail the loop fit; the fit says why c_visc is 0."""
    from pathlib import Path

    from idkit.fit import measurements as fit_measurements
    from idkit.io import load_measurement_set

    def no_resonance(model, sweeps, level):
        raise FitError("level 0.12: the measured |H1| peaks at the edge of the sweep (3 Hz)")

    monkeypatch.setattr(fit_measurements, "fit_viscous_damping", no_resonance)
    data = load_measurement_set(Path(__file__).resolve().parents[2] / "data" / "wire_rope")
    fit = fit_iwan_measurements(data, order=2)
    assert fit.damping is None and fit.model.c_visc == 0.0
    assert "peaks at the edge of the sweep" in fit.report()
    assert "peaks at the edge" in fit.provenance_dict()["viscous_damping"]

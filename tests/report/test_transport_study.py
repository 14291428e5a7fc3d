"""The transport-tool study end to end (quick settings) and its tables."""

import json

import numpy as np
import pytest

from idkit.report.transport import compute_transport_study, run_transport_study


def test_quick_transport_study_writes_numbers_and_figures(tmp_path):
    out = tmp_path / "transport"
    study = run_transport_study(out, quick=True, seed=5)
    names = {p.name for p in out.iterdir()}
    assert {"transport_output_psd.png", "transport_rest_shock.png", "transport_rms.csv",
            "transport_tuning.csv", "transport_shock_vs_height.csv", "summary.json"} <= names
    summary = json.loads((out / "summary.json").read_text())
    assert summary["seed"] == 5 and summary["n_realizations"] == 4
    # systems: reference, elastomer, wire rope and the two quick hybrids
    assert list(study.rms.index) == ["reference", "elastomer", "wire rope", "hybrid r_k=0.2", "hybrid r_k=1"]
    # linear systems: output RMS scales with the square root of the input level (1e-6 -> 1e-3: x sqrt(1000))
    for name in ("reference", "elastomer"):
        ratio = study.rms.loc[name].iloc[1] / study.rms.loc[name].iloc[0]
        assert ratio == pytest.approx(np.sqrt(1e3), rel=1e-6)
    with pytest.raises(FileExistsError):
        run_transport_study(out, quick=True)


def test_study_is_reproducible_with_a_seed():
    options = dict(levels=(1e-4,), n_realizations=2, r_k_values=(0.5,), speeds=[0.05, 0.1], heights=[0.01])
    first = compute_transport_study(seed=3, **options)
    second = compute_transport_study(seed=3, **options)
    other = compute_transport_study(seed=4, **options)
    assert first.rms.equals(second.rms)
    assert not first.rms.equals(other.rms)

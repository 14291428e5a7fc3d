"""The drop SRS figure: measured, model and impact spectra in one colour per height."""

import numpy as np

from idkit.plot.equivalent import plot_drop_shock_spectra
from idkit.studies.equivalent import DropShockSpectra


def test_drop_srs_draws_measured_model_and_impact_per_height():
    freq = np.geomspace(1.0, 100.0, 5)
    spectra = DropShockSpectra(isolator="wire_rope", top_mass_kg=4.33, height_m=(0.01, 0.07), freq_hz=freq,
                               acceleration=(freq, 2 * freq), damping_ratio=0.05,
                               model_acceleration=(1.1 * freq, 2.2 * freq), input_acceleration=(9 * freq, 18 * freq))
    ax = plot_drop_shock_spectra(spectra)
    lines = ax.get_lines()
    assert [line.get_linestyle() for line in lines] == ["-", "--", ":"] * 2
    assert len({line.get_color() for line in lines[:3]}) == 1 and lines[0].get_color() != lines[3].get_color()
    np.testing.assert_array_equal(lines[4].get_ydata(), 2.2 * freq)
    legend = [text.get_text() for text in ax.get_legend().get_texts()]
    assert legend == ["h = 1 cm", "h = 7 cm", "measured top", "model top", "impact (rigid mount)"]
    measured_only = DropShockSpectra(isolator="e", top_mass_kg=1.0, height_m=(0.01,), freq_hz=freq,
                                     acceleration=(freq,), damping_ratio=0.05)
    assert [line.get_linestyle() for line in plot_drop_shock_spectra(measured_only).get_lines()] == ["-"]


def test_frf_residuals_shade_the_systematic_bands():
    from idkit.models import GeneralizedMaxwell
    from idkit.observe.white_noise import TransmissibilitySet
    from idkit.plot.equivalent import plot_frf_residuals
    from idkit.studies.residuals import ResidualBand

    model = GeneralizedMaxwell(k0=1.4e4, k=[3.5e3], rate=[46.6])
    freq = np.linspace(1.0, 100.0, 50)
    frf = TransmissibilitySet(1.0, freq, np.full(freq.size, 1.1 + 0j))
    ax = plot_frf_residuals(model, [frf], systematic=[ResidualBand(65.8, 100.0, -1, 0.24)])
    spans = [patch for patch in ax.patches]
    assert len(spans) == 1
    assert spans[0].get_x() == 65.8 and spans[0].get_x() + spans[0].get_width() == 100.0
    assert "systematic residual" in [text.get_text() for text in ax.get_legend().get_texts()]
    assert not plot_frf_residuals(model, [frf]).patches

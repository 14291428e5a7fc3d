"""Complex stiffness / DMA tables: units decide stiffness vs modulus; master curves."""

from __future__ import annotations

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io import (
    ComplexStiffnessTable,
    ShiftFactorTable,
    read_complex_stiffness,
    read_shift_factors,
    write_complex_stiffness,
)


def test_modulus_table_in_mpa(tmp_path):
    path = tmp_path / "dma.csv"
    path.write_text("frequency [Hz],storage [MPa],loss [MPa]\n0.1,8.0,0.5\n1,9.0,0.9\n")
    table = read_complex_stiffness(path)
    assert table.quantity == "modulus" and table.unit == "Pa"
    np.testing.assert_array_equal(table.storage, [8e6, 9e6])
    np.testing.assert_allclose(table.loss_factor, [0.5 / 8, 0.1])
    np.testing.assert_allclose(table.omega, 2 * np.pi * np.array([0.1, 1.0]))
    assert table.complex_value[1] == 9e6 + 0.9e6j


def test_stiffness_table_in_n_per_mm(tmp_path):
    path = tmp_path / "k.csv"
    path.write_text("frequency [Hz],storage [N/mm],loss [N/mm]\n5,12,1.2\n10,13,1.5\n")
    table = read_complex_stiffness(path)
    assert table.quantity == "stiffness" and table.unit == "N/m"
    np.testing.assert_array_equal(table.storage, [12e3, 13e3])


def test_write_read_round_trip(tmp_path):
    rng = np.random.default_rng(3)
    table = ComplexStiffnessTable(freq=np.logspace(-1, 2, 17), storage=rng.uniform(1, 2, 17) * 1e4,
                                  loss=rng.uniform(0, 1, 17) * 1e3, quantity="stiffness",
                                  temperature=np.full(17, 296.15), log_a_t=np.zeros(17))
    back = read_complex_stiffness(write_complex_stiffness(table, tmp_path / "t.csv"))
    for name in ("freq", "storage", "loss", "temperature", "log_a_t"):
        assert np.array_equal(getattr(back, name), getattr(table, name))
    assert back.quantity == "stiffness"
    with pytest.raises(FileExistsError):
        write_complex_stiffness(table, tmp_path / "t.csv")


def test_master_curve_from_isotherms(tmp_path):
    iso = tmp_path / "iso.csv"
    iso.write_text("frequency [Hz],storage [MPa],loss [MPa],temperature [C]\n"
                   "1,10,1,20.2\n10,11,1,20.1\n1,5,1,39.8\n10,6,1,40.0\n")
    shift = tmp_path / "shift.csv"
    shift.write_text("temperature [C],log_aT [-]\n20,0\n40,-2\n")
    factors = read_shift_factors(shift)
    assert factors.reference_temperature == pytest.approx(293.15)
    master = read_complex_stiffness(iso).master_curve(factors)
    np.testing.assert_allclose(master.freq, [0.01, 0.1, 1.0, 10.0])
    np.testing.assert_array_equal(master.storage, [5e6, 6e6, 10e6, 11e6])
    np.testing.assert_array_equal(master.log_a_t, [-2, -2, 0, 0])
    with pytest.raises(DataError, match="within 0.1 K"):
        read_complex_stiffness(iso).master_curve(factors, temperature_tol_k=0.1)


def test_master_curve_needs_temperatures():
    table = ComplexStiffnessTable(freq=[1.0], storage=[1.0], loss=[0.1])
    with pytest.raises(DataError, match="no temperature column"):
        table.master_curve(ShiftFactorTable(temperature=[293.15], log_a_t=[0.0]))


@pytest.mark.parametrize("kwargs", [
    {"quantity": "force"}, {"freq": [1.0, np.inf]}, {"loss": [0.1]}, {"freq": [-1.0, 2.0]},
])
def test_constructor_checks(kwargs):
    base = {"freq": [1.0, 2.0], "storage": [1.0, 2.0], "loss": [0.1, 0.2]}
    with pytest.raises(DataError):
        ComplexStiffnessTable(**{**base, **kwargs})

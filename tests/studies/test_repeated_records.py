"""``idkit report`` refuses a data folder that lists one recording twice (fast: tiny sets, no fit).

A fit record copied into the validation split under a new id and file name (or in other units)
made the held-out check validate the model on its own fit data, and the report said PASS (a
Table A.1 / Table 7.3 set, white noise 0.99 kg repetition 1 copied as repetition 5).
"""

from __future__ import annotations

import shutil

import numpy as np
import pytest

from idkit.cli.main import main
from idkit.errors import DataError
from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set
from idkit.io.discover import find_measurement_sets
from idkit.studies.pipeline import refuse_missing_held_out, refuse_repeated_records


def _loop(ident, isolator, split, seed):
    rng = np.random.default_rng(seed)
    time = np.arange(200) / 50.0
    deflection = 2e-3 * np.sin(2 * np.pi * time / 4.0)
    force = 1e4 * deflection + 0.05 * rng.standard_normal(time.size)
    return QuasiStaticMeasurement(time=time, deflection=np.round(deflection, 7), force=np.round(force, 3),
                                  info=MeasurementInfo(id=ident, isolator=isolator, split=split, repetition=1))


def _folder(tmp_path, units=None):
    for seed, (isolator, code) in enumerate((("wire_rope", "wr"), ("elastomer", "el"))):
        write_measurement_set(tmp_path / isolator, [
            _loop(f"qs_{code}_1", isolator, "fit", 2 * seed),
            _loop(f"qs_{code}_3", isolator, "validation", 2 * seed + 1),
        ], units=units)
    return tmp_path


def test_distinct_records_pass(tmp_path):
    refuse_repeated_records(find_measurement_sets(_folder(tmp_path)))


@pytest.mark.parametrize("units", [None, {"deflection": "mm", "force": "kN"}])
def test_a_fit_record_copied_into_the_validation_split_is_refused(tmp_path, units, capsys):
    folder = _folder(tmp_path / "data", units)
    manifest = (folder / "elastomer" / "manifest.json")
    text = manifest.read_text()
    shutil.copyfile(folder / "elastomer/quasi_static/qs_el_1.csv", folder / "elastomer/quasi_static/qs_el_5.csv")
    entry = ('{"id": "qs_el_5", "kind": "quasi_static", "file": "quasi_static/qs_el_5.csv", '
             '"isolator": "elastomer", "repetition": 5, "split": "validation"}')
    manifest.write_text(text.replace("\n  ]\n}", ",\n" + entry + "\n  ]\n}"))
    with pytest.raises(DataError, match=r"qs_el_5 \(.*qs_el_5\.csv, split validation\) repeats qs_el_1 "
                                        r"\(.*qs_el_1\.csv, split fit\)"):
        refuse_repeated_records(find_measurement_sets(folder))
    assert main(["report", str(folder), "-o", str(tmp_path / "out"), "--quick", "--quiet"]) == 2
    assert "qs_el_5" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_folder_without_records_for_a_validation_is_refused_before_any_fit(tmp_path, capsys):
    """Every held-out wire-rope drop removed from a Table A.1 / 7.3 set: the report fitted both
    isolators (about a minute) and then stopped with 'wire rope: drops (validation split): no
    drop measurements given', naming no file. Now refused on loading, naming each manifest and
    every kind missing."""
    folder = _folder(tmp_path / "data")  # quasi-static loops only: nothing to validate on
    with pytest.raises(DataError) as raised:
        refuse_missing_held_out(find_measurement_sets(folder))
    message = str(raised.value)
    for isolator, kinds in (("wire_rope", ("stepped_sine", "drop")), ("elastomer", ("white_noise", "stepped_sine", "drop"))):
        for kind in kinds:
            assert f"{folder / isolator / 'manifest.json'}: no {kind} record with split 'validation' (the {isolator} set)" \
                in message
    assert main(["report", str(folder), "-o", str(tmp_path / "out"), "--quick", "--quiet"]) == 2
    assert "no drop record with split 'validation' (the wire_rope set)" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()

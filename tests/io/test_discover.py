"""Finding measurements on disk: kind from a header, the sets of a data folder, a lone file's manifest."""

from pathlib import Path

import pytest

from idkit.errors import DataError
from idkit.io.discover import default_data_dir, find_measurement_sets, guess_kind, load_measurements

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.mark.parametrize("header, kind", [
    ("time [s],deflection [m],force [N]", "quasi_static"),
    ("time [s],a_base [m/s^2],a_top_1 [m/s^2]", "drop"),
    ("time [s],x_base [m],x_top [m]", "stepped_sine"),
    ("time [s],v_base [m/s],v_top [m/s]", "white_noise"),
    ("time [s],a_base [m/s^2],a_top [m/s^2]", "white_noise"),
])
def test_guess_kind_from_the_header(tmp_path, header, kind):
    path = tmp_path / "record.csv"
    path.write_text(header + "\n0,0,0\n")
    assert guess_kind(path) == kind


def test_guess_kind_names_the_file_when_it_cannot_tell(tmp_path):
    path = tmp_path / "odd.csv"
    path.write_text("time [s],pressure [Pa]\n0,0\n")
    with pytest.raises(DataError, match="odd.csv.*cannot tell the kind"):
        guess_kind(path)


def test_guess_kind_reads_the_header_of_a_cr_only_file(tmp_path):
    path = tmp_path / "odd.csv"
    path.write_bytes(b"time [s],pressure [Pa]\r0,0\r0.1,1\r")
    # the header alone, not the whole file up to a "\n" that never comes
    with pytest.raises(DataError, match=r"from the header 'time \[s\],pressure \[Pa\]'; expected"):
        guess_kind(path)
    path.write_bytes(b"time [s],deflection [m],force [N]\r0,0,0\r")
    assert guess_kind(path) == "quasi_static"


def test_bundled_data_sets_and_a_listed_file():
    assert default_data_dir().resolve() == DATA.resolve() or (default_data_dir() / "README.md").exists()
    sets = find_measurement_sets(DATA)
    assert {"wire_rope", "elastomer"} <= set(sets)
    record = next((DATA / "elastomer" / "white_noise").iterdir())
    title, (measurement,) = load_measurements(record)
    assert title == record.name and measurement.kind == "white_noise" and measurement.info.top_mass_kg > 0


def test_missing_and_empty_folders_are_refused(tmp_path):
    with pytest.raises(DataError, match=r"^data_dir: found '.*nowhere' \(not found\), expected a data folder"):
        find_measurement_sets(tmp_path / "nowhere")
    (tmp_path / "file.csv").write_text("time [s]\n")
    with pytest.raises(DataError, match=r"^data_dir: found '.*file.csv' \(not a folder\), expected a data folder"):
        find_measurement_sets(tmp_path / "file.csv")
    with pytest.raises(DataError, match="no manifest.json"):
        find_measurement_sets(tmp_path)
    with pytest.raises(DataError, match=r"^path: found '.*nowhere' \(not found\), expected a measurement-set folder"):
        load_measurements(tmp_path / "nowhere")

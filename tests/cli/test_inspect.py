"""``idkit inspect`` and ``idkit data generate`` on generated data and on a broken folder."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from idkit.cli.main import main

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture(scope="module")
def quick_data(tmp_path_factory):
    folder = tmp_path_factory.mktemp("quick") / "data"
    assert main(["data", "generate", "-o", str(folder), "--quick", "--quiet",
                 "--sets", "elastomer"]) == 0
    return folder


def test_inspect_prints_summary_and_saves_plots_atomically(quick_data, tmp_path, capsys):
    plots = tmp_path / "plots"
    assert main(["inspect", str(quick_data / "elastomer"), "--plots", str(plots)]) == 0
    out = capsys.readouterr().out
    for text in ("22 measurements", "quasi_static", "white_noise", "stepped_sine", "drop",
                 "fs 2000 Hz", "top mass 0.99-6.4 kg", "height 2-9 cm", "split: ",
                 "[non_flat_input]"):
        assert text in out, text
    names = sorted(p.name for p in plots.iterdir())
    assert names == ["overview_drop.png", "overview_quasi_static.png",
                     "overview_stepped_sine.png", "overview_white_noise.png"]
    assert main(["inspect", str(quick_data / "elastomer"), "--plots", str(plots)]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main(["inspect", str(quick_data / "elastomer"), "--plots", str(plots), "--force"]) == 0


def test_inspect_single_file_uses_its_manifest_or_its_header(quick_data, tmp_path, capsys):
    wn = next((quick_data / "elastomer" / "white_noise").iterdir())
    assert main(["inspect", str(wn)]) == 0
    out = capsys.readouterr().out
    assert "1 measurements: 1 white_noise" in out and "top mass" in out
    lone = tmp_path / "lone.csv.gz"
    shutil.copy(next((quick_data / "elastomer" / "drop").iterdir()), lone)
    assert main(["inspect", str(lone)]) == 0
    assert "1 drop" in capsys.readouterr().out


def test_inspect_flags_a_clipped_signal(quick_data, tmp_path, capsys):
    source = next((quick_data / "elastomer" / "quasi_static").iterdir())
    import gzip

    lines = gzip.decompress(source.read_bytes()).decode().splitlines()
    header, rows = lines[0], [line.split(",") for line in lines[1:]]
    column = header.split(",").index("force [N]")
    peak = max(float(r[column]) for r in rows)
    clip = f"{0.8 * peak:.3f}"
    for row in rows:
        if float(row[column]) > 0.8 * peak:
            row[column] = clip
    target = tmp_path / "clipped.csv"
    target.write_text("\n".join([header] + [",".join(r) for r in rows]) + "\n")
    assert main(["inspect", str(target)]) == 0
    assert "[clipped]" in capsys.readouterr().out


def test_inspect_broken_folder_exits_2_with_a_clear_message(quick_data, tmp_path, capsys):
    broken = tmp_path / "broken"
    shutil.copytree(quick_data / "elastomer", broken)
    manifest = json.loads((broken / "manifest.json").read_text())
    missing = manifest["measurements"][0]["file"]
    (broken / missing).unlink()
    assert main(["inspect", str(broken)]) == 2
    err = capsys.readouterr().err
    assert "idkit: error:" in err and missing in err
    assert main(["inspect", str(tmp_path / "nowhere")]) == 2
    assert "nowhere' (not found), expected a measurement-set folder" in capsys.readouterr().err
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main(["inspect", str(empty)]) == 2
    assert "no manifest.json" in capsys.readouterr().err


def test_data_generate_refuses_to_overwrite(quick_data, capsys):
    assert main(["data", "generate", "-o", str(quick_data), "--quick", "--quiet",
                 "--sets", "elastomer"]) == 2
    assert "use --force" in capsys.readouterr().err


def test_inspect_bundled_hybrid_set(capsys):
    if not (DATA / "hybrid" / "manifest.json").exists():
        pytest.skip("bundled data/ not generated")
    assert main(["inspect", str(DATA / "hybrid")]) == 0
    out = capsys.readouterr().out
    assert "178 measurements" in out and "hybrid" in out and "[non_flat_input]" in out


def test_a_lone_mat_file_is_refused_with_what_it_needs(tmp_path):
    """A .mat holds arrays, not the kind, units and masses: inspect says so instead of a UTF-8 error."""
    import numpy as np
    import scipy.io

    from tests.cli.hostile import check, run_main

    path = tmp_path / "record.mat"
    scipy.io.savemat(path, {"x": np.arange(10.0), "f": np.arange(10.0)})
    outcome = run_main(["inspect", path], inputs=[path])
    check(outcome, "error", ["record.mat", "lone .mat", "manifest"], case="inspect a lone .mat")

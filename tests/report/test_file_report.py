"""``idkit report FILE``: one data file to a report (a DMA table, a loop record, any other record)."""

import json
import shutil
from html.parser import HTMLParser
from pathlib import Path

import numpy as np

from idkit.io.complex_stiffness import write_complex_stiffness
from tests.cli.hostile import check, run_main
from tests.cli.test_dma_cli import _isotherms

DATA = Path(__file__).resolve().parents[2] / "data"


class _Images(HTMLParser):
    def __init__(self):
        super().__init__()
        self.images, self.captions = [], 0

    def handle_starttag(self, tag, attrs):
        if tag == "img":
            self.images.append(dict(attrs))
        if tag == "figcaption":
            self.captions += 1


def _parse(path):
    parser = _Images()
    parser.feed(path.read_text())
    return parser


def test_report_of_a_dma_table(tmp_path):
    table = write_complex_stiffness(_isotherms(np.arange(260.0, 321.0, 10.0)), tmp_path / "dma.csv")
    out = tmp_path / "report"
    outcome = run_main(["report", table, "-o", out], inputs=[table])
    assert outcome.status in (0, 1), outcome.stderr
    provenance = json.loads((out / "provenance.json").read_text())
    assert provenance["kind"] == "complex_stiffness" and provenance["input"]["sha256"]
    assert (outcome.status == 0) == provenance["success"]
    assert json.loads((out / "model.json").read_text())["model"]["units"]["k0"] == "Pa"
    assert (out / "figures" / "shift_factors.png").exists() and (out / "tables" / "master_curve.csv").exists()
    page = _parse(out / "report.html")
    assert len(page.images) == 2 and page.captions == 2
    assert all(image.get("alt") for image in page.images)


def test_report_of_a_loop_record(tmp_path):
    source = DATA / "wire_rope" / "quasi_static" / "qs_wr_large_1.csv.gz"
    lone = tmp_path / source.name
    shutil.copyfile(source, lone)
    out = tmp_path / "report"
    outcome = run_main(["report", lone, "-o", out], inputs=[lone])
    # the bundled rope's slip changes with the deflection: the plain Iwan stays more than 2
    # points above the record's noise floor, so the family rule fits the slip-modulated one
    check(outcome, "ok")
    assert "quasi_static fit" in outcome.stdout
    assert json.loads((out / "model.json").read_text())["model"]["kind"] == "iwan_modulated"
    assert (out / "figures" / "loops.png").exists()


def test_folder_only_options_are_refused_for_a_file(tmp_path):
    source = DATA / "wire_rope" / "quasi_static" / "qs_wr_large_1.csv.gz"
    outcome = run_main(["report", source, "-o", tmp_path / "r", "--quick"], inputs=[source],
                       must_not_exist=[tmp_path / "r"])
    check(outcome, "error", ["--quick", "single file"], case="report-file-quick")

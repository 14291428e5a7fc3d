"""Hostile outputs through the real ``idkit`` entry point: nothing destroys an input or a good output.

Each case runs :func:`idkit.cli.main.main` through the corpus harness (:mod:`cli.hostile`),
which hashes every input before and after, looks for outputs a refusal must not create and
for staging leftovers, and asserts the exit status and the words of the message.

Categories: an output overlapping an input (equal, inside, containing, through a symlink);
output locations that cannot work (missing folder, below a regular file, a folder where a
file is expected, read-only, full disk); existing outputs (refused without ``--force``,
untouched); a write failing half way; and kill tests of ``study elastomer --force`` and
``report --force`` at the folder swap (``SIGTERM`` and ``SIGKILL``, paused there by the
test hook :data:`idkit.atomic.SWAP_PAUSE_VARIABLE`).

Running as root: permission bits do not stop root, so the ``chmod`` cases are skipped when
``os.access`` still reports the folder writable; the ``/sys`` case (a read-only mount even
for root in most containers) stands in, and is skipped where ``/sys`` is writable.
"""

from __future__ import annotations

import errno
import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from idkit.io import MeasurementInfo, QuasiStaticMeasurement, write_measurement_set
from idkit.io.complex_stiffness import write_complex_stiffness
from tests.cli.hostile import check, run_main
from tests.cli.test_dma_cli import _isotherms


@pytest.fixture(scope="module")
def measurement_set(tmp_path_factory) -> Path:
    """A tiny valid set (two wire-rope loops), inside a folder that holds nothing else."""
    folder = tmp_path_factory.mktemp("inputs") / "set"
    x = 5e-3 * np.sin(np.linspace(0, 4 * np.pi, 400))
    measurements = [QuasiStaticMeasurement(time=np.arange(x.size) / 50.0, deflection=x, force=3e3 * x + 0.1 * k,
                                           info=MeasurementInfo(id=f"qs_{k}", isolator="wire_rope", repetition=k,
                                                                split="fit", sample_rate_hz=50.0))
                    for k in (1, 2)]
    write_measurement_set(folder, measurements, name="hostile outputs")
    return folder


@pytest.fixture
def model_file(tmp_path) -> Path:
    path = tmp_path / "model.json"
    check(run_main(["library", "system_b1_low", "-o", path]), "ok", case="library -o new file")
    return path


@pytest.fixture
def regular_file(tmp_path) -> Path:
    path = tmp_path / "plain.txt"
    path.write_text("not a folder\n")
    return path


def _old_output(path: Path) -> dict[str, str]:
    """An existing output folder with known content; returns its manifest."""
    (path / "models").mkdir(parents=True)
    (path / "summary.json").write_text('{"old": true}\n')
    (path / "models" / "a.json").write_text("{}\n")
    return _manifest(path)


def _manifest(path: Path) -> dict[str, str]:
    return {p.relative_to(path).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(path.rglob("*")) if p.is_file()}


# --- an output overlapping an input -------------------------------------------------------------

def test_report_output_equal_to_its_input_is_refused(measurement_set):
    outcome = run_main(["report", measurement_set.parent, "-o", measurement_set.parent, "--force", "--quiet"],
                       inputs=[measurement_set.parent])
    check(outcome, "error", ["is the input", str(measurement_set.parent)], case="report -o = input --force")


def test_report_output_inside_its_input_is_refused(measurement_set):
    target = measurement_set.parent / "report"
    outcome = run_main(["report", measurement_set.parent, "-o", target, "--force", "--quiet"],
                       inputs=[measurement_set.parent], must_not_exist=[target])
    check(outcome, "error", ["lies inside the input", str(target)], case="report -o inside input")


def test_report_output_containing_its_input_is_refused(measurement_set):
    outcome = run_main(["report", measurement_set, "-o", measurement_set.parent, "--force", "--quiet"],
                       inputs=[measurement_set.parent])
    check(outcome, "error", ["contains the input", str(measurement_set)], case="report -o contains input")


def test_report_output_through_a_symlink_to_its_input_is_refused(measurement_set, tmp_path):
    link = tmp_path / "link"
    link.symlink_to(measurement_set.parent, target_is_directory=True)
    outcome = run_main(["report", measurement_set.parent, "-o", link, "--force", "--quiet"],
                       inputs=[measurement_set.parent])
    check(outcome, "error", ["is the input", str(link)], case="report -o symlink to input")
    assert link.is_symlink()


@pytest.mark.parametrize("where", ["set", "set/model.json"])
def test_fit_model_file_inside_or_equal_to_the_data_set_is_refused(measurement_set, where):
    target = measurement_set.parent / where
    outcome = run_main(["fit", "iwan", measurement_set, "-o", target], inputs=[measurement_set],
                       must_not_exist=[] if where == "set" else [target], watch=[measurement_set])
    check(outcome, "error", [str(target)], case=f"fit -o {where}")


@pytest.mark.parametrize("plots", ["set", "set/plots"])
def test_fit_plots_overlapping_the_data_set_are_refused(measurement_set, tmp_path, plots):
    model = tmp_path / "m.json"
    outcome = run_main(["fit", "iwan", measurement_set, "-o", model, "--plots", measurement_set.parent / plots],
                       inputs=[measurement_set], must_not_exist=[model])
    check(outcome, "error", ["--plots", "input"], case=f"fit --plots {plots}")


def test_inspect_plots_inside_the_inspected_set_are_refused(measurement_set):
    target = measurement_set / "plots"
    outcome = run_main(["inspect", measurement_set, "--plots", target], inputs=[measurement_set],
                       must_not_exist=[target])
    check(outcome, "error", ["--plots", "lies inside the input"], case="inspect --plots inside input")


def test_simulate_output_onto_its_model_file_is_refused(model_file, tmp_path):
    link = tmp_path / "link.json"
    link.symlink_to(model_file)
    for target in (model_file, link):
        outcome = run_main(["simulate", "harmonic", target, "--freq", "10", "--amplitude", "1e-4", "-o", target,
                            "--quiet"], inputs=[model_file])
        check(outcome, "error", ["is the input", str(target)], case="simulate -o = model file")


def test_transport_study_output_containing_its_model_files_is_refused(model_file):
    outcome = run_main(["study", "transport", "--wire-rope", model_file, "--elastomer", model_file,
                        "-o", model_file.parent, "--force", "--quiet"], inputs=[model_file])
    check(outcome, "error", ["contains the input", str(model_file)], case="study transport -o contains input")


def test_transport_study_refuses_a_data_folder_it_would_not_read(model_file, tmp_path):
    """With both model files the parts are given: a --data-dir (even a missing one) was silently ignored."""
    output = tmp_path / "study"
    outcome = run_main(["study", "transport", "--wire-rope", model_file, "--elastomer", model_file,
                        "--data-dir", tmp_path / "missing", "-o", output, "--quick", "--quiet"],
                       inputs=[model_file], must_not_exist=[output])
    check(outcome, "error", ["--data-dir", "not used", "--wire-rope"], case="study transport --data-dir unused")


def test_study_never_replaces_the_working_folder_or_its_parents(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    (work / "precious.txt").write_text("keep me\n")
    monkeypatch.chdir(work)
    for target in (work, tmp_path, "."):
        outcome = run_main(["study", "elastomer", "-o", target, "--force", "--quick", "--quiet"], inputs=[work])
        check(outcome, "error", ["working folder"], case="study -o cwd or a parent --force")


# --- output locations that cannot work -----------------------------------------------------------

def test_simulate_into_a_missing_folder_or_below_a_file_or_onto_a_folder(model_file, regular_file, tmp_path):
    folder = tmp_path / "folder"
    folder.mkdir()
    cases = [(tmp_path / "missing" / "out.csv", "does not exist"),
             (regular_file / "out.csv", "which is a file"),
             (folder, "is a folder")]
    for target, words in cases:
        outcome = run_main(["simulate", "drop", model_file, "--velocity", "0.5", "-o", target],
                           inputs=[model_file, regular_file], must_not_exist=[] if target == folder else [target])
        check(outcome, "error", [words, str(target)], case=f"simulate -o {words}")


def test_library_into_a_missing_folder_or_below_a_file(regular_file, tmp_path):
    for target, words in ((tmp_path / "missing" / "m.json", "does not exist"),
                          (regular_file / "m.json", "which is a file")):
        outcome = run_main(["library", "system_b1_low", "-o", target], inputs=[regular_file],
                           must_not_exist=[target])
        check(outcome, "error", [words], case=f"library -o {words}")


@pytest.mark.parametrize("command", [["study", "wire-rope", "--quick"],
                                     ["data", "generate", "--quick"], ["report", "{set}", "--quick"]])
def test_folder_outputs_below_a_regular_file_are_refused(command, regular_file, measurement_set):
    target = regular_file / "out"
    argv = [str(measurement_set.parent) if word == "{set}" else word for word in command]
    outcome = run_main([*argv, "-o", target, "--quiet"], inputs=[regular_file, measurement_set])
    check(outcome, "error", ["which is a file", str(regular_file)], case=f"{command[0]} -o below a file")


def test_study_will_not_replace_a_regular_file_by_a_folder(regular_file):
    outcome = run_main(["study", "elastomer", "-o", regular_file, "--force", "--quick", "--quiet"], inputs=[regular_file])
    check(outcome, "error", ["not a folder", str(regular_file)], case="study -o regular file --force")


def test_fit_plots_below_a_file_stop_before_the_model_file_is_written(measurement_set, regular_file, tmp_path):
    model = tmp_path / "m.json"
    outcome = run_main(["fit", "iwan", measurement_set, "-o", model, "--plots", regular_file / "plots"],
                       inputs=[measurement_set, regular_file], must_not_exist=[model])
    check(outcome, "error", ["--plots", "which is a file"], case="fit --plots below a file")


@pytest.mark.parametrize("command", ["iwan", "boucwen"])
def test_fit_plots_onto_the_model_file_stop_before_fitting(measurement_set, tmp_path, command):
    """Found only after the fit before: the model file written, then '[Errno 17] File exists', status 2."""
    model = tmp_path / "m.json"
    outcome = run_main(["fit", command, measurement_set, "-o", model, "--plots", tmp_path / "." / "m.json"],
                       inputs=[measurement_set], must_not_exist=[model], timeout_s=30)
    check(outcome, "error", ["--plots", "is the model file -o"], case="fit --plots = -o")


def _read_only_folder(tmp_path) -> Path:
    folder = tmp_path / "read-only"
    folder.mkdir()
    folder.chmod(0o500)
    if os.access(folder, os.W_OK):  # root: permission bits are not enforced
        folder.chmod(0o700)
        pytest.skip("running as root: chmod does not make a folder read-only (see the /sys case)")
    return folder


def test_fit_plots_into_a_read_only_folder_write_nothing(measurement_set, tmp_path):
    folder = _read_only_folder(tmp_path)
    model = tmp_path / "m.json"
    try:
        outcome = run_main(["fit", "iwan", measurement_set, "-o", model, "--plots", folder / "plots"],
                           inputs=[measurement_set], must_not_exist=[model])
    finally:
        folder.chmod(0o700)
    check(outcome, "error", ["--plots", "cannot write", str(folder)], case="fit --plots read-only folder")


def test_report_and_simulate_into_a_read_only_folder(measurement_set, model_file, tmp_path):
    folder = _read_only_folder(tmp_path)
    try:
        outcomes = [run_main(["report", measurement_set.parent, "-o", folder / "report", "--quiet"],
                             inputs=[measurement_set]),
                    run_main(["simulate", "drop", model_file, "--velocity", "0.5", "-o", folder / "out.csv"],
                             inputs=[model_file])]
    finally:
        folder.chmod(0o700)
    for outcome in outcomes:
        check(outcome, "error", ["cannot write", str(folder)], case="read-only output folder")


def test_fit_plots_on_a_read_only_mount_write_nothing(measurement_set, tmp_path):
    try:
        probe = Path("/sys") / f".idkit-probe-{os.getpid()}"
        probe.mkdir()
        probe.rmdir()
        pytest.skip("/sys is writable here")
    except OSError:
        pass
    if not Path("/sys").is_dir():
        pytest.skip("no /sys")
    model = tmp_path / "m.json"
    outcome = run_main(["fit", "iwan", measurement_set, "-o", model, "--plots", "/sys/idkit-plots"],
                       inputs=[measurement_set], must_not_exist=[model, "/sys/idkit-plots"])
    check(outcome, "error", ["--plots", "cannot write", "/sys"], case="fit --plots read-only mount")


def test_a_nearly_full_disk_is_refused_before_work(model_file, tmp_path, monkeypatch):
    import shutil

    real = shutil.disk_usage
    monkeypatch.setattr(shutil, "disk_usage", lambda path: real(path)._replace(free=2**20))
    target = tmp_path / "out.csv"
    outcome = run_main(["simulate", "drop", model_file, "--velocity", "0.5", "-o", target], inputs=[model_file],
                       must_not_exist=[target])
    check(outcome, "error", ["MiB free", str(target)], case="simulate -o full disk (checked)")


def test_a_disk_filling_up_during_the_write_leaves_nothing(model_file, tmp_path, monkeypatch):
    def full(descriptor):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr("idkit.atomic.os.fsync", full)
    target = tmp_path / "out.csv"
    outcome = run_main(["simulate", "drop", model_file, "--velocity", "0.5", "-o", target], inputs=[model_file],
                       must_not_exist=[target], watch=[tmp_path])
    check(outcome, "error", ["cannot write", str(target), "no space"], case="simulate -o disk full while writing")


def test_an_unforeseen_os_error_is_an_idkit_error_naming_its_path(tmp_path, monkeypatch):
    """Last resort in ``main``: an ``OSError`` no check foresaw still ends as exit 2 naming the path."""
    def denied(name):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), "/somewhere/locked.json")

    monkeypatch.setattr("idkit.models.library.get", denied)
    outcome = run_main(["library", "system_b1_low", "-o", tmp_path / "m.json"], must_not_exist=[tmp_path / "m.json"])
    check(outcome, "error", ["/somewhere/locked.json", "permission denied"], case="OSError escaping a command")


# --- existing outputs ----------------------------------------------------------------------------

@pytest.mark.parametrize("command", [["study", "elastomer", "--quick"], ["report", "{set}"]])
def test_existing_output_folder_without_force_is_refused_untouched(command, measurement_set, tmp_path):
    target = tmp_path / "out"
    _old_output(target)
    argv = [str(measurement_set.parent) if word == "{set}" else word for word in command]
    outcome = run_main([*argv, "-o", target, "--quiet"], inputs=[target, measurement_set], watch=[tmp_path])
    check(outcome, "error", ["exists", "--force", str(target)], case=f"{command[0]} existing output, no --force")


def test_existing_files_are_never_overwritten(measurement_set, model_file, tmp_path):
    existing = tmp_path / "old.csv"
    existing.write_text("old\n")
    cases = [["simulate", "drop", model_file, "--velocity", "0.5", "-o", existing],
             ["library", "system_b1_low", "-o", existing],
             ["fit", "iwan", measurement_set, "-o", existing]]
    for argv in cases:
        outcome = run_main(argv, inputs=[existing, model_file, measurement_set], watch=[tmp_path])
        check(outcome, "error", ["exists", str(existing)], case=f"{argv[0]} -o existing file")


def test_simulate_writes_a_new_table_atomically(model_file, tmp_path):
    target = tmp_path / "out.json"
    outcome = run_main(["simulate", "drop", model_file, "--velocity", "0.5", "-o", target], inputs=[model_file],
                       watch=[tmp_path])
    check(outcome, "ok", case="simulate -o new file")
    assert target.read_text().startswith("[")


# --- kill tests at the folder swap ---------------------------------------------------------------

def _start_paused(argv, point: str, flag: Path) -> subprocess.Popen:
    """Start ``idkit argv`` in a subprocess that pauses at ``point`` of the folder swap."""
    env = dict(os.environ, IDKIT_TEST_SWAP_PAUSE=f"{point}:{flag}", MPLBACKEND="Agg")
    process = subprocess.Popen([sys.executable, "-m", "idkit", *map(str, argv)], cwd=flag.parent, env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 900
    while not flag.exists():
        if process.poll() is not None or time.monotonic() > deadline:
            process.kill()
            _, err = process.communicate()
            pytest.fail(f"never reached the swap ({point}): {err[-2000:]}")
        time.sleep(0.05)
    return process


def _staged(target: Path) -> Path:
    (staging,) = target.parent.glob(f".{target.name}.partial.*")
    return staging


def _kill_at_swap(argv, target: Path, point: str, signum: int, tmp_path: Path):
    """Run ``argv`` (writing ``target``) up to ``point`` of the swap, deliver ``signum``, return
    (exit status, stderr, old manifest, new manifest)."""
    old = _old_output(target)
    flag = tmp_path / "paused"
    process = _start_paused(argv, point, flag)
    try:
        new = _manifest(target if point == "after" else _staged(target))
        last = {"study": "summary.json", "report": "report.html"}[str(argv[0])]  # written last: complete
        assert new != old and last in new
    except BaseException:
        process.kill()
        process.communicate()
        raise
    process.send_signal(signum)
    _, err = process.communicate(timeout=120)
    return process.returncode, err, old, new


def _leftovers(target: Path) -> list[str]:
    return [p.name for p in target.parent.iterdir() if p.name.startswith(f".{target.name}.")]


@pytest.mark.parametrize("point", ["between"])
def test_study_sigterm_at_the_swap_keeps_the_old_output(tmp_path, point):
    target = tmp_path / "study"
    status, err, old, _ = _kill_at_swap(["study", "elastomer", "-o", target, "--force", "--quick", "--quiet"], target, point,
                                        signal.SIGTERM, tmp_path)
    assert status == 128 + signal.SIGTERM and "terminated" in err and "Traceback" not in err
    assert _manifest(target) == old
    assert _leftovers(target) == []


def test_study_sigkill_between_the_renames_is_recovered_by_the_next_run(tmp_path):
    target = tmp_path / "study"
    status, _, old, _ = _kill_at_swap(["study", "elastomer", "-o", target, "--force", "--quick", "--quiet"], target, "between",
                                      signal.SIGKILL, tmp_path)
    assert status == -signal.SIGKILL
    assert not target.exists()  # the one instant the name points nowhere: between the two renames
    assert any(".old." in name for name in _leftovers(target))
    outcome = run_main(["study", "elastomer", "-o", target, "--quick", "--quiet"], inputs=[], watch=[tmp_path])
    check(outcome, "error", ["exists", "--force"], case="study after SIGKILL at the swap (recovered)")
    assert _manifest(target) == old


@pytest.mark.slow
@pytest.mark.parametrize("point", ["before", "after"])
def test_study_sigkill_before_or_after_the_renames_leaves_old_or_new(tmp_path, point):
    target = tmp_path / "study"
    status, _, old, new = _kill_at_swap(["study", "elastomer", "-o", target, "--force", "--quick", "--quiet"], target, point,
                                        signal.SIGKILL, tmp_path)
    assert status == -signal.SIGKILL
    assert _manifest(target) == (old if point == "before" else new)
    outcome = run_main(["study", "elastomer", "-o", target, "--quick", "--quiet"], watch=[tmp_path])  # cleans the leftovers
    check(outcome, "error", ["exists"], case=f"study after SIGKILL {point} the swap")
    assert _manifest(target) == (old if point == "before" else new)


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGTERM])  # SIGKILL at the swap: the study tests above (same writer)
def test_report_killed_at_the_swap_keeps_old_or_complete_new(tmp_path, signum):
    # every report writes through the same swap: a one-file report (a DMA table, three isotherms)
    # reaches it fastest
    data = write_complex_stiffness(_isotherms(np.arange(280.0, 301.0, 10.0)), tmp_path / "dma.csv")
    target = tmp_path / "report"
    status, _, old, _ = _kill_at_swap(["report", data, "-o", target, "--force", "--quiet"], target,
                                        "between", signum, tmp_path)
    assert status == (128 + signal.SIGTERM if signum == signal.SIGTERM else -signal.SIGKILL)
    if signum == signal.SIGKILL:
        assert not target.exists()
        outcome = run_main(["report", data, "-o", target, "--quiet"], watch=[tmp_path])
        check(outcome, "error", ["exists"], case="report after SIGKILL at the swap (recovered)")
    assert _manifest(target) == old  # the new one was never in place
    assert _leftovers(target) == []

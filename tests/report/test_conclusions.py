"""The report's sentences follow the numbers they are read from (small synthetic results)."""

import numpy as np
import pandas as pd

from idkit.report.conclusions import (
    drop_model_sentence,
    fit_sentence,
    parameters_sentence,
    rest_shock_ends,
    transport_conclusions,
    validation_sentence,
)
from idkit.studies.transport import TransportStudy
from idkit.validate import ValidationResult


def _result(summary, thresholds, **extra):
    return ValidationResult(name="check", metrics=pd.DataFrame({"x": [1, 2, 3]}), summary=summary,
                            thresholds=thresholds, **extra)


def test_a_failing_validation_names_the_metric_over_its_limit_and_what_holds():
    verdict, text = validation_sentence("rope drops", _result({"peak error": 0.31, "phase error": 0.02},
                                                              {"peak error": 0.2, "phase error": 0.1}))
    assert verdict == "FAIL"
    assert "fails on peak error 0.31 > 0.2" in text and "within the limits: phase error 0.02 <= 0.1" in text
    assert "(3 points)" in text


def test_an_inconclusive_validation_gives_its_reasons():
    verdict, text = validation_sentence("sweeps", _result({"a": np.nan, "b": 0.01}, {"a": 1.0, "b": 0.1},
                                                          inconclusive=("5 of 9 points never settled",)))
    assert verdict == "INCONCLUSIVE"
    assert "inconclusive because 5 of 9 points never settled; a could not be computed" in text
    assert "b 0.01 <= 0.1" in text


def test_a_passing_validation_says_what_it_predicts_well_and_what_it_cannot_see():
    verdict, text = validation_sentence("hybrid", _result({"a": 0.05}, {"a": 0.1}, cannot_see=("upper x2",)),
                                        quick_note="quick")
    assert verdict == "PASS" and "predicts well: a 0.05 <= 0.1" in text
    assert "cannot tell these wrong components apart: upper x2" in text and text.endswith("(quick).")


def test_notes_follow_the_verdict_without_changing_it():
    notes = ("level 0.002 (largest deflection amplitude 0.007 mm) lies below the loops",)
    verdict, text = validation_sentence("rope sweeps", _result({"a": 0.3}, {"a": 0.1}, notes=notes))
    assert verdict == "FAIL"
    assert text.endswith("fails on a 0.3 > 0.1. Note: level 0.002 (largest deflection amplitude 0.007 mm) lies "
                         "below the loops.")


def test_a_record_beyond_its_own_limit_is_named_in_the_sentence():
    line = "drop-9: peak compression error +0.467 lies 0.400 outside 0 to the other drops' median +0.067 (limit 0.25)"
    verdict, text = validation_sentence("rope drops", _result({"a": 0.07, "records_beyond_limit": 1},
                                                              {"a": 0.25, "records_beyond_limit": 0},
                                                              record_failures=(line,)))
    assert verdict == "FAIL"
    assert f"fails on records_beyond_limit 1 > 0 ({line}); within the limits: a 0.07 <= 0.25" in text


def _study(rms, heights, shock_height, speeds, shock_velocity):
    return TransportStudy(tuning=pd.DataFrame(), rms=rms, psd=(), seed=0, n_realizations=1, flagged_runs=0,
                          shock_height=pd.DataFrame(shock_height, index=pd.Index(heights)),
                          shock_velocity=pd.DataFrame(shock_velocity, index=pd.Index(speeds)))


def test_transport_sentences_rank_the_systems_from_the_numbers():
    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.30, 0.10, 0.20], "0.001 [(m/s^2)^2/Hz]": [3.0, 4.0, 6.0]},
                       index=["reference", "elastomer", "wire rope"])
    heights = [0.01, 0.03, 0.05]
    study = _study(rms, heights, {"reference": [10.0, 20.0, 30.0], "elastomer": [5.0, 12.0, 40.0],
                                  "wire rope": [8.0, 9.0, np.nan]},
                   [0.1, 0.2, 0.3], {"reference": [1.0, 2.0, 3.0], "elastomer": [1.0, 2.0, 3.0],
                                     "wire rope": [1.0, 2.0, np.nan]})
    sentences = transport_conclusions(study, heights=(0.02, 0.05))
    assert sentences[0].startswith("floor PSD 1e-06 [(m/s^2)^2/Hz], RMS top acceleration: elastomer protects "
                                   "the payload best (0.1 m/s^2; next wire rope 0.2 m/s^2, 2 times as much; "
                                   "the viscous reference 0.3 m/s^2)")
    assert "0.001 [(m/s^2)^2/Hz], RMS top acceleration: reference protects" in sentences[1]
    # 2 cm: midway, elastomer 8.5, wire rope 8.5 -> 8.5 both; reference 15
    assert "drop height 2 cm" in sentences[2] and "reference 15 m/s^2" in sentences[2]
    # 5 cm: the wire rope has no value there (model invalid), the reference wins
    assert sentences[3].startswith("drop height 5 cm, rest shock: reference protects the payload best (30 m/s^2")
    assert "no value (model invalid) for wire rope" in sentences[3]
    assert sentences[4].startswith("wire rope: the rest-shock curve stops at an impact speed of 0.2 m/s")


def test_a_ranked_system_whose_runs_did_not_settle_is_flagged():
    import dataclasses

    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.30, 0.10, 0.20]}, index=["reference", "elastomer", "wire rope"])
    study = _study(rms, [0.01, 0.03], {"reference": [1.0, 2.0], "elastomer": [1.0, 2.0], "wire rope": [1.0, 2.0]},
                   [0.1, 0.2], {"reference": [1.0, 2.0], "elastomer": [1.0, 2.0], "wire rope": [1.0, 2.0]})
    settled = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.0, 0.0, 0.0]}, index=rms.index)
    assert "Not settled" not in transport_conclusions(dataclasses.replace(study, settling=settled))[0]
    ringing = settled.copy()
    ringing.loc["wire rope"] = 0.26  # the second best: named; a third-ranked one would not be
    sentence = transport_conclusions(dataclasses.replace(study, settling=ringing))[0]
    assert sentence.endswith("Not settled, so uncertain by about that fraction: wire rope (settling error 0.26).")


def test_a_drop_height_on_a_sweep_point_takes_that_points_level_in_words_and_table():
    # the study's sweep, np.linspace(0.005, 0.15, 30), puts 5 cm at 0.04999999999999999: the
    # hybrid's last valid point is 5 cm itself, so its level there is computed, and it is the lowest
    heights = [0.03, 0.04, 0.04999999999999999, 0.06, 0.07]
    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.3, 0.2]}, index=["reference", "hybrid"])
    study = _study(rms, heights, {"reference": [20.0, 25.0, 28.0, 31.0, 34.0],
                                  "hybrid": [12.0, 15.0, 17.6, np.nan, np.nan]},
                   [0.1, 0.2], {"reference": [1.0, 2.0], "hybrid": [1.0, 2.0]})
    sentence = transport_conclusions(study, heights=(0.05,))[1]
    assert sentence.startswith("drop height 5 cm, rest shock: hybrid protects the payload best (17.6 m/s^2")
    assert "model invalid" not in sentence
    assert study.summary_table(heights=(0.05,)).loc["hybrid", "rest shock at h = 5 cm [m/s^2]"] == 17.6
    # between the last valid point and the first invalid one there is no value
    assert np.isnan(study.rest_shock_at(0.055)["hybrid"]) and np.isclose(study.rest_shock_at(0.055)["reference"], 29.5)


def test_a_curve_that_stops_only_versus_drop_height_is_named_too():
    # the speed sweep ends (1 m/s) before the height sweep (15 cm is 1.7 m/s): a hybrid valid
    # over every speed still stops versus height, and its blank drop heights need a reason
    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.3, 0.2, 0.1]}, index=["reference", "hybrid", "wire rope"])
    study = _study(rms, [0.05, 0.10, 0.15], {"reference": [28.0, 40.0, 49.0], "hybrid": [18.0, np.nan, np.nan],
                                             "wire rope": [np.nan, np.nan, np.nan]},
                   [0.5, 1.0], {"reference": [14.0, 28.0], "hybrid": [9.0, 17.0], "wire rope": [5.0, np.nan]})
    ends = rest_shock_ends(study)
    assert ends["hybrid"] == ("at a drop height of 5 cm (its curve versus impact speed runs to the end of that "
                              "sweep, 1 m/s)")
    # no valid drop height at all is a stop too, not a curve that runs to the end
    assert ends["wire rope"] == "at an impact speed of 0.5 m/s and a drop height of 5 cm already (no valid point)"
    assert "reference" not in ends
    sentences = transport_conclusions(study, heights=(0.10,))
    assert "no value (model invalid) for hybrid, wire rope" in sentences[1]
    assert "hybrid: the rest-shock curve stops at a drop height of 5 cm" in sentences[2]


def test_a_fit_that_is_not_a_success_is_flagged_as_the_cli_prints_it_not_failed():
    # FAIL is a validation's verdict (exit status 1); a fit that is not a success is FLAGGED
    # (exit status 4 for the fits the report predicts with, nothing for the Bouc-Wen comparison)
    from types import SimpleNamespace

    fit = SimpleNamespace(success=False, reasons=["small-loop error 7.64 % is 7.54 points above the noise floor"])
    verdict, text = fit_sentence("Maxwell fit", fit)
    assert verdict == "FLAGGED" and text == ("Maxwell fit: the fit is not a success: small-loop error 7.64 % is "
                                             "7.54 points above the noise floor.")
    verdict, text = fit_sentence("Bouc-Wen comparison", fit, comparison=True)
    assert verdict == "FLAGGED" and text.endswith("it enters neither the verdicts nor the exit status.")
    assert fit_sentence("Iwan fit", SimpleNamespace(success=True, reasons=[])) == ("PASS", "Iwan fit: the fit succeeded.")


def test_the_identified_model_is_stated_whole_with_how_its_unfitted_parameters_were_set():
    # the rope's c_visc is not a loop-fit parameter, but the model file and every prediction carry it
    table = pd.DataFrame({"parameter": ["g1", "c_visc"], "unit": ["N/m", "N s/m"], "value": [18383.3, 13.9155],
                          "stderr": [8.3, None], "stderr_note": ["", "from the stepped-sine resonance, not the loops"],
                          "fitted": [True, False]})
    assert parameters_sentence(table) == "g1 = 1.84e+04 +- 8.3 N/m"
    assert parameters_sentence(table, unfitted=True) == ("g1 = 1.84e+04 +- 8.3 N/m; c_visc = 13.9 N s/m (from the "
                                                         "stepped-sine resonance, not the loops)")


def test_drop_model_support_for_another_model_than_the_validated_one_says_so():
    from types import SimpleNamespace

    from idkit.studies.drop_models import DropModelComparison

    def result(compression, tension):
        return SimpleNamespace(verdict="PASS", summary={"median_peak_acceleration_compression_error": compression,
                                                        "median_peak_acceleration_tension_error": tension})

    # the bundled rope: the plain model's worse phase (0.040) beats the modulated one's (0.086)
    comparison = DropModelComparison(table=pd.DataFrame(), results={
        ("plain Iwan", "rig"): result(0.040, 0.028), ("slip-modulated Iwan", "rig"): result(0.030, 0.086),
        ("plain Iwan", "conditioned"): result(0.11, 0.24)})
    text = drop_model_sentence(comparison, used=("slip-modulated Iwan", "rig"))
    assert text == ("The held-out drops support the plain Iwan model with the rig drop model: median peak error "
                    "0.040 in compression and 0.028 in tension; the slip-modulated Iwan model with the rig drop "
                    "model, which the validations above use, 0.030 and 0.086.")
    assert drop_model_sentence(comparison, used=("plain Iwan", "rig")).endswith("0.028 in tension.")


def test_drop_models_that_all_fail_are_not_said_to_be_supported():
    """Held-out rope drops made with a 7.39 kg payload declared as 4.33 kg (Table A.1 asymmetric
    set): both pairs FAIL (0.415 / 0.251 conditioned, 0.620 / 0.259 rig), and the report said
    'The held-out drops support the plain Iwan model with the conditioned drop model'."""
    from types import SimpleNamespace

    from idkit.studies.drop_models import DropModelComparison

    def result(verdict, compression, tension):
        return SimpleNamespace(verdict=verdict, summary={"median_peak_acceleration_compression_error": compression,
                                                         "median_peak_acceleration_tension_error": tension})

    comparison = DropModelComparison(table=pd.DataFrame(), results={
        ("plain Iwan", "conditioned"): result("FAIL", 0.415, 0.251), ("plain Iwan", "rig"): result("FAIL", 0.620, 0.259)})
    text = drop_model_sentence(comparison, used=("plain Iwan", "rig"))
    assert "support the" not in text
    assert text == ("The held-out drops support no rope and drop model compared (2 pairs, none passes); the closest "
                    "is the plain Iwan model with the conditioned drop model (FAIL): median peak error 0.415 in "
                    "compression and 0.251 in tension; the plain Iwan model with the rig drop model, which the "
                    "validations above use, 0.620 and 0.259.")


def test_the_reference_is_named_once_when_it_is_the_runner_up():
    rms = pd.DataFrame({"1e-06 [(m/s^2)^2/Hz]": [0.3, 0.2, 0.4]}, index=["reference", "hybrid", "wire rope"])
    study = _study(rms, [0.01, 0.03], {name: [1.0, 2.0] for name in rms.index}, [0.1, 0.2],
                   {name: [1.0, 2.0] for name in rms.index})
    sentence = transport_conclusions(study, heights=())[0]
    assert sentence.endswith("hybrid protects the payload best (0.2 m/s^2; next reference 0.3 m/s^2, 1.5 times as "
                             "much).")

"""Measured drops beside the model's (idkit.studies.drop_histories) on records the rig model wrote."""

import numpy as np
import pytest

from idkit.io import DropMeasurement, MeasurementInfo
from idkit.models import SDOFSystem, VoigtModel
from idkit.plot import plot_drop_histories
from idkit.simulate.drop_rig import ContactModel, drop_rig, rig_time_step
from idkit.studies.drop_histories import drop_histories

TOP, BOTTOM, K, C = 4.0, 8.0, 4.0 * (2 * np.pi * 8.0) ** 2, 2 * 0.08 * 4.0 * 2 * np.pi * 8.0
HEIGHTS = (0.02, 0.05, 0.08, 0.11)
FS = 5000.0


def truth(scale=1.0):
    return VoigtModel(k=scale * K, damping=C)


@pytest.fixture(scope="module")
def records():
    """Rig drops of the truth simulated at the rig's own step, recorded at about 5 kHz from 50 ms
    before the first contact."""
    system = SDOFSystem(TOP, truth())
    step = rig_time_step(system, BOTTOM, CONTACT)
    every = max(1, round(1 / FS / step))
    run = drop_rig(system, bottom_mass=BOTTOM, drop_height=list(HEIGHTS), contact=CONTACT, before=0.05, duration=0.4)
    out = []
    for index, height in enumerate(HEIGHTS):
        accel = run.top_acceleration[index, ::every]
        out.append(DropMeasurement(
            time=run.time[::every] - run.time[0], deflection=run.deflection[index, ::every], a_top_1=accel,
            a_top_2=accel, v_rel=run.relative_velocity[index, ::every],
            info=MeasurementInfo(id=f"drop_{height}", isolator="elastomer", top_mass_kg=TOP, bottom_mass_kg=BOTTOM,
                                 drop_height_m=height, split="validation")))
    return out


def _deflection_mismatch(history):
    """Largest |model - measured| deflection over the shown window, relative to the peak compression."""
    drop = history
    simulated = np.interp(drop.measured_time, drop.simulated_time, drop.simulated_deflection)
    return np.max(np.abs(simulated - drop.measured_deflection)) / np.max(np.abs(drop.measured_deflection))


CONTACT = ContactModel(restitution=0.3)


def test_the_generating_model_retraces_its_own_records(records):
    histories = drop_histories(records, isolator=truth(), contact=CONTACT)
    # lowest, a middle and the highest height
    heights = [d.drop_height_m for d in histories.drops]
    assert heights[0] == 0.02 and heights[-1] == 0.11 and heights[1] in (0.05, 0.08)
    assert histories.setup == "top mass 4 kg, bottom mass 8 kg"
    for drop in histories.drops:
        assert drop.status == "ok"
        assert drop.measured_time[0] == pytest.approx(-0.005, abs=2 / FS)
        # both records are read by the same processor at the same rate: what is left is the
        # truth's sampling (the model's run is not decimated), a fraction of the |v0| / FS
        # one sample of shift would make (about 1 % of the peak here)
        assert _deflection_mismatch(drop) < 0.01


def test_contact_read_off_the_records_keeps_the_model_close(records):
    """The default contact: the median restitution read off the records (as the validation)."""
    histories = drop_histories(records, isolator=truth())
    assert 0.2 < histories.contact.restitution < 0.45
    # a restitution off by up to half changes the bottom mass's rebound and so the stroke
    # by a few percent
    assert max(_deflection_mismatch(drop) for drop in histories.drops) < 0.08


def test_a_stiffness_twice_the_truth_is_visible(records):
    histories = drop_histories(records, isolator=truth(2.0), contact=CONTACT)
    assert min(_deflection_mismatch(drop) for drop in histories.drops) > 0.3


def test_figure_has_one_curve_pair_per_drop_and_no_drop_gives_none(records):
    histories = drop_histories(records, isolator=truth())
    accel_ax, deflection_ax = plot_drop_histories(histories)
    assert len(accel_ax.get_lines()) == 2 * len(histories.drops)
    assert "tension positive" in deflection_ax.get_ylabel()
    no_rig = [DropMeasurement(time=r.time, deflection=r.deflection, a_top_1=r.a_top_1, a_top_2=r.a_top_2,
                              info=MeasurementInfo(id=r.info.id, top_mass_kg=TOP)) for r in records]
    assert drop_histories(no_rig, isolator=truth()) is None

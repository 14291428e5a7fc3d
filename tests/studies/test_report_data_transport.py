"""``ReportData.transport``: the study computed in a forked child is waited for on first use."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from idkit.forked import fork_call
from idkit.studies.pipeline import STAGES, ReportData


def test_the_study_is_waited_for_on_first_use_and_kept():
    holder = SimpleNamespace(transport_source=fork_call(sum, [1, 2, 3]), timings_s={})
    assert ReportData.transport.fget(holder) == 6
    assert holder.transport_source == 6  # the value replaces the pending call
    assert STAGES[4] in holder.timings_s and holder.timings_s[STAGES[4]] >= 0.0
    assert ReportData.transport.fget(holder) == 6


def test_a_failed_study_raises_its_error_and_abandon_is_harmless():
    holder = SimpleNamespace(transport_source=fork_call(int, "not a number"), timings_s={})
    with pytest.raises(ValueError, match="not a number"):
        ReportData.transport.fget(holder)
    ReportData.abandon_transport(holder)  # nothing left to stop
    pending = SimpleNamespace(transport_source=fork_call(sum, [1]), timings_s={})
    ReportData.abandon_transport(pending)  # a child nobody will wait for is stopped
    done = SimpleNamespace(transport_source=6, timings_s={})
    ReportData.abandon_transport(done)
    assert ReportData.transport.fget(done) == 6

"""Studies: whole computations on models and data sets, each returning a typed result.

Compute only: figures are drawn by :mod:`idkit.plot` (:mod:`idkit.plot.studies`,
:mod:`idkit.plot.inspect`, :mod:`idkit.plot.shock`) and files written by :mod:`idkit.report`.

- :mod:`~idkit.studies.chapters` - thesis chapters 3-5: wire rope, elastomer, hybrid (:class:`ChapterStudy`);
- :mod:`~idkit.studies.transport` - the transport systems, their tuning and the study (:class:`TransportStudy`);
- :mod:`~idkit.studies.pipeline` - the compute half of ``idkit report`` (``ReportData``);
- :mod:`~idkit.studies.inspection` - what ``idkit inspect`` shows;
- :mod:`~idkit.studies.harmonic_grid` - the table of ``idkit simulate harmonic``;
- :mod:`~idkit.studies.shock` - shock records: conditioning, spectra, response ratios.
"""

from idkit.studies.chapters import STUDY_NAMES, ChapterStudy, StudyError, compute_chapter_study
from idkit.studies.transport import (
    RK_VALUES,
    TransportStudy,
    TransportSystem,
    compute_transport_study,
    transport_systems,
    tuning_table,
)

__all__ = [
    "RK_VALUES",
    "STUDY_NAMES",
    "ChapterStudy",
    "StudyError",
    "TransportStudy",
    "TransportSystem",
    "compute_chapter_study",
    "compute_transport_study",
    "transport_systems",
    "tuning_table",
]

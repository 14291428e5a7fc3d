"""Reports: render computed results (:mod:`idkit.studies`) and write them (top layer but the CLI).

- :mod:`~idkit.report.main_report` - ``idkit report``: :class:`~idkit.studies.pipeline.ReportData`
  rendered to one self-contained HTML page with models, tables and provenance; its sections are
  drawn by :mod:`~idkit.report.front_page` (first screen, exit status),
  :mod:`~idkit.report.fit_sections`, :mod:`~idkit.report.validation_sections` and
  :mod:`~idkit.report.transport_section`;
- :mod:`~idkit.report.study_files` - a study's figures, CSV tables and ``summary.json``;
- :mod:`~idkit.report.inspect_files` - the overview figures of ``idkit inspect --plots``;
- :mod:`~idkit.report.html` - the HTML builder.
"""

from idkit.report.study_files import run_study, run_transport_study

__all__ = ["run_study", "run_transport_study"]

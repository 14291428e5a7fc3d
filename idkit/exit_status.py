"""Exit statuses of the commands that judge a data set (``idkit report``), in one light module
the CLI can import at start-up without loading the report's dependencies."""

from __future__ import annotations

__all__ = ["REPORT_EXIT_STATUSES"]

#: exit statuses of ``idkit report`` (the report is written in every case); the first that
#: applies, in this order: 1, 3, 4, else 0
REPORT_EXIT_STATUSES = {
    0: "every validation passed and every fit the report predicts with is a success",
    1: "a validation failed",
    3: "no validation failed, but one is inconclusive",
    4: "every validation passed, but a fit the report predicts with is not a success (see its reasons)",
}

"""The order rule: how many elements (or modulation parameters) a model earns (docs/fitting.md).

A richer model must cut the error of the simpler one by more than :data:`ORDER_RULE_FACTOR`:
the lowest order whose error is within that factor of the best is the one kept. The same
comparison decides the Iwan and Maxwell order tables (:mod:`idkit.fit.compare`), the family
rule (:mod:`idkit.fit.family`), the modulated order continuation
(:func:`idkit.fit.iwan_modulated.fit_modulated_orders`) and the Maxwell loss-factor rule
(:func:`idkit.fit.fit_maxwell`); the report quotes the decisions and never compares again.
"""

from __future__ import annotations

import pandas as pd

__all__ = ["ORDER_RULE_FACTOR", "within_order_rule", "earns_its_place", "order_rule"]

#: Order rule: the lowest order whose error (loops: the mean of small and large sets, weighted
#: equally) is within this factor of the best order's. An element more must earn its two
#: parameters by cutting the error by more than a tenth.
ORDER_RULE_FACTOR = 1.10


def within_order_rule(error, best):
    """True where a model of error ``error`` is within the order rule of ``best`` (``error <=
    ORDER_RULE_FACTOR best``): preferred, being simpler, to the model of error ``best``.
    Works on floats and on pandas or numpy arrays alike."""
    return error <= ORDER_RULE_FACTOR * best


def earns_its_place(error: float, simpler_error: float) -> bool:
    """True when a richer model of error ``error`` beats the simpler model's ``simpler_error`` by
    more than the order rule's factor (``ORDER_RULE_FACTOR error < simpler_error``): the simpler
    model is then not within the rule (:func:`within_order_rule`), and a tie keeps it."""
    return ORDER_RULE_FACTOR * error < simpler_error


def order_rule(table: pd.DataFrame, error: pd.Series) -> int:
    """The order of ``table`` the rule keeps: the lowest ``order`` whose ``error`` is within
    :data:`ORDER_RULE_FACTOR` of the best, among the rows that succeeded (``success``); when
    none did, among those whose only reasons are the model-form check's (``model_form_only``:
    every order of the family misses the loops, and the rule still prefers the orders whose
    parameters the data determine); else among all rows."""
    candidates = table["success"]
    if not candidates.any() and "model_form_only" in table and table["model_form_only"].any():
        candidates = table["model_form_only"].astype(bool)
    if not candidates.any():
        candidates = pd.Series(True, index=table.index)
    error = error[candidates]
    return int(table.loc[error.index[within_order_rule(error, error.min())], "order"].min())

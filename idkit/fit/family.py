"""The family rule: a plain or a slip-modulated Iwan model for the wire rope (docs/fitting.md, "Model family").

The plain model is kept while it explains the loops to within the noise margin
(:mod:`idkit.fit.model_form`) with every parameter determined; else the slip-modulation stage
(:func:`idkit.fit.iwan_modulated.fit_modulated_orders`) runs, and its fit is kept when it earns its
three parameters by the order rule (:mod:`idkit.fit.orders`) or determines what the plain fit left
undetermined.
"""

from __future__ import annotations

import math

import pandas as pd

from idkit.fit.compare import iwan_order_row
from idkit.fit.iwan_modulated import fit_modulated_orders
from idkit.fit.model_form import is_model_form_reason
from idkit.fit.orders import earns_its_place, order_rule

__all__ = ["IWAN_FAMILIES", "choose_iwan_family"]


#: Model families of :func:`~idkit.fit.fit_iwan_measurements` (``family=``).
IWAN_FAMILIES = ("auto", "plain", "modulated")


def choose_iwan_family(small, large, plain_fits: dict, *, plain_order: int | None = None, family: str = "auto",
                       valid_range=None, initial_state: str = "auto", floor_check=lambda fit: ()):
    """The family rule: plain or slip-modulated Iwan model (docs/fitting.md, "Model family").

    Parameters
    ----------
    small, large : sequence of LoopSet
        The loop sets the plain fits saw.
    plain_fits : dict
        Order -> plain :class:`~idkit.fit.IwanFitResult` (``order="auto"``: every order of the
        table; a given order: that order alone).
    plain_order : int, optional
        The order the plain order rule chose (default: the lowest in ``plain_fits``).
    family : {"auto", "modulated"}
    valid_range : (float, float), optional
        Passed to the modulation stage (its valid-range barrier).
    initial_state : {"auto", "cycled", "virgin"}
    floor_check : callable
        ``floor_check(fit) -> tuple of str``: why a fit's loop errors are more than
        :data:`~idkit.fit.model_form.FLOOR_MARGIN` above the records' noise floor (empty when they are not).

    Returns
    -------
    (IwanFitResult, pandas.DataFrame or None, IwanFitResult or None)
        The chosen fit (``settings.family`` says which), one order-table row per modulated fit
        (``family="modulated"``) and the modulated fit of the modulated order rule (both None
        when the modulation stage did not run).

    Notes
    -----
    With ``"auto"`` a plain fit that passes ``floor_check`` and whose parameters the data
    determine (no group in :attr:`~idkit.fit.IwanFitResult.undetermined`) is kept as it is: the
    plain model explains the loops down to the noise margin and the modulation could only fit
    noise. Else the modulation stage (:func:`idkit.fit.fit_iwan_modulated`, three parameters
    more) runs from the lowest plain fit given and adds elements by continuation in the order
    (:func:`idkit.fit.iwan_modulated.fit_modulated_orders`: each order starts from the one below
    with an element split in two), and the modulated order is the lowest successful one that
    passes ``floor_check`` with every parameter determined
    (elements are added until the model explains the loops to within the margin, and no
    further: the higher orders are not fitted, so the table's modulated rows stop there); when
    none does, the order rule of the table (:data:`~idkit.fit.orders.ORDER_RULE_FACTOR`: the
    lowest successful order within 1.1 x the best mean of small and large error). ``"auto"``
    keeps the modulated fit when it succeeds and either its mean error is below the plain
    fit's divided by that factor (the modulation parameters must earn their place as an
    element's two do), or the plain fit leaves a combination of parameters undetermined while
    the modulated one, within the floor margin, determines every parameter (a plain fit that
    trades g1 against an element slipping only at the tips of the largest loops is not a
    property of the data); ``"modulated"`` keeps it in any case, its
    reasons saying what is wrong.
    """
    orders = sorted(plain_fits)
    plain = plain_fits[orders[0] if plain_order is None else plain_order]
    plain_undetermined = bool(plain.undetermined)
    misses_the_loops = bool(floor_check(plain)) or any(map(is_model_form_reason, plain.reasons))
    if family == "auto" and not misses_the_loops and not plain_undetermined:
        return plain, None, None

    judged: dict = {}  # order -> (IwanFitResult, accepted), each link judged once

    def accept(modulated) -> bool:  # a determined, successful fit within the floor margin
        order = modulated.model.order
        if order not in judged:
            settings = plain_fits.get(order, plain).settings
            fit = modulated.to_iwan_result(settings if modulated.plain is None else None)
            judged[order] = (fit, fit.success and not floor_check(fit) and not fit.undetermined)
        return judged[order][1]

    # upwards by continuation in the order (fit_modulated_orders), from the lowest plain fit,
    # stopping at the first determined order that reaches the floor margin
    chain = fit_modulated_orders(list(small), list(large), plain_fits[orders[0]], max_order=orders[-1],
                                 points_per_set=None, valid_range=valid_range, initial_state=initial_state,
                                 accept=accept)
    within = [order for order, modulated in chain.items() if accept(modulated)][:1]  # judges the last link too
    fits = {order: judged[order][0] for order in chain}
    rows = pd.DataFrame([iwan_order_row(fit, math.nan) for fit in fits.values()])
    chosen = fits[within[0] if within else order_rule(rows, 0.5 * (rows["error_small_percent"]
                                                                   + rows["error_large_percent"]))]
    mean = 0.5 * (chosen.error_small + chosen.error_large)
    plain_mean = 0.5 * (plain.error_small + plain.error_large)
    determines_more = plain_undetermined and bool(within)
    if family == "modulated" or (chosen.success and (earns_its_place(mean, plain_mean) or determines_more)):
        return chosen, rows, chosen
    return plain, rows, chosen

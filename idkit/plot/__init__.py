"""Figures of results. Every function takes ``ax``/``axes=None``, returns the Axes it drew into and never calls ``show``.

Plots draw what the caller computed: they never run a fitter or a simulation (model forces
along loops and error landscapes come from :mod:`idkit.fit.predictions`, studies from
:mod:`idkit.studies`). matplotlib is imported lazily, and only by the one axes helper
:mod:`idkit.plot._figure`: with ``ax=None`` it creates a :class:`matplotlib.figure.Figure`
directly (no pyplot, no figure registry to leak); pass axes from pyplot to draw into a
figure pyplot/Jupyter displays. The backend is never chosen here: that is the caller's
(``MPLBACKEND``, ``%matplotlib``).
"""

# each module's __all__ is its public list, re-exported here as it stands (as scipy.signal does)
from idkit.plot import basic, branches, fits, responses, validation
from idkit.plot.basic import *  # noqa: F403
from idkit.plot.branches import *  # noqa: F403
from idkit.plot.fits import *  # noqa: F403
from idkit.plot.responses import *  # noqa: F403
from idkit.plot.validation import *  # noqa: F403

__all__ = [*basic.__all__, *branches.__all__, *fits.__all__, *responses.__all__, *validation.__all__]

"""Linear (small-amplitude) frequency domain: complex stiffness, transmissibility, damping.

SPEC 1.4 and 5, thesis 4.2-4.3 (eqs. 4.3-4.5) and 5.3 (figs. 5.7, 5.8):

- complex stiffness ``k*(f)`` of any isolator model at vanishing amplitude (exact for the
  linear Maxwell/Voigt models; the all-stuck limit of a wire rope) and its loss factor
  ``eta = Im k* / Re k*`` (4.4);
- transmissibility ``H = X_top / X_base`` of an SDOF system, ``k* / (k* - m omega^2)``, and
  of the small-amplitude (stuck wire rope) hybrid, from the systems' own
  ``transmissibility`` methods;
- the resonance (peak of ``|H|``) and two equivalent damping ratios: from the half-power
  (-3 dB) width, ``zeta = (f_2 - f_1) / (2 f_r)`` where ``|H| = |H|_max / sqrt(2)``, and
  from the loss factor, ``zeta = eta(f_r) / 2`` (4.5; valid for ``eta`` up to about 0.4).
  For the hybrid the loss factor is that of the series stiffness of the two isolators.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

from idkit.checks import Instance, Real, Reals, Whole, accepts
from idkit.errors import SimulationError
from idkit.models import HybridSystem, IsolatorModel, SDOFSystem
from idkit.signal.harmonics import search_resonance

__all__ = [
    "LinearFrf",
    "LinearResonance",
    "StiffnessResponse",
    "complex_stiffness",
    "effective_stiffness",
    "linear_frf",
    "linear_resonance",
    "loss_factor",
    "stiffness_response",
]


#: The systems whose small-amplitude response is linear algebra (a Coulomb-spring system has none).
LINEAR_SYSTEM = Instance((SDOFSystem, HybridSystem))
#: Positive frequencies, Hz.
FREQUENCIES = Reals(unit="Hz", gt=0)


@accepts(model=Instance((IsolatorModel,), "an idkit isolator model"), freq=FREQUENCIES, error=SimulationError)
def complex_stiffness(model: IsolatorModel, freq: ArrayLike) -> NDArray[np.complex128]:
    """Small-amplitude complex stiffness ``k*(2 pi i f)`` of an isolator model, N/m.

    Parameters
    ----------
    model : IsolatorModel
        Any isolator model (Maxwell, Voigt: exact; Iwan: all elements stuck; Bouc-Wen:
        initial tangent).
    freq : array_like
        Frequencies, Hz.

    Returns
    -------
    ndarray, complex, shape of ``freq``

    Examples
    --------
    >>> from idkit.models import VoigtModel
    >>> complex_stiffness(VoigtModel(k=1e3, damping=10.0), 1.0 / (2 * np.pi))
    array(1000.+10.j)
    """
    return np.asarray(model.small_amplitude_stiffness(freq), dtype=complex)


def loss_factor(stiffness: ArrayLike) -> NDArray[np.float64]:
    """Loss factor ``Im k* / Re k*`` (eq. 4.4) of complex stiffness values, dimensionless.

    NaN where the storage stiffness ``Re k*`` is 0 and the loss too, +-inf where only the storage is 0
    (IEEE division, without numpy's warning: the ratio is undefined or unbounded there).
    """
    if isinstance(stiffness, (str, bytes)):  # numpy reads text as a complex number
        raise SimulationError(f"stiffness: found {stiffness!r}, expected complex stiffness values in N/m")
    try:
        values = np.asarray(stiffness, dtype=complex)
    except (TypeError, ValueError):
        raise SimulationError(f"stiffness: found <{type(stiffness).__name__}>, expected complex stiffness "
                              "values in N/m") from None
    with np.errstate(divide="ignore", invalid="ignore"):
        return values.imag / values.real


@accepts(system=LINEAR_SYSTEM, freq=FREQUENCIES, error=SimulationError)
def effective_stiffness(system, freq: ArrayLike) -> NDArray[np.complex128]:
    """Small-amplitude stiffness between base and top mass, N/m.

    SDOF: the isolator's ``k*``; hybrid: the series stiffness of both isolators
    (:meth:`HybridSystem.series_stiffness`, intermediate mass neglected).
    """
    if isinstance(system, HybridSystem):
        return np.asarray(system.series_stiffness(freq), dtype=complex)
    return complex_stiffness(system.isolator, freq)


@dataclass(frozen=True)
class StiffnessResponse:
    """Complex stiffness of an isolator over frequency (thesis fig. 4.3).

    Attributes
    ----------
    freq : ndarray, shape (n,)
        Hz.
    stiffness : ndarray, complex, shape (n,)
        ``k*``, N/m.
    """

    freq: NDArray[np.float64]
    stiffness: NDArray[np.complex128]

    @property
    def magnitude(self) -> NDArray[np.float64]:
        """``|k*|``, N/m."""
        return np.abs(self.stiffness)

    @property
    def loss_factor(self) -> NDArray[np.float64]:
        """``Im k* / Re k*``, dimensionless."""
        return loss_factor(self.stiffness)

    @property
    def phase(self) -> NDArray[np.float64]:
        """Phase of ``k*`` in rad; ``tan(phase) = loss factor`` (eq. 4.6)."""
        return np.angle(self.stiffness)

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``freq [Hz]``, ``storage [N/m]``, ``loss [N/m]``, ``magnitude [N/m]``, ``loss_factor``."""
        return pd.DataFrame({
            "freq [Hz]": self.freq, "storage [N/m]": self.stiffness.real, "loss [N/m]": self.stiffness.imag,
            "magnitude [N/m]": self.magnitude, "loss_factor": self.loss_factor,
        })


@accepts(freq=FREQUENCIES, error=SimulationError)
def stiffness_response(model: IsolatorModel, freq: ArrayLike) -> StiffnessResponse:
    """:class:`StiffnessResponse` of ``model`` at ``freq`` (Hz)."""
    freq = freq.ravel()
    return StiffnessResponse(freq=freq, stiffness=complex_stiffness(model, freq))


@dataclass(frozen=True)
class LinearResonance:
    """Resonance of a linear(ized) transmissibility and its equivalent damping.

    Attributes
    ----------
    freq : float
        Frequency of the peak of ``|H|``, Hz.
    peak_magnitude : float
        ``|H(freq)|``, dimensionless.
    half_power_freq : tuple of float
        ``(f_1, f_2)`` where ``|H| = peak / sqrt(2)`` below and above the peak, Hz
        (NaN where the search range ends first).
    damping_ratio_half_power : float
        ``(f_2 - f_1) / (2 freq)``.
    loss_factor : float
        Loss factor of the effective stiffness at ``freq``.
    damping_ratio_loss_factor : float
        ``loss_factor / 2`` (eq. 4.5).
    """

    freq: float
    peak_magnitude: float
    half_power_freq: tuple[float, float]
    damping_ratio_half_power: float
    loss_factor: float
    damping_ratio_loss_factor: float

    def to_dict(self) -> dict:
        """Plain dict with unit-bearing keys (for JSON)."""
        return {
            "resonance_Hz": self.freq, "peak_magnitude": self.peak_magnitude,
            "half_power_low_Hz": self.half_power_freq[0], "half_power_high_Hz": self.half_power_freq[1],
            "damping_ratio_half_power": self.damping_ratio_half_power, "loss_factor": self.loss_factor,
            "damping_ratio_loss_factor": self.damping_ratio_loss_factor,
        }


@accepts(f_min=Real(unit="Hz", gt=0), f_max=Real(unit="Hz", gt=0),
         n_grid=Whole(ge=3, meaning="a peak needs a sample on each side"), error=SimulationError)
def linear_resonance(system, *, f_min: float = 1e-2, f_max: float = 1e4, n_grid: int = 4000) -> LinearResonance:
    """Resonance frequency and equivalent damping ratios of the small-amplitude transmissibility.

    The peak of ``|H|`` is located on a log grid of ``n_grid`` points over
    ``[f_min, f_max]`` Hz and refined by bounded Brent minimisation of ``-log|H|`` in
    ``log f`` (:func:`idkit.signal.harmonics.search_resonance`); the half-power frequencies are roots of ``|H| - peak/sqrt(2)`` (brentq).

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
    f_min, f_max : float
        Search range, Hz.
    n_grid : int
        Points of the coarse search grid.

    Returns
    -------
    LinearResonance

    Examples
    --------
    >>> from idkit.models import SDOFSystem, VoigtModel
    >>> system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.02 * 2 * np.pi * 5))
    >>> resonance = linear_resonance(system)
    >>> round(resonance.freq, 3), round(resonance.damping_ratio_half_power, 4)
    (5.0, 0.01)
    """
    if not f_min < f_max:
        raise SimulationError(f"f_min, f_max: found {f_min!r}, {f_max!r}, expected f_min < f_max in Hz")

    def magnitude(freq):
        return np.abs(system.transmissibility(freq))

    found = search_resonance(magnitude, f_min=f_min, f_max=f_max, n_grid=n_grid)
    grid, values, index = found.grid, found.values, found.index
    if not found.inside:
        raise SimulationError(
            f"linear_resonance: |H| is largest at the end of the search range ({grid[index]:.6g} Hz of "
            f"[{f_min:.6g}, {f_max:.6g}] Hz), expected a peak inside it: the resonance lies outside the "
            "range (widen f_min, f_max) or the transmissibility has no peak")
    f_peak, peak = found.freq, found.peak
    level = peak / np.sqrt(2.0)

    def crossing(lo, hi):
        if (magnitude(lo) - level) * (magnitude(hi) - level) > 0:
            return float("nan")
        return float(optimize.brentq(lambda f: magnitude(f) - level, lo, hi, xtol=1e-12 * f_peak, rtol=1e-12))

    below = grid[:index][values[:index] < level]
    above = grid[index + 1:][values[index + 1:] < level]
    f_1 = crossing(below[-1], f_peak) if below.size else float("nan")
    f_2 = crossing(f_peak, above[0]) if above.size else float("nan")
    eta = float(loss_factor(effective_stiffness(system, f_peak)))
    return LinearResonance(
        freq=f_peak, peak_magnitude=peak, half_power_freq=(f_1, f_2),
        damping_ratio_half_power=(f_2 - f_1) / (2.0 * f_peak), loss_factor=eta,
        damping_ratio_loss_factor=0.5 * eta,
    )


@dataclass(frozen=True)
class LinearFrf:
    """Small-amplitude frequency response of a system (thesis figs. 4.4, 5.7, 5.8).

    Attributes
    ----------
    freq : ndarray, shape (n,)
        Hz.
    transmissibility : ndarray, complex, shape (n,)
        Top over base displacement (= acceleration) ``H``, dimensionless.
    stiffness : ndarray, complex, shape (n,)
        Effective base-to-top stiffness (:func:`effective_stiffness`), N/m.
    component_stiffness : tuple of ndarray
        ``k*`` of each isolator, top first (hybrid: elastomer, then stuck wire rope), N/m.
    resonance : LinearResonance
    """

    freq: NDArray[np.float64]
    transmissibility: NDArray[np.complex128]
    stiffness: NDArray[np.complex128]
    component_stiffness: tuple[NDArray[np.complex128], ...]
    resonance: LinearResonance

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``freq [Hz]``, ``H_magnitude [-]``, ``H_phase [deg]``, ``stiffness_magnitude [N/m]``,
        ``loss_factor [-]`` and the same two per isolator (``isolator_<i>_...``)."""
        columns = {
            "freq [Hz]": self.freq,
            "H_magnitude [-]": np.abs(self.transmissibility),
            "H_phase [deg]": np.degrees(np.unwrap(np.angle(self.transmissibility))),
            "stiffness_magnitude [N/m]": np.abs(self.stiffness),
            "loss_factor [-]": loss_factor(self.stiffness),
        }
        for index, values in enumerate(self.component_stiffness):
            columns[f"isolator_{index}_magnitude [N/m]"] = np.abs(values)
            columns[f"isolator_{index}_loss_factor [-]"] = loss_factor(values)
        return pd.DataFrame(columns)

    def report(self) -> str:
        """Resonance and damping in one paragraph."""
        r = self.resonance
        return (
            f"linear resonance {r.freq:.4g} Hz, |H| peak {r.peak_magnitude:.4g}; damping ratio from -3 dB width "
            f"{r.damping_ratio_half_power:.4g}, from eta/2 {r.damping_ratio_loss_factor:.4g} (eta {r.loss_factor:.4g})"
        )


@accepts(system=LINEAR_SYSTEM, freq=FREQUENCIES, error=SimulationError)
def linear_frf(system, freq: ArrayLike) -> LinearFrf:
    """Transmissibility, stiffnesses and resonance of the small-amplitude system at ``freq`` (Hz).

    Examples
    --------
    >>> from idkit.models import library
    >>> frf = linear_frf(library.get("system_b1_medium"), np.geomspace(1.0, 100.0, 50))
    >>> round(frf.resonance.freq, 2)
    4.99
    """
    freq = freq.ravel()
    return LinearFrf(
        freq=freq, transmissibility=np.asarray(system.transmissibility(freq), dtype=complex),
        stiffness=effective_stiffness(system, freq),
        component_stiffness=tuple(complex_stiffness(isolator, freq) for isolator in system.isolators),
        resonance=linear_resonance(system, **_resonance_range(system)),
    )


def _resonance_range(system) -> dict[str, float]:
    """A search range of :func:`linear_resonance` that holds ``system``'s resonance.

    The undamped natural frequencies lie between ``sqrt(k_low / M) / 2 pi`` (the softest
    isolator's static stiffness under the whole mass) and ``sqrt(k_high / m) / 2 pi`` (every
    isolator's high-frequency stiffness on the lightest mass); damping only lowers the peak
    of ``|H|``. The range is the default 0.01 Hz - 10 kHz widened to two decades below and one
    above those bounds, so a stiff small part (or a soft heavy one) is not cut off.
    """
    masses = np.asarray(system.masses, dtype=float)
    low = np.array([complex_stiffness(isolator, 1e-9).real for isolator in system.isolators])
    high = np.array([complex_stiffness(isolator, 1e9).real for isolator in system.isolators])
    f_low = np.sqrt(max(low.min(), 0.0) / masses.sum()) / (2.0 * np.pi)
    f_high = np.sqrt(max(high.sum(), 0.0) / masses.min()) / (2.0 * np.pi)
    f_min, f_max = 1e-2, 1e4
    if np.isfinite(f_low) and f_low > 0:
        f_min = min(f_min, f_low / 100.0)
    if np.isfinite(f_high):
        f_max = max(f_max, f_high * 10.0)
    return {"f_min": f_min, "f_max": f_max}

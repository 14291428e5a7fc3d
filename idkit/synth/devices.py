"""Synthetic devices with known parameters: truths built to differ (issue 32.5).

Each device is a force law computed here with its **own** plain-numpy time stepping, not
with idkit's compiled kernels (:mod:`idkit.models.laws`, :mod:`idkit.simulate`), so a test
that fits an idkit model to a device's records and compares the parameters is not circular.
Every law below is rate independent except :class:`RateDependentDamper`; each is evaluated
exactly at the samples of a piecewise-linear deflection path (a stop operator's state after
a monotone step depends on the step's end points only; the Bouc-Wen device with ``n = 1``
has a closed form along a monotone step):

* :class:`JenkinDevice` - a linear spring in parallel with Jenkin elements (the plain Iwan
  family of :class:`idkit.models.IwanModel` with ``g2 = g3 = 0``);
* :class:`BoucWenDevice` - a linear spring in parallel with a Bouc-Wen hysteretic force of
  exponent ``n = 1`` (the family of :class:`idkit.models.BoucWenModel` with ``k2 = k3 = 0``,
  ``b = 1``, ``c = 0``), integrated exactly (piecewise exponential in the deflection);
* :class:`ClearanceFrictionDamper` - a friction damper with clearance: a dead zone of
  half-width ``clearance`` with contact stiffness in series with a Jenkin element, in parallel
  with a linear spring (the issue's real friction damper shows a zero-force plateau after
  every reversal);
* :class:`PinchedRope` - a Bouc-Wen rope with Baber-Noori pinching of the hysteretic force
  (``dz/dx`` scaled by ``1 - zeta exp(-((z sgn(dx) - q z_u) / psi)^2)``, ``z_u`` the
  ultimate ``z``), integrated by RK4 sub-steps in the deflection;
* :class:`RateDependentDamper` - a linear spring in parallel with a Jenkin element whose slip
  force rises with the deflection rate, ``fc(v) = fc0 + fc1 tanh(|v| / v_ref)``, ``v`` the
  deflection rate of each sampled step, plus viscous damping ``c_visc``.

Deflection histories (:func:`sine_history`, :func:`random_history`,
:func:`earthquake_history`, :func:`multilevel_history`) start and end at rest at zero, so a
device and a model both start from their virgin state. :func:`device_records` turns a device
and histories into :class:`~idkit.io.QuasiStaticMeasurement` records with seeded Gaussian
force noise (the truth's own error on them, the noise floor, is ``sigma / rms(force)``);
:func:`idkit.observe.histories.force_histories` reads them, or a measurement set written
from them (:func:`idkit.io.write_measurement_set`), as force histories. All values SI.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import asdict, dataclass

import numpy as np

from idkit.checks import Real, Reals, Seed, Whole, accepts
from idkit.errors import ParameterError
from idkit.io import MeasurementInfo, QuasiStaticMeasurement

__all__ = [
    "JenkinDevice", "BoucWenDevice", "ClearanceFrictionDamper", "PinchedRope", "RateDependentDamper",
    "sine_history", "random_history", "earthquake_history", "multilevel_history", "device_records",
    "protocol_records", "DEVICES",
]


def _path(deflection, time) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(deflection, dtype=float)
    t = np.asarray(time, dtype=float)
    if x.ndim != 1 or x.shape != t.shape or x.size < 2:
        raise ParameterError(f"deflection and time: found shapes {x.shape} and {t.shape}, expected equal 1-D "
                             "shapes of at least 2 samples")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
        raise ParameterError("deflection and time: expected finite values and strictly increasing time")
    return x, t


def _positive(**values) -> None:
    for name, value in values.items():
        Real(gt=0).check(value, name)


def _non_negative(**values) -> None:
    for name, value in values.items():
        Real(ge=0).check(value, name)


@dataclass(frozen=True)
class JenkinDevice:
    """``F = parallel_stiffness x + sum_i F_i``, each ``F_i`` a Jenkin element (spring ``k_i`` in
    series with a slider of slip force ``fc_i``), every element unloaded at the start.

    ``family = "iwan"``; :meth:`true_params` uses :class:`idkit.models.IwanModel`'s names.
    """

    parallel_stiffness: float
    stiffness: tuple[float, ...]
    slip_force: tuple[float, ...]
    family = "iwan"

    def __post_init__(self):
        _positive(parallel_stiffness=self.parallel_stiffness)
        if len(self.stiffness) != len(self.slip_force) or not self.stiffness:
            raise ParameterError("stiffness, slip_force: expected equal, non-zero numbers of elements")
        for k, fc in zip(self.stiffness, self.slip_force):
            _positive(stiffness=k, slip_force=fc)

    def force(self, deflection, time) -> np.ndarray:
        x, _ = _path(deflection, time)
        k = np.asarray(self.stiffness, dtype=float)
        fc = np.asarray(self.slip_force, dtype=float)
        element = np.zeros(k.size)
        out = np.empty(x.size)
        out[0] = self.parallel_stiffness * x[0]
        element[:] = np.clip(k * x[0], -fc, fc)
        out[0] += element.sum()
        for i in range(1, x.size):
            element = np.clip(element + k * (x[i] - x[i - 1]), -fc, fc)
            out[i] = self.parallel_stiffness * x[i] + element.sum()
        return out

    def true_params(self) -> dict[str, float]:
        values = {"g1": self.parallel_stiffness}
        values.update({f"k_{i}": float(v) for i, v in enumerate(self.stiffness, start=1)})
        values.update({f"fc_{i}": float(v) for i, v in enumerate(self.slip_force, start=1)})
        return values


@dataclass(frozen=True)
class BoucWenDevice:
    """``F = k1 x + z``, ``dz/dx = alpha - (gamma + beta sgn(dx z)) |z|`` (``n = 1``), ``z(0) = 0``.

    Along a monotone step the law is linear in ``z`` with a rate that switches where ``z``
    changes sign, so each step is solved exactly: ``z -> z_inf + (z - z_inf) exp(-r s)``, ``s``
    the travel, ``r = gamma + beta sgn(dx z)``, ``z_inf = alpha / r`` (``z + alpha s`` when
    ``r = 0``), split at the zero crossing. ``family = "boucwen"``; :meth:`true_params` uses
    :class:`idkit.models.BoucWenModel`'s names.
    """

    k1: float
    alpha: float
    beta: float
    gamma: float
    family = "boucwen"

    def __post_init__(self):
        _non_negative(k1=self.k1)
        _positive(alpha=self.alpha, beta_plus_gamma=self.beta + self.gamma, beta=self.beta)

    def _advance(self, z: float, step: float) -> float:
        """``z`` after a deflection step ``step`` (either sign), exactly."""
        direction = 1.0 if step > 0 else -1.0
        travel = abs(step)
        # in the travel coordinate s (>= 0): dw/ds = alpha - r |w| with w = direction * z ... written per sign
        w = direction * z  # w grows towards alpha / (beta + gamma) while loading
        while travel > 0.0:
            rate = self.gamma + (self.beta if w >= 0.0 else -self.beta)
            if w < 0.0:  # unloading side: w rises towards 0 with dw/ds = alpha - rate |w| = alpha + rate w
                if rate == 0.0:
                    reach = -w / self.alpha
                    if reach >= travel:
                        return direction * (w + self.alpha * travel)
                else:
                    w_inf = -self.alpha / rate  # fixed point of alpha + rate w
                    # w(s) = w_inf + (w - w_inf) exp(rate s); the crossing of 0 at s0
                    ratio = w_inf / (w_inf - w)
                    reach = math.log(ratio) / rate if ratio > 0.0 else math.inf
                    if not reach < travel:
                        return direction * (w_inf + (w - w_inf) * math.exp(rate * travel))
                travel -= reach
                w = 0.0
                continue
            w_inf = self.alpha / rate
            return direction * (w_inf + (w - w_inf) * math.exp(-rate * travel))
        return direction * w

    def hysteretic_force(self, deflection, time) -> np.ndarray:
        x, _ = _path(deflection, time)
        z = np.empty(x.size)
        z[0] = self._advance(0.0, x[0]) if x[0] != 0.0 else 0.0
        for i in range(1, x.size):
            step = x[i] - x[i - 1]
            z[i] = self._advance(z[i - 1], step) if step != 0.0 else z[i - 1]
        return z

    def force(self, deflection, time) -> np.ndarray:
        x, _ = _path(deflection, time)
        return self.k1 * x + self.hysteretic_force(x, time)

    def true_params(self) -> dict[str, float]:
        return {"k1": self.k1, "k2": 0.0, "k3": 0.0, "alpha": self.alpha, "beta": self.beta, "gamma": self.gamma,
                "n": 1.0, "b": 1.0, "c": 0.0}


@dataclass(frozen=True)
class ClearanceFrictionDamper:
    """Friction damper with clearance: ``F = parallel_stiffness x + F_s``, ``F_s`` the force through
    a dead zone of half-width ``clearance`` (no force while the play is open, ``contact_stiffness``
    beyond it) in series with a Jenkin element (``stiffness``, ``slip_force``).

    State: the slider position ``p``. With ``e = x - p``: ``F_s = 0`` for ``|e| <= clearance``, else
    ``sgn(e) (|e| - clearance) / (1 / contact_stiffness + 1 / stiffness)`` while below the slip
    force; at the slip force the slider follows, ``p = x - sgn(e) (clearance + slip_force /
    contact_stiffness + slip_force / stiffness)``. After each reversal the force falls to zero and
    stays there over ``2 clearance`` of travel (the plateau). ``family = "clearance_jenkin"``.
    """

    parallel_stiffness: float
    contact_stiffness: float
    clearance: float
    stiffness: float
    slip_force: float
    family = "clearance_jenkin"

    def __post_init__(self):
        _non_negative(parallel_stiffness=self.parallel_stiffness, clearance=self.clearance)
        _positive(contact_stiffness=self.contact_stiffness, stiffness=self.stiffness, slip_force=self.slip_force)

    def series_force(self, deflection, time) -> np.ndarray:
        x, _ = _path(deflection, time)
        compliance = 1.0 / self.contact_stiffness + 1.0 / self.stiffness
        at_slip = self.clearance + self.slip_force * compliance
        p = 0.0
        out = np.empty(x.size)
        for i, xi in enumerate(x):
            e = xi - p
            if abs(e) <= self.clearance:
                out[i] = 0.0
                continue
            sign = 1.0 if e > 0 else -1.0
            trial = (abs(e) - self.clearance) / compliance
            if trial > self.slip_force:
                p = xi - sign * at_slip
                trial = self.slip_force
            out[i] = sign * trial
        return out

    def force(self, deflection, time) -> np.ndarray:
        x, t = _path(deflection, time)
        return self.parallel_stiffness * x + self.series_force(x, t)

    def true_params(self) -> dict[str, float]:
        return asdict(self)


@dataclass(frozen=True)
class PinchedRope:
    """A pinched Bouc-Wen rope (Baber-Noori pinching, no degradation): ``F = k1 x + z``,

    ``dz/dx = h(z) (alpha - (gamma + beta sgn(dx z)) |z|^n)``,
    ``h(z) = 1 - pinching exp(-((z sgn(dx) - position z_u) / width)^2)``,
    ``z_u = (alpha / (beta + gamma))^(1/n)``: near ``z = position z_u`` on each branch the
    hysteretic force stalls, the loop narrows (pinches) there. Integrated by classical RK4 in
    the deflection with sub-steps of at most ``yield_travel / 200`` (``z_u / alpha``).
    ``width`` is in N. ``family = "pinched_boucwen"``.
    """

    k1: float
    alpha: float
    beta: float
    gamma: float
    n: float
    pinching: float
    width: float
    position: float = 0.0
    family = "pinched_boucwen"

    def __post_init__(self):
        _non_negative(k1=self.k1)
        _positive(alpha=self.alpha, beta_plus_gamma=self.beta + self.gamma, n=self.n, width=self.width)
        if not 0.0 <= self.pinching < 1.0:
            raise ParameterError(f"pinching: found {self.pinching!r}, expected 0 <= pinching < 1")

    @property
    def ultimate_z(self) -> float:
        return (self.alpha / (self.beta + self.gamma)) ** (1.0 / self.n)

    def _rate(self, z: float, direction: float) -> float:
        shape = self.gamma + (self.beta if direction * z >= 0.0 else -self.beta)
        pinch = 1.0 - self.pinching * math.exp(-((z * direction - self.position * self.ultimate_z) / self.width) ** 2)
        return pinch * (self.alpha - shape * abs(z) ** self.n)

    def hysteretic_force(self, deflection, time) -> np.ndarray:
        x, _ = _path(deflection, time)
        largest = self.ultimate_z / self.alpha / 200.0
        z = 0.0
        out = np.empty(x.size)
        previous = 0.0
        for i, xi in enumerate(x):
            step = xi - previous
            if step != 0.0:
                direction = 1.0 if step > 0 else -1.0
                count = max(1, int(math.ceil(abs(step) / largest)))
                h = step / count
                for _ in range(count):
                    k1 = self._rate(z, direction)
                    k2 = self._rate(z + 0.5 * h * k1, direction)
                    k3 = self._rate(z + 0.5 * h * k2, direction)
                    k4 = self._rate(z + h * k3, direction)
                    z += h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
            out[i] = z
            previous = xi
        return out

    def force(self, deflection, time) -> np.ndarray:
        x, t = _path(deflection, time)
        return self.k1 * x + self.hysteretic_force(x, t)

    def true_params(self) -> dict[str, float]:
        return asdict(self)


@dataclass(frozen=True)
class RateDependentDamper:
    """``F = parallel_stiffness x + F_j + c_visc v``: a Jenkin element (``stiffness``) whose slip
    force rises with the deflection rate ``v`` of each sampled step,
    ``fc(v) = fc0 + fc1 tanh(|v| / v_ref)``. ``family = "rate_dependent_jenkin"``."""

    parallel_stiffness: float
    stiffness: float
    fc0: float
    fc1: float
    v_ref: float
    c_visc: float = 0.0
    family = "rate_dependent_jenkin"

    def __post_init__(self):
        _non_negative(parallel_stiffness=self.parallel_stiffness, fc1=self.fc1, c_visc=self.c_visc)
        _positive(stiffness=self.stiffness, fc0=self.fc0, v_ref=self.v_ref)

    def force(self, deflection, time) -> np.ndarray:
        x, t = _path(deflection, time)
        velocity = np.diff(x) / np.diff(t)
        out = np.empty(x.size)
        element = 0.0
        out[0] = self.parallel_stiffness * x[0]
        for i in range(1, x.size):
            limit = self.fc0 + self.fc1 * math.tanh(abs(velocity[i - 1]) / self.v_ref)
            element = min(max(element + self.stiffness * (x[i] - x[i - 1]), -limit), limit)
            out[i] = self.parallel_stiffness * x[i] + element + self.c_visc * velocity[i - 1]
        return out

    def true_params(self) -> dict[str, float]:
        return asdict(self)


#: The element-identification devices with parameters of a small friction damper / rope (SI units):
#: the plain Iwan and Bouc-Wen families fit the first two to their noise floor and miss the other
#: three (docs/elements.md).
DEVICES = {
    "jenkin": JenkinDevice(parallel_stiffness=2.0e4, stiffness=(1.5e5, 4.0e4), slip_force=(60.0, 200.0)),
    "boucwen": BoucWenDevice(k1=2.0e4, alpha=2.0e5, beta=800.0, gamma=400.0),
    "clearance_friction_damper": ClearanceFrictionDamper(parallel_stiffness=5.0e3, contact_stiffness=5.0e5,
                                                         clearance=2.0e-3, stiffness=2.0e5, slip_force=400.0),
    "pinched_rope": PinchedRope(k1=1.5e4, alpha=1.2e5, beta=600.0, gamma=300.0, n=1.0, pinching=0.9,
                                width=60.0, position=0.0),
    "rate_dependent_damper": RateDependentDamper(parallel_stiffness=1.0e4, stiffness=2.0e5, fc0=150.0, fc1=150.0,
                                                 v_ref=0.02, c_visc=0.0),
}


def _envelope_taper(n: int, fraction: float) -> np.ndarray:
    """Cosine ramps over ``fraction`` of ``n`` samples at each end (start and end at rest)."""
    ramp = max(2, int(fraction * n))
    window = np.ones(n)
    shape = 0.5 * (1.0 - np.cos(np.pi * np.arange(ramp) / ramp))
    window[:ramp] = shape
    window[n - ramp:] = shape[::-1]
    return window


_RATE = Real(unit="Hz", gt=0, meaning="sample rate")
_PEAK = Real(unit="m", gt=0, meaning="largest |deflection|")


@accepts(amplitude=Real(unit="m", gt=0), frequency_hz=Real(unit="Hz", gt=0), cycles=Real(gt=0),
         sample_rate_hz=_RATE)
def sine_history(amplitude: float, frequency_hz: float, *, cycles: float = 3.0,
                 sample_rate_hz: float = 200.0) -> tuple[np.ndarray, np.ndarray]:
    """``x = amplitude sin(2 pi f t)`` over ``cycles`` periods from ``t = 0``: ``(time, deflection)``."""
    rate = sample_rate_hz
    n = int(round(cycles * rate / frequency_hz)) + 1
    time = np.arange(n) / rate
    return time, amplitude * np.sin(2.0 * np.pi * frequency_hz * time)


def _band_noise(n: int, rate: float, band: tuple[float, float], rng: np.random.Generator) -> np.ndarray:
    spectrum = np.fft.rfft(rng.standard_normal(n))
    freq = np.fft.rfftfreq(n, 1.0 / rate)
    spectrum[(freq < band[0]) | (freq > band[1])] = 0.0
    return np.fft.irfft(spectrum, n)


@accepts(peak=_PEAK, duration=Real(unit="s", gt=0), sample_rate_hz=_RATE, seed=Seed())
def random_history(peak: float, band_hz: tuple[float, float], *, duration: float, sample_rate_hz: float = 200.0,
                   seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Band-limited Gaussian deflection (flat spectrum in ``band_hz``), cosine-tapered over the
    first and last 10 % so it starts and ends at rest, scaled to ``peak`` (largest |x|)."""
    rate = sample_rate_hz
    if not 0 < band_hz[0] < band_hz[1] < rate / 2:
        raise ParameterError(f"band_hz: found {band_hz!r}, expected 0 < low < high < {rate / 2:g} Hz")
    n = int(round(duration * rate)) + 1
    x = _band_noise(n, rate, band_hz, np.random.default_rng(seed)) * _envelope_taper(n, 0.1)
    return np.arange(n) / rate, peak * x / np.max(np.abs(x))


@accepts(peak=_PEAK, duration=Real(unit="s", gt=0), dominant_hz=Real(unit="Hz", gt=0), sample_rate_hz=_RATE,
         seed=Seed())
def earthquake_history(peak: float, *, duration: float = 20.0, dominant_hz: float = 1.0,
                       sample_rate_hz: float = 200.0, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Earthquake-like deflection: noise in ``0.3-3 x dominant_hz`` under a Saragoni-Hart-like envelope
    (quadratic rise over the first 15 %, strong phase to 45 %, exponential decay to the end), cosine
    tapered at both ends, scaled to ``peak``. Non-stationary, with a strong-motion window well inside
    the record."""
    rate = sample_rate_hz
    if not 3.0 * dominant_hz < rate / 2:
        raise ParameterError(f"dominant_hz: found {dominant_hz!r}, expected 3 x dominant_hz below the Nyquist "
                             f"frequency {rate / 2:g} Hz")
    n = int(round(duration * rate)) + 1
    time = np.arange(n) / rate
    u = time / duration
    envelope = np.where(u < 0.15, (u / 0.15) ** 2, np.where(u < 0.45, 1.0, np.exp(-6.0 * (u - 0.45))))
    x = _band_noise(n, rate, (0.3 * dominant_hz, 3.0 * dominant_hz), np.random.default_rng(seed))
    x = x * envelope * _envelope_taper(n, 0.05)
    return time, peak * x / np.max(np.abs(x))


@accepts(amplitudes=Reals(unit="m", gt=0), frequency_hz=Real(unit="Hz", gt=0), cycles_per_level=Whole(ge=1),
         sample_rate_hz=_RATE)
def multilevel_history(amplitudes, frequency_hz: float, *, cycles_per_level: int = 2,
                       sample_rate_hz: float = 200.0) -> tuple[np.ndarray, np.ndarray]:
    """Sine blocks of the given amplitudes, one after the other, each ``cycles_per_level`` whole periods."""
    rate = sample_rate_hz
    pieces = []
    for amplitude in amplitudes.ravel():
        time, x = sine_history(amplitude, frequency_hz, cycles=cycles_per_level, sample_rate_hz=rate)
        pieces.append(x[:-1])
    x = np.concatenate(pieces + [np.zeros(1)])
    return np.arange(x.size) / rate, x


@accepts(force_noise=Real(unit="N", ge=0), seed=Whole(ge=0, le=2**32 - 1, meaning="seed"))
def device_records(device, histories: dict, *, force_noise: float, seed: int = 0, split: str = "fit",
                   isolator: str = "device") -> list[QuasiStaticMeasurement]:
    """Quasi-static records of ``device`` under each ``{id: (time, deflection)}``, with Gaussian force
    noise of standard deviation ``force_noise`` (N) seeded by ``(seed, crc32(id))``."""
    records = []
    for ident, (time, deflection) in histories.items():
        clean = device.force(deflection, time)
        rng = np.random.default_rng([int(seed), zlib.crc32(str(ident).encode())])
        rate = 1.0 / float(np.median(np.diff(time)))
        info = MeasurementInfo(id=str(ident), isolator=isolator, split=split, sample_rate_hz=rate)
        records.append(QuasiStaticMeasurement(time=np.asarray(time, dtype=float),
                                              deflection=np.asarray(deflection, dtype=float),
                                              force=clean + force_noise * rng.standard_normal(clean.size),
                                              info=info))
    return records


def protocol_records(device, *, amplitudes=(3e-3, 6e-3, 9e-3, 12e-3), frequency_hz: float = 0.5,
                     training_frequencies_hz=None, cycles: float = 2.0,
                     held_out_peak: float = 10e-3, held_out_duration: float = 20.0, sample_rate_hz: float = 100.0,
                     force_noise: float = 3.0, seed: int = 0, isolator: str = "device"):
    """Issue 32.5's protocol for one device: ``(training, held_out)`` records. Training: a sine of each
    amplitude at ``frequency_hz``, or at each of ``training_frequencies_hz`` (a rate-dependent device
    needs several to be identified) (split ``fit``); held out: one random record (0.1-1 Hz) and one
    earthquake-like record (dominant ``frequency_hz``), both of peak ``held_out_peak`` (split
    ``validation``). Every record with ``force_noise`` N of seeded noise; the truth's own error on them
    (the noise floor) is ``force_noise / rms(force)``."""
    if training_frequencies_hz is None:
        sines = {f"sine_{1e3 * a:g}mm": sine_history(a, frequency_hz, cycles=cycles, sample_rate_hz=sample_rate_hz)
                 for a in amplitudes}
    else:
        sines = {f"sine_{1e3 * a:g}mm_{f:g}Hz": sine_history(a, f, cycles=cycles, sample_rate_hz=sample_rate_hz)
                 for a in amplitudes for f in training_frequencies_hz}
    held = {"random": random_history(held_out_peak, (0.1, 1.0), duration=held_out_duration,
                                     sample_rate_hz=sample_rate_hz, seed=seed),
            "quake": earthquake_history(held_out_peak, duration=held_out_duration, dominant_hz=frequency_hz,
                                        sample_rate_hz=sample_rate_hz, seed=seed)}
    return (device_records(device, sines, force_noise=force_noise, seed=seed, isolator=isolator),
            device_records(device, held, force_noise=force_noise, seed=seed, split="validation", isolator=isolator))

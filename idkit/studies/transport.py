"""The transport-tool study of SPEC 6 (thesis chapter 8): systems tuned to one resonance, compared.

Which isolation system protects a payload best? The reference (viscous), the elastomer,
the wire rope and seven hybrids, all tuned to a 5 Hz small-amplitude resonance
(:func:`transport_systems`), are compared by :func:`compute_transport_study` on

* output acceleration PSDs for the six flat floor levels of SPEC 5 (30 seeded
  realizations, Welch; :func:`idkit.responses.random_vibration.random_response`; the
  linear reference and elastomer systems in the frequency domain, ``method="auto"``:
  the same estimate without simulating, and so are the nonlinear ones at levels where no
  Jenkin element would slip (:func:`~idkit.responses.small_amplitude.stays_stuck`); the others settle for five small-amplitude time
  constants, at most one record, :func:`~idkit.responses.random_vibration.settle_records_for`;
  a realization still not periodic then (settling error above :data:`SETTLING_LIMIT`) is
  continued from its own state, record by record, up to :data:`SETTLE_EXTRA_RECORDS`
  (``random_response(settle_until=...)``), and a level with a run still not settled is
  repeated from the small-amplitude steady state, the better settled kept; what is still
  not settled is listed by :meth:`TransportStudy.unsettled`),
* the rest shock level versus impact velocity and drop height
  (:func:`idkit.responses.shock.shock_sweep`, conditioned free fall).

Compute only: the figures are drawn by :mod:`idkit.plot.studies`, the files written by
:mod:`idkit.report.study_files`.

Every system is tuned to a small-amplitude resonance at ``target_freq`` (5 Hz):

* reference: viscous mass-spring-damper, m = 15.0 kg, zeta = 0.07;
* elastomer: the identified elastomer; moving mass (top mass plus the isolator's
  ``m_eff``) from ``|k*(5 Hz)| = m (2 pi 5)^2``;
* wire rope: the identified wire rope; mass from the stuck stiffness ``g1 + sum k_i``;
* hybrids: wire rope unchanged; elastomer stiffnesses scaled so that
  ``r_k = g1 / |k*_el(5 Hz)|`` takes each requested value; moving top mass from the
  magnitude of the series stiffness at 5 Hz; intermediate mass 1 % of the top mass.

Choice (the study is silent): the rule fixes the *moving* mass, so the elastomer's
``m_eff`` is subtracted to get the top mass; the resonance is then exactly at 5 Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Instance, Items, Real, Reals, Whole, accepts
from idkit.errors import ParameterError, SimulationError
from idkit.limits import MAX_IMPACT_SPEED
from idkit.models import GeneralizedMaxwell, HybridSystem, IwanModel, SDOFSystem, VoigtModel, library
from idkit.responses.random_vibration import FLAT_LEVELS, random_response, settle_records_for
from idkit.responses.shock import shock_sweep
from idkit.signal.psd import PsdProfile

__all__ = [
    "RK_VALUES",
    "SETTLE_EXTRA_RECORDS",
    "SETTLING_LIMIT",
    "OutputPsd",
    "TransportStudy",
    "TransportSystem",
    "compute_transport_study",
    "quick_transport_options",
    "transport_systems",
    "tuning_table",
]

RK_VALUES = (0.1, 0.2, 0.4, 0.6, 0.8, 1.0, 1.25)

#: settling error above which a random run's PSD is reported as not settled (a change of
#: 5 % of the signal over one periodic record)
SETTLING_LIMIT = 0.05

#: records a realization that has not settled is continued by, at most (20 s each at the
#: default 0.05 Hz line spacing): 160 s, about 8 time constants of a 0.25 %-damped 5 Hz
#: system; on the bundled parts one extra record settled every run
SETTLE_EXTRA_RECORDS = 8


@dataclass(frozen=True)
class TransportSystem:
    """One tuned system of the study: a name, its kind, the system and the tuning numbers."""

    name: str
    kind: str  # "reference", "elastomer", "wire_rope", "hybrid"
    system: SDOFSystem | HybridSystem
    stiffness_at_target: float  # N/m, magnitude used by the tuning rule
    r_k: float | None = None


#: Highest tuning frequency (Hz): ``omega^2`` at most sqrt(float64 max) = 1.3e154, so that it times any
#: mass up to 1.3e154 kg stays finite (1e300 Hz ended in a bare OverflowError).
MAX_TARGET_FREQ = float(np.sqrt(np.sqrt(np.finfo(float).max))) / (2.0 * np.pi)


#: ``target_freq`` of the tuning, Hz.
_TARGET_FREQ = Real(unit="Hz", gt=0, le=MAX_TARGET_FREQ, meaning="omega^2 at most sqrt of the largest float64")


@accepts(wire_rope=Instance((IwanModel,), optional=True), elastomer=Instance(
             (GeneralizedMaxwell,), what="a GeneralizedMaxwell stiffness model", optional=True),
         target_freq=_TARGET_FREQ, reference_mass=Real(unit="kg", gt=0), reference_damping_ratio=Real(ge=0),
         r_k_values=Reals(gt=0, min_size=0, meaning="stiffness ratios g1 / |k*_el|: none, no hybrids"),
         intermediate_fraction=Real(gt=0, lt=1, meaning="of the top mass: the hybrids are tuned to target_freq on "
                                    "the top mass alone, the intermediate mass small beside it (thesis 5.1)"))
def transport_systems(*, wire_rope: IwanModel | None = None, elastomer: GeneralizedMaxwell | None = None,
                      target_freq: float = 5.0, reference_mass: float = 15.0, reference_damping_ratio: float = 0.07,
                      r_k_values=RK_VALUES, intermediate_fraction: float = 0.01) -> list[TransportSystem]:
    """Build the reference, elastomer, wire-rope and hybrid systems tuned to ``target_freq`` (Hz).

    Defaults: the identified parts of the study (Table 7.1 wire rope, Table 7.3 elastomer).
    ``intermediate_fraction``: the hybrids' intermediate mass as a fraction of their top mass,
    0 < fraction < 1 (the tuning counts the top mass alone).
    """
    wire_rope = wire_rope if wire_rope is not None else library.get("table_7_1_wire_rope")
    elastomer = elastomer if elastomer is not None else library.get("table_7_3_elastomer")
    omega = 2.0 * np.pi * target_freq
    systems = []

    stiffness = reference_mass * omega**2
    damping = 2.0 * reference_damping_ratio * np.sqrt(stiffness * reference_mass)
    systems.append(TransportSystem("reference", "reference",
                                   SDOFSystem(reference_mass, VoigtModel(k=stiffness, damping=damping)), stiffness))

    k_elastomer = float(abs(elastomer.complex_stiffness(target_freq)))
    moving = k_elastomer / omega**2
    systems.append(TransportSystem("elastomer", "elastomer", SDOFSystem(_top_mass(moving, elastomer), elastomer),
                                   k_elastomer))

    k_stuck = wire_rope.stuck_stiffness
    systems.append(TransportSystem("wire rope", "wire_rope", SDOFSystem(k_stuck / omega**2, wire_rope), k_stuck))

    for r_k in np.ravel(r_k_values).tolist():
        scaled = elastomer.scaled(wire_rope.g1 / (r_k * k_elastomer))
        series = float(abs(1.0 / (1.0 / scaled.complex_stiffness(target_freq)
                                   + 1.0 / wire_rope.small_amplitude_stiffness(target_freq))))
        moving = series / omega**2
        top = _top_mass(moving, scaled)
        systems.append(TransportSystem(f"hybrid r_k={r_k:g}", "hybrid",
                                       HybridSystem(top, scaled, intermediate_fraction * top, wire_rope), series,
                                       float(r_k)))
    return systems


def _top_mass(moving_mass: float, isolator) -> float:
    top = moving_mass - isolator.m_eff
    if top <= 0:
        raise ParameterError(
            f"tuning: the moving mass {moving_mass:.4g} kg is below the isolator's m_eff {isolator.m_eff:.4g} kg"
        )
    return top


@accepts(systems=Items(Instance((TransportSystem,), what="a TransportSystem (transport_systems)")),
         target_freq=_TARGET_FREQ)
def tuning_table(systems: list[TransportSystem], target_freq: float = 5.0) -> pd.DataFrame:
    """Masses and tuning checks of the study systems (one row each).

    Columns: ``moving mass [kg]``, the mass the thesis prints for each system (top mass plus
    the elastomer's ``m_eff``, the mass the tuning rule fixes: 101, 65.4, 38.4, 27.2, 21.1,
    17.2, 14.0 kg for the hybrids, 218 kg wire rope, 15.4 kg elastomer);
    ``top mass without m_eff [kg]``, the rigid top mass alone (what the simulator's
    ``SDOFSystem.mass`` / ``HybridSystem.mass`` holds); ``intermediate mass [kg]``;
    ``stiffness at target [N/m]``; ``r_k [-]`` requested and, for the hybrids, achieved.
    """
    rows = []
    for item in systems:
        system = item.system
        masses = system.masses
        row = {"system": item.name, "moving mass [kg]": masses[0], "top mass without m_eff [kg]": system.mass,
               "intermediate mass [kg]": getattr(system, "intermediate_mass", np.nan),
               "stiffness at target [N/m]": item.stiffness_at_target, "r_k [-]": item.r_k}
        if item.kind == "hybrid":
            elastomer_k = abs(system.upper.complex_stiffness(target_freq))
            row["r_k achieved [-]"] = system.lower.g1 / elastomer_k
        rows.append(row)
    return pd.DataFrame(rows)


@dataclass(frozen=True)
class OutputPsd:
    """Mean output acceleration PSD of one system at one flat floor level.

    Attributes
    ----------
    level : float
        Flat floor PSD level over 0.1-100 Hz, (m/s^2)^2/Hz.
    system : str
        Name of the tuned system.
    freq : ndarray
        Frequencies in Hz.
    output_psd : ndarray
        Top acceleration PSD in (m/s^2)^2/Hz.
    """

    level: float
    system: str
    freq: np.ndarray
    output_psd: np.ndarray


@dataclass(frozen=True)
class TransportStudy:
    """Numbers of the transport-tool study.

    Attributes
    ----------
    tuning : DataFrame
        Masses and tuning checks per system (:func:`tuning_table`).
    rms : DataFrame
        RMS top acceleration (m/s^2) per system (rows) and flat input level (columns,
        (m/s^2)^2/Hz; the input RMS is sqrt(level x 99.9 Hz)).
    shock_velocity, shock_height : DataFrame
        Rest shock level (m/s^2) per system (columns) versus |v0| (m/s) / h (m).
    psd : tuple of OutputPsd
        One per level and system, levels in the order computed.
    seed, n_realizations : int
        Seed and number of random realizations per level.
    flagged_runs : int
        Simulations flagged by the kernel (random and shock runs together).
    failures : tuple of str
        Random runs that could not be computed at all (every realization left the model's
        valid range): system, level and why; their RMS and settling entries are NaN.
    settling : DataFrame, optional
        Largest settling error (:attr:`~idkit.responses.random_vibration.RandomResponse.settling_error`:
        change over one record relative to the signal, 0 when periodic) per system (rows)
        and level (columns); 0 for the linear systems, solved without simulating.
    """

    tuning: pd.DataFrame
    rms: pd.DataFrame
    shock_velocity: pd.DataFrame
    shock_height: pd.DataFrame
    psd: tuple[OutputPsd, ...]
    seed: int
    n_realizations: int
    flagged_runs: int
    settling: pd.DataFrame | None = None
    failures: tuple = ()

    def unsettled(self, limit: float = SETTLING_LIMIT) -> list[tuple[str, str, float]]:
        """``(system, level column, settling error)`` of every random run whose settling error exceeds ``limit``."""
        if self.settling is None:
            return []
        return [(str(system), str(level), float(value)) for system, row in self.settling.iterrows()
                for level, value in row.items() if value > limit]

    @property
    def levels(self) -> list[float]:
        """Floor levels of the PSDs, ascending, (m/s^2)^2/Hz."""
        return sorted({item.level for item in self.psd})

    def psd_at(self, level: float) -> tuple[OutputPsd, ...]:
        """The output PSDs of every system at floor level ``level``."""
        return tuple(item for item in self.psd if item.level == level)

    def psd_table(self) -> pd.DataFrame:
        """Every output PSD in long format (level, system, frequency, PSD)."""
        return pd.concat([pd.DataFrame({"level [(m/s^2)^2/Hz]": item.level, "system": item.system,
                                        "freq [Hz]": item.freq, "output PSD [(m/s^2)^2/Hz]": item.output_psd})
                          for item in self.psd])

    def rest_shock_at(self, height: float) -> pd.Series:
        """Rest shock level (m/s^2) of every system at drop height ``height`` (m).

        A height within rounding of a point of the height sweep takes that point's value
        (``np.linspace`` gives 0.04999999999999999 for 5 cm); between two points the level is
        interpolated, and is NaN where either point is (the model went invalid there) or
        outside the sweep.

        Examples
        --------
        >>> study = TransportStudy(tuning=pd.DataFrame(), rms=pd.DataFrame(), psd=(), seed=0, n_realizations=1,
        ...                        flagged_runs=0, shock_velocity=pd.DataFrame(),
        ...                        shock_height=pd.DataFrame({"a": [1.0, 2.0, np.nan]}, index=[0.01, 0.04999999999999999, 0.06]))
        >>> float(study.rest_shock_at(0.05)["a"]), float(study.rest_shock_at(0.055)["a"])
        (2.0, nan)
        """
        heights = self.shock_height.index.to_numpy(float)
        exact = np.flatnonzero(np.isclose(heights, height, rtol=1e-9, atol=0.0))
        if exact.size:
            return self.shock_height.iloc[int(exact[0])].astype(float).rename(None)
        if not heights.min() < height < heights.max():
            return pd.Series(np.nan, index=self.shock_height.columns, dtype=float)
        # np.interp is NaN wherever one of the two neighbours is
        return pd.Series({name: float(np.interp(height, heights, self.shock_height[name].to_numpy(float)))
                          for name in self.shock_height.columns})

    def summary_table(self, heights=(0.02, 0.05, 0.10)) -> pd.DataFrame:
        """RMS per system and level, and rest shock at a few drop heights (m; :meth:`rest_shock_at`)."""
        table = self.rms.copy()
        for height in heights:
            table[f"rest shock at h = {height * 100:g} cm [m/s^2]"] = self.rest_shock_at(height).reindex(table.index)
        return table


def _worst_settling(result) -> float:
    """Largest settling error of a random response (0 when solved in the frequency domain)."""
    values = np.asarray(result.settling_error, dtype=float)
    return float(values.max()) if values.size else 0.0


def quick_transport_options(*, max_speed: float = 1.0, max_height: float = 0.15) -> dict:
    """Settings of a quick study: two levels, 4 realizations, two hybrids, 8 speeds and 6 heights.

    Parameters
    ----------
    max_speed : float
        Highest impact speed |v0| in m/s (from 0.02 m/s).
    max_height : float
        Highest drop height in m (from 1 cm).
    """
    return dict(levels=(1e-6, 1e-3), n_realizations=4, r_k_values=(0.2, 1.0),
                speeds=np.linspace(0.02, max_speed, 8), heights=np.linspace(0.01, max_height, 6))


# checked before the first simulation, not after minutes of random vibration
@accepts(levels=Reals(unit="(m/s^2)^2/Hz", gt=0, meaning="flat floor PSD levels"), n_realizations=Whole(ge=1),
         seed=Whole(ge=0, meaning="random seed"),
         speeds=Reals(unit="m/s", ge=0, lt=MAX_IMPACT_SPEED, optional=True,
                      meaning="impact speeds |v0|: a negative one would be an upward impact"),
         heights=Reals(unit="m", ge=0, optional=True, meaning="drop heights"))
def compute_transport_study(*, wire_rope=None, elastomer=None, levels=FLAT_LEVELS, n_realizations: int = 30,
                            seed: int = 2026, r_k_values=RK_VALUES, speeds=None, heights=None, workers=None,
                            progress=None) -> TransportStudy:
    """Run the study; models default to the study's identified parts (Tables 7.1, 7.3).

    Parameters
    ----------
    wire_rope, elastomer : IwanModel, GeneralizedMaxwell, optional
        Identified components (e.g. from ``idkit fit``).
    levels : sequence of float
        Flat floor PSD levels over 0.1-100 Hz, (m/s^2)^2/Hz.
    n_realizations, seed : int
        Random realizations per level and the seed (each level and system uses
        ``seed``; the same floor signals drive every system).
    r_k_values : sequence of float
        Stiffness ratios of the hybrids (:func:`transport_systems`).
    speeds, heights : array_like, optional
        Impact speeds |v0| (m/s) and drop heights (m) of the shock sweeps
        (defaults 0.01-1.0 m/s and 0.5-15 cm).
    workers : int, optional
        Simulation threads.
    progress : callable(done, total), optional
        One unit per (system, level) and per shock sweep.

    Returns
    -------
    TransportStudy
    """
    systems = transport_systems(wire_rope=wire_rope, elastomer=elastomer, r_k_values=r_k_values)
    # writable copies, as the defaults: the compiled drivers take writable arrays (a read-only one is
    # another signature to compile)
    speeds = np.linspace(0.01, 1.0, 40) if speeds is None else np.array(speeds)
    heights = np.linspace(0.005, 0.15, 30) if heights is None else np.array(heights)
    levels = np.ravel(levels)
    for name, values in (("speeds", speeds), ("heights", heights)):  # shock_sweep takes one axis
        if values.ndim != 1:
            raise ParameterError(f"{name}: found an array of shape {values.shape}, expected a 1-D array")
    profiles = {float(level): PsdProfile.flat(level, f_lo=0.1, f_hi=100.0) for level in levels}
    total = len(systems) * (len(levels) + 2)
    done = 0
    rms_rows, psd, flagged, settling_rows, failures = {}, [], 0, {}, []
    velocity_table, height_table = {}, {}
    settle_of = {item.name: settle_records_for(item.system) for item in systems}
    rms_rows = {item.name: {} for item in systems}
    # level by level: every system is driven by the same seeded floor signals, synthesized once
    for level in levels:
        profile = profiles[float(level)]
        for item in systems:
            settle = settle_of[item.name]
            # linear systems in the frequency domain (the expected Welch estimate, nothing
            # simulated); nonlinear ones start at rest and settle five small-amplitude time
            # constants, at most one record; a realization still not periodic then is
            # continued from its own state, record by record, until it settles (at most
            # SETTLE_EXTRA_RECORDS); a run that still has one that did not (the nearly stuck
            # wire rope rings for minutes) is repeated from its small-amplitude steady state,
            # and the better settled of the two is kept
            try:
                result = random_response(item.system, profile, seed=seed, n_realizations=n_realizations,
                                         method="auto", settle_records=settle, settle_until=SETTLING_LIMIT,
                                         max_extra_records=SETTLE_EXTRA_RECORDS, workers=workers)
            except SimulationError as problem:  # every realization left the model's valid range
                flagged += int(n_realizations)
                failures.append(f"{item.name} at {level:g} (m/s^2)^2/Hz: {problem}")
                rms_rows[item.name][level] = np.nan
                settling_rows.setdefault(item.name, {})[level] = np.nan
                done += 1
                if progress is not None:
                    progress(done, total)
                continue
            if _worst_settling(result) > SETTLING_LIMIT:
                try:
                    linear = random_response(item.system, profile, seed=seed, n_realizations=n_realizations,
                                             method="auto", settle_records=settle, start="linear",
                                             settle_until=SETTLING_LIMIT, max_extra_records=SETTLE_EXTRA_RECORDS,
                                             workers=workers)
                except SimulationError:  # every run left the valid range from the stuck state
                    linear = None
                if linear is not None and _worst_settling(linear) < _worst_settling(result) \
                        and int((linear.flags != 0).sum()) <= int((result.flags != 0).sum()):
                    result = linear
            settling_rows.setdefault(item.name, {})[level] = _worst_settling(result)
            flagged += int((result.flags != 0).sum())
            rms_rows[item.name][level] = result.output_rms
            psd.append(OutputPsd(float(level), item.name, result.freq, result.output_psd))
            done += 1
            if progress is not None:
                progress(done, total)
    for item in systems:
        by_speed = shock_sweep(item.system, impact_velocity=-speeds, workers=workers)
        velocity_table[item.name] = by_speed.rest_shock_level
        done += 1
        by_height = shock_sweep(item.system, drop_height=heights, workers=workers)
        height_table[item.name] = by_height.rest_shock_level
        flagged += int((by_speed.flags != 0).sum() + (by_height.flags != 0).sum())
        done += 1
        if progress is not None:
            progress(done, total)
    settling = pd.DataFrame(settling_rows).T
    settling.columns = [f"{level:g} [(m/s^2)^2/Hz]" for level in settling.columns]
    settling.index.name = "system"
    rms = pd.DataFrame(rms_rows).T
    rms.columns = [f"{level:g} [(m/s^2)^2/Hz]" for level in rms.columns]
    rms.index.name = "system"
    # order the PSDs level by level (every system at the first level, then the next)
    ordered = tuple(sorted(psd, key=lambda item: list(levels).index(item.level)))
    return TransportStudy(
        tuning=tuning_table(systems),
        rms=rms,
        shock_velocity=pd.DataFrame(velocity_table, index=pd.Index(speeds, name="impact speed [m/s]")),
        shock_height=pd.DataFrame(height_table, index=pd.Index(heights, name="drop height [m]")),
        psd=ordered, seed=int(seed), n_realizations=int(n_realizations), flagged_runs=flagged,
        settling=settling, failures=tuple(failures),
    )

"""The synthetic experiments of SPEC section 3: plan (what is measured) and realization.

:func:`plan` lists every measurement of the bundled data as a :class:`Planned` item (id,
kind, set, settings); :func:`realize` turns one item into an :mod:`idkit.io` measurement and a
truth record. Each item draws its random numbers from its own generator seeded with
``(seed, crc32(id))``, so any single measurement can be regenerated alone and bit for bit
(the basis of the "bundled data match the generator" test).

Sensors: every channel gets white Gaussian noise (levels in :data:`NOISE`) and is then
rounded to a fixed resolution (:data:`RESOLUTION`, decimals of the SI value), like an ADC;
the rounding also keeps the CSV files small.

Truth ``"b"`` (:func:`idkit.synth.truth.truth_models`) changes the protocol where the first
one leaves identification untested: a near-stuck stepped-sine level (5e-4 m/s) below the
four of SPEC 3, every level measured also in the reduced grid, and a validation split that
holds out every other frequency **at every level** instead of one whole level; its random
streams are seeded with ``(seed, crc32("b/" + id))``, independent of truth "a".
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass, field

import numba
import numpy as np
from scipy.signal import lfilter

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.io import (
    DropMeasurement,
    Excitation,
    MeasurementInfo,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
)
from idkit.checks import Choice, Flag, accepts
from idkit.synth.chain import link_force_path, pack_links, run_chain
from idkit.synth.names import TRUTH_NAMES

__all__ = ["GRAVITY", "NOISE", "RESOLUTION", "Planned", "plan", "realize"]

GRAVITY = 9.80665  # m/s^2

#: Standard deviation of the white sensor noise per channel (SI units).
NOISE = {
    "qs_deflection": 1.0e-6, "qs_force_wire_rope": 0.05, "qs_force_elastomer": 0.03,
    "shaker_velocity": 5.0e-6, "shaker_position": 1.0e-6, "shaker_voltage": 1.0e-3,
    "drop_deflection": 5.0e-6, "drop_velocity": 2.0e-3, "drop_acceleration": 0.3,
}
#: Decimals kept per quantity (resolution 10**-d in SI units).
RESOLUTION = {"deflection": 7, "force": 3, "velocity": 6, "position": 7, "voltage": 4,
              "acceleration": 2}

SHAKER_RATE_HZ = 2000.0
DROP_RATE_HZ = 2000.0
QS_RATE_HZ = 50.0

ISOLATOR_CODES = {"wire_rope": "wr", "elastomer": "el", "hybrid": "hy"}
WN_MASSES_KG = tuple(float(m) for m in np.round(np.geomspace(0.99, 6.40, 8), 2))
SS_MASSES = {"wire_rope": {"top_mass_kg": 2.98},
             "elastomer": {"top_mass_kg": 0.99},
             "hybrid": {"top_mass_kg": 0.99, "intermediate_mass_kg": 0.14}}
DROP_MASSES = {
    "wire_rope": {"top": (4.33, 7.39), "bottom": 7.88},
    "elastomer": {"top": (4.37, 7.42), "bottom": 7.83},
    "hybrid": {"top": (4.25, 7.31), "intermediate": 0.14, "bottom": 7.83},
}
CONTACT = {"stiffness_N_per_m": 3.0e7, "damping_N_s_per_m": 1.6e4}  # restitution ~0.15
VALIDATION_REPETITION = 3
VALIDATION_SS_AMPLITUDE = 2  # 0-based index into the amplitude list


@dataclass(frozen=True)
class Planned:
    """One measurement to generate.

    Attributes
    ----------
    id : str
        Measurement id (unique in the whole data set).
    kind : str
        Measurement kind.
    set_name : str
        Measurement set (``wire_rope``, ``elastomer``, ``hybrid``).
    settings : dict
        Kind-specific settings (SI): amplitudes, mass, frequency, height, ...
    split : str
        ``fit`` or ``validation``.
    truth : str
        Name of the generating truth (``"a"`` or ``"b"``).
    """

    id: str
    kind: str
    set_name: str
    settings: dict = field(default_factory=dict)
    split: str = "fit"
    truth: str = "a"

    @property
    def stream(self) -> str:
        """Name seeding the item's random numbers (its id; ``"b/" + id`` for truth "b")."""
        return self.id if self.truth == "a" else f"{self.truth}/{self.id}"


def _rng(seed: int, ident: str) -> np.random.Generator:
    return np.random.default_rng([int(seed), zlib.crc32(ident.encode())])


def _sensor(values, sigma, decimals, rng) -> np.ndarray:
    noisy = np.asarray(values, dtype=float) + sigma * rng.standard_normal(np.shape(values))
    return np.round(noisy, decimals) + 0.0  # + 0.0 turns -0.0 into 0.0


def ss_frequencies(quick: bool, truth: str = "a") -> list[float]:
    """Stepped-sine frequencies in Hz (log-spaced 3-100 Hz, 2 decimals): 20, or 6 in the
    reduced grid (9 for truth "b", whose split halves every level)."""
    count = 20 if not quick else 6 if truth == "a" else 9
    return [float(f) for f in np.round(np.geomspace(3.0, 100.0, count), 2)]


def ss_amplitudes(isolator: str, truth: str = "a") -> list[float]:
    """Nominal base-velocity amplitudes in m/s of the stepped-sine sweeps (truth "b" adds a
    near-stuck 5e-4 m/s level below them)."""
    levels = [2e-3, 8e-3, 3e-2, 1.2e-1]
    levels = levels + [2e-1] if isolator == "hybrid" else levels
    return [5e-4] + levels if truth == "b" else levels


def shaker_flatness(freq: float) -> float:
    """Actual / nominal first-harmonic base amplitude of the shaker (not flat, ~1.6:1)."""
    return 1.0 + 0.22 * math.sin(2.2 * math.log(freq / 3.0)) - 0.12 * (freq / 100.0) ** 2


STROKE_LIMIT_M = 6e-3


@accepts(quick=Flag(), truth=Choice(TRUTH_NAMES), error=ValueError)
def plan(*, quick: bool = False, truth: str = "a") -> list[Planned]:
    """Every measurement of a synthetic data set (``quick``: a reduced grid for tests).

    The validation split holds back repetition 3 of the quasi-static, white-noise and drop
    experiments; of the stepped sines, truth "a" holds back the third amplitude level
    (3e-2 m/s) of each isolator, truth "b" every other frequency (the 2nd, 4th, ...) at every
    level. The reduced grid of truth "b" keeps every stepped-sine level and three of the
    white-noise top masses.
    """
    items: list[Planned] = []
    reps = (1, 3) if quick else (1, 2, 3)

    def split_of(rep):
        return "validation" if rep == VALIDATION_REPETITION else "fit"

    qs_programs = {
        ("wire_rope", "small"): [0.05, 0.1, 0.2, 0.35, 0.6, 1.0, 1.6, 2.4, 3.4, 4.5],
        ("wire_rope", "large"): [1.0, 2.0, 3.5, 5.0, 7.0, 9.5, 12.0, 15.0],
        ("elastomer", "loops"): [1.0, 2.0, 3.0, 4.5, 6.0, 8.0],
    }
    speeds = {"small": 0.4e-3, "large": 1.5e-3, "loops": 1.0e-3}
    for (isolator, group), amplitudes_mm in qs_programs.items():
        if quick:
            amplitudes_mm = amplitudes_mm[::3]
        for rep in reps:
            code = ISOLATOR_CODES[isolator]
            items.append(Planned(
                f"qs_{code}_{group}_{rep}", "quasi_static", isolator,
                {"amplitudes_m": [a * 1e-3 for a in amplitudes_mm], "cycles": 2,
                 "speed_m_per_s": speeds[group], "group": group, "repetition": rep},
                split_of(rep), truth))
    masses = WN_MASSES_KG[:: 7 if truth == "a" else 3] if quick else WN_MASSES_KG
    for mass in masses:
        for rep in reps:
            items.append(Planned(
                f"wn_el_{mass:.2f}kg_{rep}", "white_noise", "elastomer",
                {"top_mass_kg": mass, "duration_s": 4.0 if quick else 16.0, "band_hz": [1.0, 500.0],
                 "accel_rms": 3.0, "repetition": rep}, split_of(rep), truth))
    for isolator in ("wire_rope", "elastomer", "hybrid"):
        code = ISOLATOR_CODES[isolator]
        amplitudes = ss_amplitudes(isolator, truth)
        for a_index, amplitude in enumerate(amplitudes):
            if quick and truth == "a" and a_index not in (0, VALIDATION_SS_AMPLITUDE):
                continue
            for f_index, freq in enumerate(ss_frequencies(quick, truth)):
                if amplitude * shaker_flatness(freq) / (2 * math.pi * freq) > STROKE_LIMIT_M:
                    continue  # beyond the shaker's stroke: not measured
                held_out = a_index == VALIDATION_SS_AMPLITUDE if truth == "a" else f_index % 2 == 1
                items.append(Planned(
                    f"ss_{code}_a{a_index + 1}_{freq:06.2f}Hz", "stepped_sine", isolator,
                    {"freq_hz": freq, "amplitude_m_per_s": amplitude, "amplitude_index": a_index,
                     **SS_MASSES[isolator]},
                    "validation" if held_out else "fit", truth))
    heights_cm = (2, 9) if quick else tuple(range(1, 15))
    for isolator in ("wire_rope", "elastomer", "hybrid"):
        code = ISOLATOR_CODES[isolator]
        spec = DROP_MASSES[isolator]
        for top in spec["top"][:1] if quick else spec["top"]:
            for height in heights_cm:
                for rep in reps:
                    items.append(Planned(
                        f"drop_{code}_{top:.2f}kg_{height:02d}cm_{rep}", "drop", isolator,
                        {"top_mass_kg": top, "bottom_mass_kg": spec["bottom"],
                         "intermediate_mass_kg": spec.get("intermediate"),
                         "drop_height_m": height / 100.0, "repetition": rep},
                        split_of(rep), truth))
    return items


# ---------------------------------------------------------------------------------------------
# chains


def _links(isolator: str, wire_rope, elastomer):
    """Masses added by the isolator(s) and the links, top first."""
    if isolator == "wire_rope":
        return [], [wire_rope.link()]
    extra, links = elastomer.chain_links()
    if isolator == "elastomer":
        return extra, links
    return extra, links + [wire_rope.link()]


def _static_link(link, load):
    """Deflection (m) and internal state of a link carrying ``load`` N (positive = tension)
    after slow monotonic loading (Maxwell elements relaxed)."""
    kinds, scalars, ks, bs, ns = pack_links([link])

    def force_at(y):
        path = np.linspace(0.0, y, 400)
        slow = np.linspace(0.0, 1e9, 400)  # so slow that every Maxwell element relaxes
        forces, state = link_force_path(kinds[0], scalars[0], ks[0], bs[0], ns[0],
                                        np.zeros(ks.shape[1]), path, slow)
        return forces[-1], state

    if load == 0:
        return 0.0, np.zeros(ks.shape[1])
    low, high = 0.0, math.copysign(1e-4, load)
    while abs(force_at(high)[0]) < abs(load):
        high *= 2.0
    for _ in range(60):
        middle = 0.5 * (low + high)
        if abs(force_at(middle)[0]) < abs(load):
            low = middle
        else:
            high = middle
    y = 0.5 * (low + high)
    return y, force_at(y)[1]


def _static_chain(masses, links, bottom_position):
    """Positions (m) and link states at rest under gravity, the lowest link standing on
    ``bottom_position`` (base or the held bottom mass)."""
    n_links = len(links)
    n_max = max(1, max(len(link[2]) for link in links))
    states = np.zeros((n_links, n_max))
    deflections = np.zeros(n_links)
    for j in range(n_links):
        load = -GRAVITY * float(np.sum(masses[: j + 1]))
        deflections[j], state = _static_link(links[j], load)
        states[j, : state.size] = state
    positions = np.empty(n_links)
    level = bottom_position
    for j in range(n_links - 1, -1, -1):
        level = level + deflections[j]
        positions[j] = level
    return positions, states, deflections


# ---------------------------------------------------------------------------------------------
# the four kinds


@numba.njit(cache=True)
def _advance(arc, lengths, speed, jerk, dt):
    """Arc length along the waypoint path: slowed near reversals, pushed by the jerks."""
    s = np.zeros(speed.size)
    position = 0.0
    segment = 0
    for i in range(1, speed.size):
        while segment < lengths.size - 1 and position >= arc[segment + 1]:
            segment += 1
        to_corner = min(position - arc[segment], arc[segment + 1] - position)
        slow = min(1.0, 0.15 + to_corner / max(0.3 * lengths[segment], 1e-9))
        position += speed[i] * (slow + jerk[i]) * dt
        s[i] = position
        if position >= arc[-1]:
            return s[: i + 1]
    return s


def _hand_path(amplitudes, cycles, speed, rng, rate_hz, oversample):
    """Deflection of a hand-driven spindle: waypoints 0, +A, -A, ... at an irregular rate.

    The speed along the path is ``speed`` times a log-normal random factor (a smoothed
    random walk), slowed near each reversal, with occasional forward jerks (spikes in the
    rate lasting ~0.1 s). Returns the deflection on a grid ``oversample`` times finer than
    ``rate_hz``.
    """
    waypoints = [0.0]
    for amplitude in amplitudes:
        for _ in range(cycles):
            waypoints += [amplitude, -amplitude]
    waypoints.append(0.0)
    waypoints = np.asarray(waypoints)
    lengths = np.abs(np.diff(waypoints))
    arc = np.concatenate([[0.0], np.cumsum(lengths)])
    dt = 1.0 / (rate_hz * oversample)
    n_max = int(4 * arc[-1] / speed / dt) + 10
    noise = rng.standard_normal(n_max)
    # Ornstein-Uhlenbeck speed modulation (correlation time 2 s, 30 % log-sd)
    theta = dt / 2.0
    log_factor = lfilter([0.3 * math.sqrt(2 * theta)], [1.0, -(1.0 - theta)], noise)
    jerks = rng.random(n_max) < dt / 8.0  # one every ~8 s
    jerk_profile = np.zeros(n_max)
    width = int(0.1 / dt)
    for start in np.flatnonzero(jerks):
        jerk_profile[start:start + width] += 2.5
    s = _advance(arc, lengths, speed * np.exp(log_factor), jerk_profile, dt)
    s = np.minimum(s, arc[-1])
    keep = (s.size - 1) // oversample * oversample + 1
    s = s[:keep]
    return np.interp(s, arc, waypoints), dt


def _quasi_static(item, rng, wire_rope, elastomer):
    st = item.settings
    deflection, dt = _hand_path(st["amplitudes_m"], st["cycles"], st["speed_m_per_s"], rng,
                                QS_RATE_HZ, 10)
    time = np.arange(deflection.size) * dt
    if item.set_name == "wire_rope":
        link, share, sigma_f = wire_rope.link(), 1.0, NOISE["qs_force_wire_rope"]
    else:
        (link, share), sigma_f = elastomer.quasi_static_link(), NOISE["qs_force_elastomer"]
    kinds, scalars, ks, bs, ns = pack_links([link])
    force, _ = link_force_path(kinds[0], scalars[0], ks[0], bs[0], ns[0], np.zeros(ks.shape[1]),
                               share * deflection, time)
    offset = float(np.round(0.1 * rng.standard_normal(), 3))  # load-cell zero error, N
    deflection, force, time = deflection[::10], force[::10], time[::10]
    n = deflection.size
    measured_time = np.arange(n) / QS_RATE_HZ
    info = MeasurementInfo(
        id=item.id, isolator=item.set_name, repetition=st["repetition"], split=item.split,
        sample_rate_hz=QS_RATE_HZ,
        notes=f"{st['group']} loops, amplitudes {', '.join(f'{a * 1e3:g}' for a in st['amplitudes_m'])} mm, "
              f"{st['cycles']} cycles each, hand-driven lathe")
    measurement = QuasiStaticMeasurement(
        time=measured_time,
        deflection=_sensor(deflection, NOISE["qs_deflection"], RESOLUTION["deflection"], rng),
        force=_sensor(force + offset, sigma_f, RESOLUTION["force"], rng), info=info)
    truth = {"force_offset_N": offset, "amplitudes_m": st["amplitudes_m"],
             "mean_speed_m_per_s": st["speed_m_per_s"]}
    return measurement, truth


def _shaker_chain(isolator, top_mass, wire_rope, elastomer, intermediate_mass=None):
    extra, links = _links(isolator, wire_rope, elastomer)
    masses = [top_mass + (elastomer.moving_mass_kg if isolator != "wire_rope" else 0.0)]
    masses += extra
    if isolator == "hybrid":
        masses.append(intermediate_mass)
    return np.asarray(masses), links


def _run_shaker(masses, links, base_x, base_v, dt, record_every):
    positions, states, _ = _static_chain(masses, links, base_x[0])
    return run_chain(masses, links, time_step=dt, n_steps=base_x.size - 1, x0=positions,
                     v0=np.full(masses.size, base_v[0]), state0=states, base_x=base_x,
                     base_v=base_v, gravity=GRAVITY, record_every=record_every)


SHAKER_SUBSTEPS = 10  # integration at 20 kHz, recorded at 2 kHz


def _white_noise(item, rng, wire_rope, elastomer):
    st = item.settings
    dt = 1.0 / (SHAKER_RATE_HZ * SHAKER_SUBSTEPS)
    lead = 1.0
    n = int(round((st["duration_s"] + lead) / dt))
    n += n % 2
    freq = np.fft.rfftfreq(n, dt)
    low, high = st["band_hz"]
    taper = np.clip((freq - 0.8 * low) / (0.2 * low), 0, 1) * np.clip((1.05 * high - freq) / (0.05 * high), 0, 1)
    phase = np.exp(2j * np.pi * rng.random(freq.size))
    spectrum = taper * phase
    scale = st["accel_rms"] / np.sqrt(np.mean(np.fft.irfft(spectrum, n) ** 2))
    omega = 2 * np.pi * freq
    with np.errstate(divide="ignore", invalid="ignore"):
        velocity_spectrum = np.where(omega > 0, scale * spectrum / (1j * omega), 0.0)
        displacement_spectrum = np.where(omega > 0, scale * spectrum / (-(omega**2)), 0.0)
    base_v = np.fft.irfft(velocity_spectrum, n)
    base_x = np.fft.irfft(displacement_spectrum, n)
    base_v = np.append(base_v, base_v[0])
    base_x = np.append(base_x, base_x[0])
    masses, links = _shaker_chain("elastomer", st["top_mass_kg"], wire_rope, elastomer)
    run = _run_shaker(masses, links, base_x, base_v, dt, SHAKER_SUBSTEPS)
    first = int(round(lead * SHAKER_RATE_HZ))
    count = int(round(st["duration_s"] * SHAKER_RATE_HZ))
    window = slice(first, first + count)
    v_base = base_v[::SHAKER_SUBSTEPS][window]
    v_top = run.velocity[0][window]
    info = MeasurementInfo(
        id=item.id, isolator="elastomer", top_mass_kg=st["top_mass_kg"], repetition=st["repetition"],
        split=item.split, sample_rate_hz=SHAKER_RATE_HZ,
        excitation=Excitation(band=(low, high)),
        notes=f"band-limited random base motion, base acceleration {st['accel_rms']:g} m/s^2 rms")
    sigma = NOISE["shaker_velocity"]
    measurement = WhiteNoiseMeasurement(
        time=np.arange(count) / SHAKER_RATE_HZ,
        v_base=_sensor(v_base, sigma, RESOLUTION["velocity"], rng),
        v_top=_sensor(v_top, sigma, RESOLUTION["velocity"], rng), info=info)
    return measurement, {"base_acceleration_rms_m_per_s2": st["accel_rms"],
                         "moving_masses_kg": masses.tolist()}


def _stepped_sine(item, rng, wire_rope, elastomer, quick):
    st = item.settings
    freq = st["freq_hz"]
    omega = 2 * math.pi * freq
    dt = 1.0 / (SHAKER_RATE_HZ * SHAKER_SUBSTEPS)
    amplitude = st["amplitude_m_per_s"] * shaker_flatness(freq)
    ratio_2 = 0.010 * (1 + 0.3 * rng.uniform(-1, 1))
    ratio_3 = 0.007 * (1 + 0.3 * rng.uniform(-1, 1))
    phase_2, phase_3 = rng.uniform(0, 2 * math.pi, 2)
    settle = max(1.0 if quick else 2.5, 20.0 / freq)
    periods = max(4, 2 * math.ceil(0.15 * freq / 2))  # even: the 1/2 subharmonic fits
    record = periods / freq
    ramp = max(3.0 / freq, 0.1)
    n = int(round((settle + record) / dt)) + 1
    t = np.arange(n) * dt
    envelope = np.where(t < ramp, 0.5 * (1 - np.cos(np.pi * np.minimum(t, ramp) / ramp)), 1.0)
    base_v = amplitude * envelope * (np.sin(omega * t) + ratio_2 * np.sin(2 * omega * t + phase_2)
                                     + ratio_3 * np.sin(3 * omega * t + phase_3))
    base_x = np.concatenate([[0.0], np.cumsum(0.5 * dt * (base_v[1:] + base_v[:-1]))])
    masses, links = _shaker_chain(item.set_name, st["top_mass_kg"], wire_rope, elastomer,
                                  st.get("intermediate_mass_kg"))
    run = _run_shaker(masses, links, base_x, base_v, dt, SHAKER_SUBSTEPS)
    count = int(math.floor(record * SHAKER_RATE_HZ))
    first = run.time.size - count
    window = slice(first, first + count)
    lag = rng.uniform(0.2, 0.6)
    drive = (st["amplitude_m_per_s"] / 0.05) * np.sin(omega * t[::SHAKER_SUBSTEPS] + lag)
    info = MeasurementInfo(
        id=item.id, isolator=item.set_name, top_mass_kg=st["top_mass_kg"],
        intermediate_mass_kg=st.get("intermediate_mass_kg"), split=item.split,
        sample_rate_hz=SHAKER_RATE_HZ,
        excitation=Excitation(freq=freq, amplitude=st["amplitude_m_per_s"],
                              amplitude_quantity="velocity"),
        notes="stepped sine; nominal amplitude is the commanded base velocity")
    measurement = SteppedSineMeasurement(
        time=np.arange(count) / SHAKER_RATE_HZ,
        v_base=_sensor(base_v[::SHAKER_SUBSTEPS][window], NOISE["shaker_velocity"],
                       RESOLUTION["velocity"], rng),
        v_top=_sensor(run.velocity[0][window], NOISE["shaker_velocity"], RESOLUTION["velocity"], rng),
        x_base=_sensor(base_x[::SHAKER_SUBSTEPS][window], NOISE["shaker_position"],
                       RESOLUTION["position"], rng),
        u_in=_sensor(drive[window], NOISE["shaker_voltage"], RESOLUTION["voltage"], rng),
        info=info)
    truth = {"base_first_harmonic_m_per_s": amplitude, "ratio_2nd": ratio_2, "ratio_3rd": ratio_3,
             "settle_s": settle, "periods_recorded": periods}
    return measurement, truth


DROP_SUBSTEPS = 25  # integration at 50 kHz, recorded at 2 kHz
DROP_AFTER_S = 0.35
DROP_BEFORE_S = 0.04


def _drop(item, rng, wire_rope, elastomer):
    st = item.settings
    isolator = item.set_name
    extra, links = _links(isolator, wire_rope, elastomer)
    top = st["top_mass_kg"] + (elastomer.moving_mass_kg if isolator != "wire_rope" else 0.0)
    masses = [top] + extra
    if isolator == "hybrid":
        masses.append(st["intermediate_mass_kg"])
    masses.append(st["bottom_mass_kg"])
    masses = np.asarray(masses)
    height = st["drop_height_m"] * (1.0 + 0.02 * rng.standard_normal())  # release scatter
    # held at rest by the bottom mass, isolator(s) statically loaded by the masses above
    above, states, _ = _static_chain(masses[:-1], links, height)
    x0 = np.append(above, height)
    dt = 1.0 / (DROP_RATE_HZ * DROP_SUBSTEPS)
    fall = math.sqrt(2 * height / GRAVITY)
    n_steps = int(math.ceil((fall + DROP_AFTER_S) / dt / DROP_SUBSTEPS)) * DROP_SUBSTEPS
    run = run_chain(masses, links, time_step=dt, n_steps=n_steps, x0=x0, v0=np.zeros(masses.size),
                    state0=states, gravity=GRAVITY, floor=True,
                    k_contact=CONTACT["stiffness_N_per_m"], c_contact=CONTACT["damping_N_s_per_m"],
                    record_every=DROP_SUBSTEPS)
    contact_index = int(np.flatnonzero(run.contact > 0)[0])
    first = max(0, contact_index - int(round(DROP_BEFORE_S * DROP_RATE_HZ)))
    window = slice(first, None)
    deflection = (run.position[0] - run.position[-1])[window]
    v_rel = (run.velocity[0] - run.velocity[-1])[window]
    accel = run.acceleration[0][window]
    gains = 1.0 + 0.01 * rng.standard_normal(2)
    sigma_a = NOISE["drop_acceleration"]
    count = deflection.size
    info = MeasurementInfo(
        id=item.id, isolator=isolator, top_mass_kg=st["top_mass_kg"],
        intermediate_mass_kg=st.get("intermediate_mass_kg"), bottom_mass_kg=st["bottom_mass_kg"],
        drop_height_m=st["drop_height_m"], repetition=st["repetition"], split=item.split,
        sample_rate_hz=DROP_RATE_HZ,
        notes="accelerometers zeroed at rest before release (kinematic acceleration, up positive)")
    measurement = DropMeasurement(
        time=np.arange(count) / DROP_RATE_HZ,
        deflection=_sensor(deflection, NOISE["drop_deflection"], RESOLUTION["deflection"], rng),
        a_top_1=_sensor(gains[0] * accel, sigma_a, RESOLUTION["acceleration"], rng),
        a_top_2=_sensor(gains[1] * accel, sigma_a, RESOLUTION["acceleration"], rng),
        v_rel=_sensor(v_rel, NOISE["drop_velocity"], RESOLUTION["velocity"], rng), info=info)
    after = slice(contact_index, None)
    lift = np.flatnonzero(run.contact[after] == 0)
    relative = run.position[0] - run.position[-1]
    truth = {
        "actual_drop_height_m": height,
        "impact_velocity_bottom_m_per_s": float(run.velocity[-1][contact_index - 1]),
        "impact_time_in_record_s": (contact_index - first) / DROP_RATE_HZ,
        "peak_acceleration_m_per_s2": float(np.abs(run.acceleration[0][after]).max()),
        "max_compression_m": float(-relative[after].min()),
        "max_tension_m": float(max(relative[after].max(), 0.0)),
        "bottom_mass_lifted_off": bool(lift.size > 0),
        "accelerometer_gains": gains.tolist(),
        "masses_kg_top_first": masses.tolist(),
    }
    return measurement, truth


def realize(item: Planned, *, seed: int, wire_rope, elastomer, quick: bool = False):
    """Generate one planned measurement.

    Returns
    -------
    (Measurement, dict)
        The measurement (SI, noisy, rounded) and its truth record.
    """
    rng = _rng(seed, item.stream)
    if item.kind == "quasi_static":
        measurement, truth = _quasi_static(item, rng, wire_rope, elastomer)
    elif item.kind == "white_noise":
        measurement, truth = _white_noise(item, rng, wire_rope, elastomer)
    elif item.kind == "stepped_sine":
        measurement, truth = _stepped_sine(item, rng, wire_rope, elastomer, quick)
    else:
        measurement, truth = _drop(item, rng, wire_rope, elastomer)
    truth["seed"] = [int(seed), zlib.crc32(item.stream.encode())]
    return measurement, truth

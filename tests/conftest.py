"""Shared fixtures: locations resolved from this file, never the working directory."""

import os
import sys
from importlib import metadata
from pathlib import Path

import pytest

# headless backend for the tests, set before anything imports matplotlib (idkit never chooses one)
os.environ.setdefault("MPLBACKEND", "Agg")

REPO_ROOT = Path(__file__).resolve().parents[1]

# distributions whose versions explain a red run (printed in the pytest header)
REPORTED_PACKAGES = ("numpy", "scipy", "pandas", "numba", "llvmlite", "nlopt", "lmfit", "matplotlib",
                     "hypothesis")
HYPOTHESIS_PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "ci")


def _register_hypothesis_profiles() -> None:
    """Profiles: "ci" (default) derandomized, no deadline; "dev" random (HYPOTHESIS_PROFILE=dev).

    A test's own ``@settings(...)`` overrides only the fields it names; the rest come from
    the loaded profile, so every property test is reproducible under "ci".
    """
    try:
        from hypothesis import settings
    except ImportError:  # hypothesis is a test dependency; its tests skip or fail on their own
        return
    settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
    settings.register_profile("dev", derandomize=False, deadline=None, print_blob=True)
    settings.load_profile(HYPOTHESIS_PROFILE)


_register_hypothesis_profiles()


def _distribution_version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


def _numpy_cpu_features() -> str:
    """numpy's compiled-in baseline and the dispatched features this CPU runs (found, not disabled)."""
    try:
        from numpy._core import _multiarray_umath as umath
    except ImportError:
        try:  # numpy < 2
            from numpy.core import _multiarray_umath as umath
        except ImportError:
            return "unknown"
    found = getattr(umath, "__cpu_features__", {})
    baseline = [name for name in getattr(umath, "__cpu_baseline__", []) if found.get(name)]
    dispatch = [name for name in getattr(umath, "__cpu_dispatch__", []) if found.get(name)]
    return f"baseline {' '.join(baseline) or 'none'}; dispatch {' '.join(dispatch) or 'none'}"


def pytest_report_header(config):
    """Package versions and numpy's CPU features, so a red CI log explains itself."""
    python = f"python {sys.version.split()[0]} ({sys.platform})"
    versions = ", ".join(f"{name} {_distribution_version(name)}" for name in REPORTED_PACKAGES)
    lines = [f"idkit test environment: {python}", f"packages: {versions}",
             f"numpy cpu features in use: {_numpy_cpu_features()}"]
    disabled = os.environ.get("NPY_DISABLE_CPU_FEATURES")
    if disabled:
        lines.append(f"NPY_DISABLE_CPU_FEATURES={disabled}")
    lines.append(f"hypothesis profile: {HYPOTHESIS_PROFILE} (HYPOTHESIS_PROFILE=dev explores at random)")
    return lines


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT

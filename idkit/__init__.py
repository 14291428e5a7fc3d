"""idkit: identification and validation of vibration/shock isolator models.

Deflection is positive in tension; all quantities are SI. See README.md.
"""

from importlib.metadata import PackageNotFoundError, version

# the distribution on PyPI ("idkit" there is an unrelated project); the import name stays idkit
DISTRIBUTION_NAME = "idkit-isolators"

try:
    __version__ = version(DISTRIBUTION_NAME)
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["DISTRIBUTION_NAME", "__version__"]

"""idkit: identification and validation of vibration/shock isolator models.

Deflection is positive in tension; all quantities are SI. See README.md.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("idkit")
except PackageNotFoundError:  # running from a source tree that was not installed
    __version__ = "0+unknown"

__all__ = ["__version__"]

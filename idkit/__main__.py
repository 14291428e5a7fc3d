"""``python -m idkit`` runs the command-line interface."""

import sys

from idkit.cli.main import run

sys.exit(run())

"""Isolator models and systems (SPEC 1-2).

Isolators map a deflection history (m, positive = tension) to a force (N):
:class:`IwanModel` (wire rope), :class:`ModulatedIwanModel` (wire rope whose
slip forces follow the deflection), :class:`ClearanceIwanModel` (friction elements acting through a
clearance), :class:`RateDependentIwanModel` (slip forces rising with speed), :class:`BoucWenModel`,
:class:`PinchedBoucWenModel`, :class:`GeneralizedMaxwell`
and :class:`VoigtModel` (elastomer). Systems: :class:`SDOFSystem`,
:class:`HybridSystem`, :class:`CoulombSpringSystem`. Named parameter sets of the
study: :mod:`idkit.models.library`. Model files: :func:`save_model`, :func:`load_model`.
"""

from idkit.models import library
from idkit.models.base import IsolatorArrays, IsolatorModel
from idkit.models.boucwen import BoucWenModel
from idkit.models.boucwen_pinched import PinchedBoucWenModel
from idkit.models.clearance import ClearanceIwanModel
from idkit.models.iwan import IwanModel, jenkin_force
from idkit.models.iwan_modulated import ModulatedIwanModel
from idkit.models.maxwell import GeneralizedMaxwell, VoigtModel
from idkit.models.rate_dependent import RateDependentIwanModel
from idkit.models.modelfile import load_model, load_model_document, save_model
from idkit.models.systems import CoulombSpringSystem, HybridSystem, SDOFSystem

__all__ = [
    "IsolatorModel", "IsolatorArrays", "IwanModel", "ModulatedIwanModel", "ClearanceIwanModel", "RateDependentIwanModel",
    "jenkin_force", "BoucWenModel", "PinchedBoucWenModel",
    "GeneralizedMaxwell", "VoigtModel", "SDOFSystem", "HybridSystem", "CoulombSpringSystem",
    "library", "save_model", "load_model", "load_model_document",
]

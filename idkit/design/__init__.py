"""The design tool: choose and tune isolators for a payload, a floor and the drops it must survive.

Candidates (:func:`make_candidates`: catalogue parts, measured or predicted from the scaling
laws, times mount counts, single or hybrid pairs) are evaluated with the batched simulator
under parameter draws from each part's covariance (:func:`evaluate_candidates`), judged
against the environment's limits (:func:`judge`: margins, probabilities, verdicts, Pareto
front) and the best re-simulated in full (:func:`run_design`). ``docs/design.md``.
"""

from idkit.design.candidates import Candidate, DesignPart, draw_models, make_candidates, parts_from_catalogue, predicted_part
from idkit.design.environment import Environment, load_environment
from idkit.design.evaluation import METRICS, evaluate_candidate, evaluate_candidates
from idkit.design.ranking import judge, pareto_front
from idkit.design.run import DesignResult, run_design

__all__ = ["METRICS", "Candidate", "DesignPart", "DesignResult", "Environment", "draw_models", "evaluate_candidate",
           "evaluate_candidates", "judge", "load_environment", "make_candidates", "pareto_front",
           "parts_from_catalogue", "predicted_part", "run_design"]

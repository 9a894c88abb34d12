"""The weighing the report job does before it writes the page: the paper's weighted table of the engines
(with the answer and the ranking's interval over real runs where the study has real data of its robot) and
of the simulators, from the weight-free scores.

The weights reach only this step and the page, so a weight edit reruns one job: the weighing used to be jobs
of its own (rules answer or weighted, and simulator_scores) one level before the report, each a process
start and a scheduling step on the path a user waits for. Its tables stay where they were
(results/scores/, results/verdict/, results/simulators/), written by the report job as its outputs before it
reads them like any input.
"""

from __future__ import annotations

from collections.abc import Mapping

from pydantic import Field

from simpick.params import JobParams
from simpick.score.answer import AnswerParams
from simpick.score.simulators import SimulatorScoresParams

# the report job's outputs the weighing writes -> the key the report reads each under (simpick.report.load)
READ_AS = {
    "weighted": "weighted",
    "contributions": "contributions",
    "drivers": "drivers",
    "ranking": "verdict_ranking",
    "separation": "verdict_separation",
    "answer": "verdict_answer",
    "answer_yaml": "verdict_sentences",
    "headline": "verdict_headline",
}
# the prefix of the weighing's inputs among the report job's (they are not the page's inputs)
PREFIX = "weighing_"


class WeighingParams(JobParams):
    """What the weighing reads: the answer's settings (weights included) where the study has an answer, else
    the weights alone; the simulators' scoring where the study runs simulator profiles."""

    answer: AnswerParams | None = Field(None, description="rule report's answer (None: no real data of the robot)")
    weights: dict[str, float] = Field(description="the paper's metric weights (config weights)")
    simulators: SimulatorScoresParams | None = Field(None, description="None: the study runs no simulator")


def weigh(inputs: Mapping[str, str], params: Mapping, outputs: Mapping[str, str]) -> dict[str, str]:
    """Write the weighing's tables into ``outputs`` (the report job's) from ``inputs`` (the report job's
    inputs named with :data:`PREFIX`); returns the report's inputs they become (:data:`READ_AS`)."""
    p = WeighingParams.model_validate(params)
    own = {k.removeprefix(PREFIX): v for k, v in inputs.items() if k.startswith(PREFIX)}
    if p.answer is not None:
        from simpick.score.answer import answer_job

        answer_job(own, p.answer.model_dump(mode="json"), dict(outputs))
    else:
        from simpick.score.jobs import weighted_job

        weighted_job(own["scores"], dict(p.weights), dict(outputs))
    if p.simulators is not None:
        from simpick.score.simulators import simulator_scores_job

        simulator_scores_job(
            own["simulator_subjects"],
            p.simulators.model_dump(mode="json"),
            {"scores": outputs["simulators_scores"], "weighted": outputs["simulators_weighted"]},
        )
    return {READ_AS[k]: v for k, v in outputs.items() if k in READ_AS}

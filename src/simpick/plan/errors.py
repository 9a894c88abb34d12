"""The one error of planning (:class:`PlanError`): a config the study cannot be planned from.

It stands apart because every part of the plan (its models, its real data, a job's parameters) raises it
and the rules catch it by this one name; a module of its own lets each part import it without importing
the :class:`~simpick.plan.Plan` that gathers them.
"""


class PlanError(ValueError):
    """A config the study cannot be planned from (the rules stop before any job, naming it)."""

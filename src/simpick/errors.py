"""Errors that simpick reports to a user: what was wrong, where, and how to fix it."""


class InputError(ValueError):
    """Bad input (config, data file, terrain). ``where`` names the file and field."""

    def __init__(self, where: str, problem: str, fix: str | None = None):
        self.where, self.problem, self.fix = where, problem, fix
        message = f"{where}: {problem}"
        if fix:
            message += f" (fix: {fix})"
        super().__init__(message)


class SimulationFailure(RuntimeError):
    """A simulation that diverged or misbehaved; carries the reason for the health record."""

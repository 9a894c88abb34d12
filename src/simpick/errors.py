"""Errors that simpick reports to a user: what was wrong, where, and how to fix it."""


class InputError(ValueError):
    """Bad input (config, data file, terrain). ``where`` names the file and field."""

    def __init__(self, where: str, problem: str, fix: str | None = None):
        self.where, self.problem, self.fix = where, problem, fix
        message = f"{where}: {problem}"
        if fix:
            message += f" (fix: {fix})"
        super().__init__(message)


def validation_problems(exc, prefix: tuple = ()) -> list[tuple[str, str]]:
    """(key, problem) for each error of a pydantic ValidationError: the dotted key under
    ``prefix``, pydantic's message (what is allowed) and the value that broke it."""
    found = []
    for err in exc.errors():
        key = ".".join(str(p) for p in (*prefix, *err["loc"])) or "(top level)"
        value = err.get("input")
        shown = "" if isinstance(value, dict) else f" (got {value!r})"
        found.append((key, err["msg"].removeprefix("Value error, ") + shown))
    return found


class SimulationFailure(RuntimeError):
    """A simulation that diverged or misbehaved; carries the reason for the health record."""

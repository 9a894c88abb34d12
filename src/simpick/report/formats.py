"""How a figure reads in the report: the Jinja filters of its templates (numbers in a fixed number of
decimals or significant figures, signs, yes/no, a missing value as a dash)."""

from __future__ import annotations

import math
from typing import Any


def isnan(x: Any) -> bool:
    if x is None:
        return True
    try:
        return math.isnan(float(x))
    except (TypeError, ValueError):
        return False


def fmt(x: Any, digits: int = 3) -> str:
    """A number with ``digits`` decimals; very small non-zero values in 3 significant figures."""
    if isnan(x):
        return "–"
    try:
        v = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"
    if digits >= 3 and v != 0 and abs(v) < 0.5 * 10 ** (-digits):
        return f"{v:.2e}".replace("-", "−")
    s = f"{v:.{digits}f}"
    if s.startswith("-"):
        s = "−" + s[1:]
    return "0." + "0" * digits if s == "−0." + "0" * digits else s


def fmt_num(x: Any) -> str:
    """A weight or other round figure: no decimals when it is a whole number."""
    if isnan(x):
        return "–"
    v = float(x)
    return f"{v:.0f}" if v == round(v) else fmt(v, 2)


def fmt_sig(x: Any) -> str:
    """A measurement spanning orders of magnitude (a real-time factor): 3 significant figures."""
    if isnan(x):
        return "–"
    v = float(x)
    return f"{v:.3g}" if abs(v) < 1000 else f"{v:,.0f}".replace(",", "\u2009")


def fmt_int(x: Any) -> str:
    if isnan(x):
        return "–"
    return f"{int(round(float(x))):,}".replace(",", "\u2009")


def fmt_signed(x: Any, digits: int = 3) -> str:
    s = fmt(x, digits)
    if s not in ("–",) and not s.startswith("−") and float(x) != 0:
        s = "+" + s
    return s


def fmt_yes_no(x: Any) -> str:
    if isinstance(x, bool):
        return "yes" if x else "no"
    return "–" if x is None else str(x)


def soft_lower(text: str) -> str:
    """Lower-case the first letter unless the first word is an acronym (IMU, UI, ROS)."""
    if len(text) > 1 and text[0].isupper() and text[1].islower():
        return text[0].lower() + text[1:]
    return text

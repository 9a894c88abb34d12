"""What every simulator format's writer shares: the numbers' and comments' text, the catalog's meaning of a
setting beside its value, the XML serialisation, and the ground's friction coefficient the files state."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping

# the ground's friction coefficient the files state where a simulator needs it beside the robot's (a MuJoCo
# pair's friction, Webots' coulombFriction, Gazebo's mu under an anisotropic mu2): the validation's hard ground
GROUND_MU = 0.8


def _num(x) -> str:
    return f"{float(x):.6g}"


def _header(comment: str, lines: list[str]) -> str:
    return "\n".join(f"{comment} {line}".rstrip() for line in lines) + "\n"


def xml_comment(lines: list[str]) -> str:
    """The header as XML comments. XML forbids ``--`` inside a comment (XML 1.0, production [15]) and a comment
    ending in ``-``: a long option such as ``--configfile`` is written ``- -configfile`` there, so strict
    parsers, xacro and sdformat read the file; the command itself is given in full in the non-XML files."""
    out = []
    for line in lines:
        text = str(line)
        while "--" in text:
            text = text.replace("--", "- -")
        if text.endswith("-"):
            text += " "
        out.append(f"<!-- {text} -->".replace("<!--  -->", "<!-- -->"))
    return "\n".join(out) + "\n"


def _written(value) -> str:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return repr(value)
    return _num(value)


def _same(a, b) -> bool:
    try:
        return abs(float(a) - float(b)) <= 1e-9 * max(1.0, abs(float(b)))
    except (TypeError, ValueError):
        return a == b


def _meaning(entries: Mapping | None, key: str, settings: Mapping | None = None, name: str | None = None) -> str | None:
    """A header line for the setting ``key``: its value, its source and the catalog's note.

    The value is what the file is written from (``settings``, the profile's full settings, where given): a fitted
    value differs from the catalog's, and the catalog's is then named beside it as the profile's start, so that a
    header never states a value the file does not hold. ``name``: the file's own name for the setting where it is
    not the adapter's (Drake's YAML keys, say)."""
    if not entries or key not in entries:
        return None
    variant, s = entries[key]
    label = name or key
    held = settings.get(key) if settings is not None else None
    if held is not None and not _same(held, s.value):
        value = f"{_written(held)} (written; the {variant} profile's catalog value is {s.value!r})"
    else:
        value = f"{repr(s.value) if held is None else _written(held)} ({variant})"
    bits = [f"{label} = {value}", f"source: {s.source}"]
    if s.note:
        bits.append(s.note)
    return "; ".join(bits)


def _meanings(
    entries: Mapping | None, keys, settings: Mapping | None = None, names: Mapping[str, str] | None = None
) -> list[str]:
    names = names or {}
    return [m for m in (_meaning(entries, k, settings, names.get(k)) for k in keys) if m]


def _tostring(root) -> str:
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")

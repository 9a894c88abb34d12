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


def _meaning(entries: Mapping | None, key: str) -> str | None:
    if not entries or key not in entries:
        return None
    variant, s = entries[key]
    bits = [f"{key} = {s.value!r} ({variant})", f"source: {s.source}"]
    if s.note:
        bits.append(s.note)
    return "; ".join(bits)


def _meanings(entries: Mapping | None, keys) -> list[str]:
    return [m for m in (_meaning(entries, k) for k in keys) if m]


def _tostring(root) -> str:
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")

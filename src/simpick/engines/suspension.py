"""Passive suspension for the adapters that load the robot through their engine's URDF parser.

A suspended robot's couplings (:attr:`simpick.inputs.robot.RobotSpec.couplings`) come from the
description's ``<mimic>`` elements or from the config's ``robot.couplings``; some engines' URDF
parsers read ``<mimic>`` themselves (DART's loader makes the follower a MIMIC joint, Drake's parser
adds a coupler constraint) and some ignore it. So that every coupling is applied exactly once, and
only those the spec names (the config may add one, a test may take them away), an adapter loads
:func:`coupled_urdf`: the robot's file with its ``<mimic>`` elements replaced by the spec's couplings.
An engine that reads ``<mimic>`` then applies each coupling once, natively; one that does not reads
the file as before and the adapter adds its own constraint from the spec.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from simpick.inputs.robot import RobotSpec
from simpick.inputs.urdf import write_cached


def _mimic_of(root: ET.Element) -> dict[str, tuple[str, float, float]]:
    found = {}
    for joint in root.iter("joint"):
        mimic = joint.find("mimic")
        if mimic is not None:
            found[joint.get("name")] = (
                mimic.get("joint", ""),
                float(mimic.get("multiplier", "1")),
                float(mimic.get("offset", "0")),
            )
    return found


def coupled_urdf(robot: RobotSpec) -> Path:
    """``robot.urdf`` itself when its ``<mimic>`` elements are exactly ``robot.couplings``, else a copy
    (in the temporary folder, named by its content) whose ``<mimic>`` elements are; the file is never
    rewritten for a robot without suspension."""
    if not robot.suspension and not robot.couplings:
        return robot.urdf
    root = ET.parse(robot.urdf).getroot()
    wanted = {c.joint: (c.leader, float(c.multiplier), float(c.offset)) for c in robot.couplings}
    if _mimic_of(root) == wanted:
        return robot.urdf
    for joint in root.iter("joint"):
        for mimic in joint.findall("mimic"):
            joint.remove(mimic)
        coupling = wanted.get(joint.get("name"))
        if coupling is not None:
            leader, multiplier, offset = coupling
            ET.SubElement(joint, "mimic", joint=leader, multiplier=repr(multiplier), offset=repr(offset))
    return write_cached(ET.tostring(root, encoding="unicode"))


__all__ = ["coupled_urdf"]

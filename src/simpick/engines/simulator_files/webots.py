"""Webots: a WorldInfo node with its ContactProperties (a .wbt fragment), and its reader."""

from __future__ import annotations

import re
from collections.abc import Mapping

from simpick.engines.simulator_files.common import GROUND_MU, _header, _meanings, _num

WEBOTS_FIELDS = {  # ContactProperties field -> adapter setting
    "forceDependentSlip": "contact_slip",
    "softERP": "contact_soft_erp",
    "softCFM": "contact_soft_cfm",
    "bounce": "contact_bounce",
    "bounceVelocity": "contact_bounce_vel",
    "maxContactJoints": "max_contacts",
}


# Which of two coulombFriction values acts along which way of a wheel, read in Webots' source (cyberbotics/webots
# eee8e098 src/webots/engine/WbSimulationCluster.cpp, WbSimulationCluster::fillSurfaceParameters; 927d975a
# src/webots/nodes/WbCylinder.cpp): ODE's first friction direction (contact->fdir1, along which ODE bounds the force
# by surface.mu; mu2 across it) is the first friction direction of material1's geometry (:235-236, :262-268, :283-289),
# and a Cylinder's is, on its side, its own axis (WbCylinder::computeFrictionDirection, :549-556: "else  // side
# return WbVector3(0, 0, 1)"; the top and bottom faces are those with the normal along z, so z is the axis). With
# three values the first solid (material1) takes the first two and the other a symmetric third: mu = [0] + [2] along
# fdir1, mu2 = [1] + [2] across it (:303-305, :315-317). With two, both solids take both values, summed in
# proportions set by the angle between their directions (:306-308), so a wheel's ratio would change with the robot's
# heading on a ground whose directions are fixed. Hence material1 "wheel" and three values [lateral, longitudinal, 0]:
# the first along the wheel Cylinder's axis (the axle, across the wheel), the second along its rolling direction.
# Webots uses them only where both geometries have friction directions, the ground a Box, a Plane or a Cylinder
# (:270-275; docs/reference/contactproperties.md:56), else the first value alone, symmetric.
WEBOTS_FRICTION_SOURCE = (
    "cyberbotics/webots eee8e098 src/webots/engine/WbSimulationCluster.cpp:262-268, 283-289, 303-305, 315-317 and "
    "927d975a "
    "src/webots/nodes/WbCylinder.cpp:549-556"
)


def contact_properties(
    settings: Mapping, ground_mu: float, material1: str = "wheel", wheel_directions: bool = False
) -> list[str]:
    """The lines of the ContactProperties node of ``material1`` against the ground's "default" (unindented; the
    values after ``#`` are comments): the ground's coefficient, once (symmetric) or, where the profile sets a
    friction ratio or ``wheel_directions`` asks for the friction pyramid turned with the wheel, three times
    [across the wheel, along it, the ground's share 0] on material1's Cylinder (:data:`WEBOTS_FRICTION_SOURCE`),
    and the fields of :data:`WEBOTS_FIELDS` the profile sets."""
    ratio = float(settings.get("friction_ratio") or 1.0)
    lines = [
        "ContactProperties {",
        f'  material1 "{material1}"  # the wheels\' contactMaterial; material2 stays "default", the ground\'s'
        if material1 == "wheel"
        else f'  material1 "{material1}"',
    ]
    if ratio == 1.0 and not wheel_directions:
        lines.append(
            f"  coulombFriction [ {_num(ground_mu)} ]  # the ground's coefficient (simpick's validation: {ground_mu:g})"
        )
    else:
        lines += [
            f"  coulombFriction [ {_num(ratio * ground_mu)} {_num(ground_mu)} 0 ]  # across the wheel (along its "
            f"Cylinder's axis: friction_ratio {_num(ratio)} x the ground's {ground_mu:g}), along its rolling direction "
            "(the ground's), the ground's own share 0: material1's first friction direction on a Cylinder's side is "
            f"its axis ({WEBOTS_FRICTION_SOURCE}); the ground a Box, a Plane or a Cylinder, else Webots applies the "
            "first value alone",
            "  frictionRotation 0 0  # the first direction left on the wheel's axis",
        ]
    for field, key in WEBOTS_FIELDS.items():
        value = settings.get(key)
        if value is None:  # not set: Webots' own default holds
            continue
        text = (
            f"[ {_num(value)} ]"
            if field == "forceDependentSlip"
            else (str(int(value)) if field == "maxContactJoints" else _num(value))
        )
        lines.append(f"  {field} {text}")
    return [*lines, "}"]


def write_webots(settings: Mapping, entries: Mapping | None, title: list[str], ground_mu: float = GROUND_MU) -> dict:
    notes = _meanings(entries, ("cfm", "erp", "friction_ratio", *WEBOTS_FIELDS.values()), settings)
    ratio = float(settings.get("friction_ratio") or 1.0)
    lines = [
        "WorldInfo {",
        "  basicTimeStep 1  # ms: the step simpick ran (Webots' default is 32)",
        f"  CFM {_num(settings['cfm'])}",
        f"  ERP {_num(settings['erp'])}",
        "  contactProperties [",
        *("    " + line for line in contact_properties(settings, ground_mu)),
        "  ]",
        "}",
    ]
    if ratio != 1.0:
        # where the anisotropy holds, in the header's first lines: Webots takes a contact's first friction direction
        # from the geometry in contact (WbSimulationCluster.cpp), and only a Box, a Plane or a Cylinder gives one
        notes.insert(
            0,
            "ASSUMES the ground the wheels touch is a Box, a Plane or a Cylinder: on an ElevationGrid or a Mesh "
            f"Webots finds no friction direction and applies the first value ({_num(ratio * ground_mu)}, across the "
            "wheel) in every direction, so the wheels turn as with isotropic friction of that value "
            f"({WEBOTS_FRICTION_SOURCE})",
        )
    return {"wbt": _header("#", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_webots(text: str) -> dict:
    body = re.sub(r"#.*", "", text)
    out = {
        "cfm": float(re.search(r"\bCFM\s+(\S+)", body).group(1)),
        "erp": float(re.search(r"\bERP\s+(\S+)", body).group(1)),
    }
    for field, key in WEBOTS_FIELDS.items():
        m = re.search(rf"\b{field}\s+\[?\s*([-+\d.eE]+)", body)
        if m:
            out[key] = int(m.group(1)) if key == "max_contacts" else float(m.group(1))
    friction = re.search(r"coulombFriction\s+\[([^\]]*)\]", body).group(1).split()
    if len(friction) == 3:  # [across the wheel, along it, 0]: write_webots
        out["friction_ratio"] = float(friction[0]) / float(friction[1])
    return out

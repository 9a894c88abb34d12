"""MuJoCo: an MJCF file with the ``<option>`` and the wheel x ground ``<pair>`` elements, and its reader."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping

from simpick.engines.simulator_files.common import GROUND_MU, _meanings, _num, _tostring, xml_comment

MUJOCO_TIMECONST, MUJOCO_DMAX = 0.02, 0.95  # the adapter's (simpick.engines.mujoco_engine)


def write_mjcf(
    settings: Mapping, entries: Mapping | None, title: list[str], wheels: list[str], ground_mu: float = GROUND_MU
) -> dict[str, str]:
    """An MJCF with the profile's <option> and, under the adapter's "decoupled" wheel contact, one <pair> per
    wheel geom and the ground (geom1 "floor"), as simpick.engines.mujoco_engine builds them: the pair's friction
    is the ground's coefficient (a pair replaces the geoms' own friction mix), along the axle x friction_ratio."""
    root = ET.Element("mujoco", model="simpick settings")
    option = ET.SubElement(
        root,
        "option",
        integrator={"euler": "Euler", "rk4": "RK4"}.get(settings["integrator"], settings["integrator"]),
        cone=settings["cone"],
        iterations=str(int(settings["solver_iterations"])),
    )
    ratio = float(settings.get("friction_ratio") or 1.0)
    if settings["wheel_contact"] == "decoupled":
        d, df = settings["wheel_contact_impedance"], settings["wheel_friction_impedance"]
        option.set("impratio", _num(((1 - d) / d) / ((1 - df) / df)))
        contact = ET.SubElement(root, "contact")
        for wheel in wheels:
            ET.SubElement(
                contact,
                "pair",
                geom1="floor",
                geom2=wheel,
                condim="3",
                # tangent 1, tangent 2, spin, roll, roll: the adapter's (condim 3 uses the first two)
                friction=f"{_num(ratio * ground_mu)} {_num(ground_mu)} 0 0 0",
                solimp=f"{_num(d)} {_num(d)} 0.001 0.5 2",
                solref=f"{MUJOCO_TIMECONST} 1",
                solreffriction=f"{_num(MUJOCO_TIMECONST * MUJOCO_DMAX / d)} 1",
            )
    notes = _meanings(entries, ("integrator", "cone", "solver_iterations", "wheel_contact", "friction_ratio"), settings)
    notes.append(
        f"pairs: geom2 names the robot's wheel geoms, geom1 the ground; friction: the ground's coefficient "
        f"({ground_mu:g} here; one set of pairs per ground surface)"
    )
    if ratio != 1.0:
        notes.append(
            "friction_ratio: the first tangent (axle) gets ratio x mu; MuJoCo orients a capsule's contact frame "
            "along its axis but a cylinder's with the world, so the wheel geoms are capsules (type capsule)"
        )
    return {"xml": xml_comment([*title, *notes]) + _tostring(root) + "\n"}


def read_mjcf(text: str) -> dict:
    root = ET.fromstring(text)
    option = root.find("option")
    out = {
        "integrator": option.get("integrator").lower(),
        "cone": option.get("cone"),
        "solver_iterations": int(option.get("iterations")),
    }
    pairs = root.findall("contact/pair")
    out["wheel_contact"] = "decoupled" if pairs else "default"
    if pairs:
        d = float(pairs[0].get("solimp").split()[0])
        out["wheel_contact_impedance"] = d
        ratio = float(option.get("impratio"))
        q = ((1 - d) / d) / ratio  # (1 - df) / df
        out["wheel_friction_impedance"] = 1.0 / (1.0 + q)
        t1, t2 = (float(x) for x in pairs[0].get("friction").split()[:2])
        if t1 != t2:
            out["friction_ratio"] = t1 / t2
    return out

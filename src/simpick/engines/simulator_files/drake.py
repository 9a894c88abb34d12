"""Drake: a MultibodyPlantConfig YAML and the wheels' ``drake:`` proximity tags, and their reader."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping

from simpick.engines.simulator_files.common import _header, _meanings, _num, _tostring, xml_comment


def write_drake(settings: Mapping, entries: Mapping | None, title: list[str]) -> dict[str, str]:
    model = "hydroelastic_with_fallback" if settings["contact_model"] == "hydroelastic" else "point"
    lines = [
        f"time_step: {_num(settings.get('time_step') or 0.001)}",
        f"contact_model: {model}",
        f"discrete_contact_approximation: {settings['discrete_approximation']}",
        f"stiction_tolerance: {_num(settings['stiction_tolerance'])}",
    ]
    # under Drake's own keys and values (its YAML loader refuses the adapter's names): the header names what the
    # file sets, the adapter's name beside it
    written = {**settings, "contact_model": model}
    names = {"discrete_approximation": "discrete_contact_approximation"}
    notes = _meanings(entries, ("time_step", "discrete_approximation", "stiction_tolerance"), written, names)
    if entries and "contact_model" in entries:
        variant, s = entries["contact_model"]
        notes.insert(
            1,
            f"contact_model = {model!r} (the adapter's contact_model {settings['contact_model']!r}, {variant}); "
            f"source: {s.source}" + (f"; {s.note}" if s.note else ""),
        )
    yaml_text = (
        _header("#", [*title, "MultibodyPlantConfig (pydrake.multibody.plant)", *notes]) + "\n".join(lines) + "\n"
    )
    props = ET.Element("drake:proximity_properties")
    if settings["contact_model"] == "hydroelastic":
        ET.SubElement(props, "drake:compliant_hydroelastic")
        ET.SubElement(props, "drake:hydroelastic_modulus", value=_num(settings["hydroelastic_modulus"]))
        # a compliant cylinder needs its mesh's resolution (Drake refuses the tag set without it); the
        # adapter's: mesh_resolution, at most the wheel's radius / 8 (simpick.engines.drake_engine)
        ET.SubElement(props, "drake:mesh_resolution_hint", value=_num(settings.get("mesh_resolution") or 0.02))
    ET.SubElement(props, "drake:hunt_crossley_dissipation", value=_num(settings["wheel_dissipation"]))
    for key in ("mu_dynamic", "mu_static"):  # Drake's own names, where a profile sets them
        if settings.get(key) is not None:
            ET.SubElement(props, f"drake:{key}", value=_num(settings[key]))
    tag_notes = _meanings(
        entries,
        ("hydroelastic_modulus", "mesh_resolution", "wheel_dissipation", "mu_dynamic", "mu_static"),
        settings,
        {
            "hydroelastic_modulus": "drake:hydroelastic_modulus",
            "mesh_resolution": "drake:mesh_resolution_hint",
            "wheel_dissipation": "drake:hunt_crossley_dissipation",
            "mu_dynamic": "drake:mu_dynamic",
            "mu_static": "drake:mu_static",
        },
    )
    # the wheels' drive: Drake's implicit PD gains on each wheel joint's actuator (p 0: a velocity drive), where a
    # profile sets its damping (the calibrated profile fits it)
    gains = None
    if settings.get("wheel_drive_damping") is not None:
        gains = ET.Element("drake:controller_gains", p="0", d=_num(settings["wheel_drive_damping"]))
        tag_notes += _meanings(
            entries, ("wheel_drive_damping",), settings, {"wheel_drive_damping": "drake:controller_gains d"}
        )
    # the fragment alone is not a document (the drake: prefix is declared by the robot's <robot> element):
    # it is given inside a <robot> that declares it, to paste the <drake:proximity_properties> element from
    robot = ET.Element("robot", {"name": "simpick_wheel_tags", "xmlns:drake": "http://drake.mit.edu"})
    robot.append(props)
    paste = ["paste <drake:proximity_properties> inside each wheel's <collision>"]
    if gains is not None:
        robot.append(gains)
        paste.append(
            "and <drake:controller_gains> inside the <actuator> of each wheel joint's <transmission> (type "
            "SimpleTransmission), the joint's <limit effort> its torque bound"
        )
    urdf = xml_comment([*title, *paste, *tag_notes]) + _tostring(robot) + "\n"

    return {"yaml": yaml_text, "wheels.urdf": urdf}


def read_drake(texts: Mapping[str, str]) -> dict:
    import yaml

    # the written file's MultibodyPlantConfig, read back by Drake's own key names (a foreign file, not the study's)
    plant = yaml.safe_load(texts["yaml"])
    out = {
        "time_step": float(plant["time_step"]),
        "discrete_approximation": plant["discrete_contact_approximation"],
        "stiction_tolerance": float(plant["stiction_tolerance"]),
    }
    tags = texts["wheels.urdf"]
    hydro = "drake:compliant_hydroelastic" in tags and plant["contact_model"] != "point"
    out["contact_model"] = "hydroelastic" if hydro else "point"
    if hydro:
        out["hydroelastic_modulus"] = float(re.search(r'hydroelastic_modulus value="([^"]+)"', tags).group(1))
    out["wheel_dissipation"] = float(re.search(r'hunt_crossley_dissipation value="([^"]+)"', tags).group(1))
    m = re.search(r'drake:controller_gains[^>]*\bd="([^"]+)"', tags)
    if m:
        out["wheel_drive_damping"] = float(m.group(1))
    for key in ("mu_dynamic", "mu_static"):
        m = re.search(rf'drake:{key} value="([^"]+)"', tags)
        if m:
            out[key] = float(m.group(1))
    return out

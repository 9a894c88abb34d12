"""Gazebo and Gazebo Classic: the world's ``<physics>`` (an SDF file) and the wheels' ``<gazebo>`` tags (a URDF
fragment to include in the robot's description), and their reader."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping

from simpick.engines.simulator_files.common import GROUND_MU, _meanings, _num, _tostring, xml_comment

# Gazebo Classic combines the two surfaces of a contact (ODEPhysics.cc:1107-1115): kp in series, kd summed; the
# ground keeps the SDF defaults (kp 1e12, kd 1)
GROUND_KP, GROUND_KD = 1.0e12, 1.0
# and sums slip1/slip2 over the surfaces, then multiplies by the pair's contact count (ODEPhysics.cc:1172-1186):
# two contacts per wheel on level ground (ODE's cylinder collider here)
CONTACTS_PER_WHEEL = 2

# sdformat's URDF parser (the one Gazebo Classic 11 and gz-sim read a URDF with) maps only a fixed list of a
# <gazebo reference="link"> tag's children onto the link's collisions: mu1, mu2, fdir1, kp, kd, maxVel, minDepth,
# maxContacts, laserRetro (sdformat 12.3.0 src/parser_urdf.cc:1371-1424, emitted into <surface> at :1832-1876);
# anything else, <slip1>/<slip2> included, is kept as a blob on the <link> (:1529-1530), where no physics
# engine reads it. A <collision> child is copied into every collision of the link, and a <surface> inside it
# replaces the collision's surface (parser_urdf.cc:1291-1331, 1660-1717; the same in sdformat 9, Gazebo
# Classic's, src/parser_urdf.cc:1341, 1646). So the wheels' tags are written as one <collision><surface>
# blob, with the SDF's own element names, which lands each value where Gazebo reads it.

# gz-physics' dartsim plugin (Ignition Physics 5, Fortress) reads mu, mu2, slip1, slip2 and fdir1 of a collision's
# <surface><friction><ode> (dartsim/src/SDFFeatures.cc:813-835 at ignition-physics5_5.1.0), not kp/kd, which the
# file still carries for the other engines that read them.
# SDF surface element (its path under <surface>) -> the settings that give it: named after the SDF element
# (a gz-physics profile) or the ODE adapter's name (Gazebo Classic, whose combination rules the writer undoes)
SURFACE = {
    "friction/ode/mu": ("mu", "surface_mu"),
    "friction/ode/mu2": ("mu2",),
    "friction/ode/fdir1": ("fdir1", "friction_direction"),
    "friction/ode/slip1": ("slip1", "contact_slip"),
    "friction/ode/slip2": ("slip2", "contact_slip"),
    "contact/ode/kp": ("kp", "contact_kp"),
    "contact/ode/kd": ("kd", "contact_kd"),
    "contact/ode/max_vel": ("max_vel", "contact_max_vel"),
    "contact/ode/min_depth": ("min_depth", "contact_min_depth"),
}


def surface_values(engine: str, settings: Mapping, ground_mu: float = GROUND_MU) -> dict[str, str]:
    """{SDF path under <surface>: text} of the wheels' surface a profile sets.

    ``engine`` "ode" (Gazebo Classic): the ODE adapter's settings, whose values are the contact's, turned into
    the wheel's own as Gazebo Classic combines two surfaces (kp in series with the ground's 1e12, kd summed
    with its 1, slip summed and multiplied by the pair's contact count, mu and mu2 by the minimum,
    ODEPhysics.cc:1107-1186). Any other engine (gz-sim through gz-physics): settings named after the SDF
    elements, written as they are; ``friction_ratio`` gives mu2 = ratio x mu. Where only a ratio is set, mu
    is the ground's coefficient ``ground_mu`` (both surfaces' mu combine by the minimum, so the wheel's mu2
    bounds the lateral row only when the wheel's mu is the ground's)."""
    out: dict[str, str] = {}
    ratio = float(settings.get("friction_ratio") or 1.0)
    if engine == "ode":
        mu = settings.get("surface_mu")
        if mu is None and ratio != 1.0:
            mu = ground_mu
        if mu is not None:
            out["friction/ode/mu"] = _num(mu)
            out["friction/ode/mu2"] = _num(mu * ratio)
        if settings.get("friction_direction") == "wheel_x":
            out["friction/ode/fdir1"] = "1 0 0"
        if settings.get("contact_slip", 0.0) > 0:
            slip = settings["contact_slip"] / CONTACTS_PER_WHEEL
            out["friction/ode/slip1"] = out["friction/ode/slip2"] = _num(slip)
        if settings.get("contact_kp") is not None:
            out["contact/ode/kp"] = _num(1.0 / (1.0 / settings["contact_kp"] - 1.0 / GROUND_KP))
            out["contact/ode/kd"] = _num(max(settings.get("contact_kd", 1.0) - GROUND_KD, 0.0))
        if settings.get("contact_max_vel") is not None:
            out["contact/ode/max_vel"] = _num(settings["contact_max_vel"])
        if settings.get("contact_min_depth") is not None:
            out["contact/ode/min_depth"] = _num(settings["contact_min_depth"])
        return out

    # the gz-physics adapter's names (simpick.engines.gzphysics_engine: wheel_mu, wheel_mu2, contact_kp, ...) or the
    # SDF elements' own
    def first(*keys):
        return next((settings[k] for k in keys if settings.get(k) is not None), None)

    mu, mu2 = first("mu", "wheel_mu"), first("mu2", "wheel_mu2")
    if ratio != 1.0:
        # the ratio is the contact's (the gz-physics adapter sets it on the ground's <mu2>): on the wheels it holds
        # only as the ground's coefficient along and ratio x it across, each surface's lower value governing
        # (a profile named after the elements keeps its own <mu>)
        mu, mu2 = (ground_mu if settings.get("mu") is None else settings["mu"]), None
    elif mu is None and mu2 is not None:
        mu = ground_mu
    if mu is not None:
        out["friction/ode/mu"] = _num(mu)
    if mu2 is not None:
        out["friction/ode/mu2"] = _num(mu2)
    elif ratio != 1.0:
        out["friction/ode/mu2"] = _num(mu * ratio)
    fdir1 = settings.get("fdir1")
    if fdir1 is None and settings.get("friction_direction") == "wheel_x":
        fdir1 = "1 0 0"
    fdir1 = {"wheel_x": "1 0 0", "none": None}.get(fdir1, fdir1) if isinstance(fdir1, str) else fdir1
    if fdir1 is not None:
        out["friction/ode/fdir1"] = fdir1 if isinstance(fdir1, str) else " ".join(_num(x) for x in fdir1)
    for key in ("slip1", "slip2", "kp", "kd", "max_vel", "min_depth"):
        value = first(key, f"contact_{key}")
        if value is not None:
            path = next(p for p in SURFACE if p.endswith("/" + key))
            out[path] = _num(value)
    return out


def _surface_element(values: Mapping[str, str]):
    surface = ET.Element("surface")
    for path, text in values.items():
        node = surface
        for part in path.split("/"):
            found = node.find(part)
            node = found if found is not None else ET.SubElement(node, part)
        node.text = text
    return surface


# gz-sim's <physics><dart> children -> settings: gz-sim reads collision_detector and solver/solver_type into its physics
# components (ignition-gazebo6_6.18.0, Fortress, src/SdfEntityCreator.cc:303-315; gz-sim10 :423-439)
DART_PHYSICS = {
    "solver/solver_type": ("solver_type", "lcp_solver"),
    "collision_detector": ("collision_detector",),
}


def write_sdf(
    engine: str,
    settings: Mapping,
    entries: Mapping | None,
    title: list[str],
    wheels: list[str],
    ground_mu: float = GROUND_MU,
) -> dict[str, str]:
    """{suffix: text}: ``world.sdf`` (the <physics> element) and ``wheels.urdf`` (the wheels' <gazebo> tags)."""
    sdf = ET.Element("sdf", version="1.7" if engine == "ode" else "1.9")
    world = ET.SubElement(sdf, "world", name="default")
    physics = ET.SubElement(world, "physics", name="simpick", type="ode" if engine == "ode" else "dart")
    ET.SubElement(physics, "max_step_size").text = "0.001"
    comments = []
    if engine == "ode":
        if settings.get("max_contacts") is not None:
            ET.SubElement(physics, "max_contacts").text = str(int(settings["max_contacts"]))
        ode = ET.SubElement(physics, "ode")
        solver = ET.SubElement(ode, "solver")
        ET.SubElement(solver, "type").text = settings["stepper"]
        ET.SubElement(solver, "iters").text = str(int(settings["quick_iterations"]))
        constraints = ET.SubElement(ode, "constraints")
        for key in ("cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"):
            ET.SubElement(constraints, key).text = _num(settings[key])
        comments += _meanings(
            entries,
            ("stepper", "quick_iterations", "cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"),
            settings,
        )
    else:
        dart = ET.SubElement(physics, "dart")
        for path, keys in DART_PHYSICS.items():
            key = next((k for k in keys if settings.get(k) is not None), None)
            if key is not None:
                node = dart
                for part in path.split("/"):
                    found = node.find(part)
                    node = found if found is not None else ET.SubElement(node, part)
                node.text = str(settings[key])
                comments += _meanings(entries, (key,), settings)
    world_text = xml_comment([*title, *comments]) + _tostring(sdf) + "\n"

    values = surface_values(engine, settings, ground_mu)
    texts = {"world.sdf": world_text}
    if values:
        robot = ET.Element("robot", name="simpick_wheel_tags")
        for link in wheels:
            gazebo = ET.SubElement(robot, "gazebo", reference=link)
            ET.SubElement(gazebo, "collision").append(_surface_element(values))
        keys = [
            "friction_direction",
            "contact_kp",
            "contact_kd",
            "contact_slip",
            "surface_mu",
            "friction_ratio",
            "contact_max_vel",
            "contact_min_depth",
            *[k for keys in SURFACE.values() for k in keys[:1]],
            "wheel_mu",
            "wheel_mu2",
        ]
        if engine != "ode" and float(settings.get("friction_ratio") or 1.0) != 1.0:
            # the ratio is written as the wheels' own <mu>/<mu2> (surface_values): the wheels' other mu settings
            # are not in the file, so the header does not state them
            keys = [k for k in keys if k not in ("wheel_mu", "wheel_mu2", "mu", "mu2")]
        written = ", ".join(f"<{path.rsplit('/', 1)[1]}> {text}" for path, text in values.items())
        notes = [
            "each wheel's <gazebo reference> carries a <collision><surface> that sdformat's URDF parser copies into "
            "every collision of the link (parser_urdf.cc), where Gazebo reads it",
            f"written on each wheel: {written}",
            *_meanings(entries, keys, settings),
        ]
        if engine == "ode":
            notes.append(
                f"kp/kd: the wheel's own values; Gazebo puts them in series with (adds them to) the ground's "
                f"{GROUND_KP:g} / {GROUND_KD:g}. slip1/slip2: the per-contact slip / {CONTACTS_PER_WHEEL} (Gazebo "
                "multiplies by the pair's contact count). mu/mu2 combine with the ground's by the minimum"
                + (
                    f"; mu is the ground's {ground_mu:g} where only a ratio is set"
                    if "friction_ratio" in settings
                    else ""
                )
            )
        texts["wheels.urdf"] = xml_comment([*title, *notes]) + _tostring(robot) + "\n"
    return texts


def read_sdf(engine: str, texts: Mapping[str, str], ground_mu: float = GROUND_MU) -> dict:
    """The adapter settings a world.sdf / wheels.urdf pair sets (the inverse of :func:`write_sdf`)."""
    out: dict = {}
    physics = ET.fromstring(texts["world.sdf"]).find("world/physics")
    surface = None
    if "wheels.urdf" in texts:
        surface = ET.fromstring(texts["wheels.urdf"]).find("gazebo/collision/surface")
    values = {} if surface is None else {p: surface.findtext(p) for p in SURFACE if surface.find(p) is not None}
    if engine == "gzphysics":  # the gz-physics adapter's names (simpick.engines.gzphysics_engine)
        for path, keys in DART_PHYSICS.items():
            if physics.find(f"dart/{path}") is not None:
                out[keys[0]] = physics.findtext(f"dart/{path}")
        names = {"mu": "wheel_mu", "mu2": "wheel_mu2", "kp": "contact_kp", "kd": "contact_kd"}
        for path, text in values.items():
            key = SURFACE[path][0]
            if key == "fdir1":
                out["fdir1"] = "wheel_x" if text.split() == ["1", "0", "0"] else text
            else:
                out[names.get(key, key)] = float(text)
        # a ratio is written as the ground's mu with mu2 = ratio x mu (surface_values); else the wheels' own
        out["friction_ratio"] = 1.0
        if out.get("wheel_mu") == ground_mu and "wheel_mu2" in out and out["wheel_mu2"] != ground_mu:
            out["friction_ratio"] = out.pop("wheel_mu2") / out.pop("wheel_mu")
        return out
    if engine != "ode":
        for path, keys in DART_PHYSICS.items():
            if physics.find(f"dart/{path}") is not None:
                out[keys[-1]] = physics.findtext(f"dart/{path}")
        for path, text in values.items():
            key = SURFACE[path][0]
            out[key] = text if key == "fdir1" else float(text)
        return out
    if physics.find("max_contacts") is not None:
        out["max_contacts"] = int(physics.findtext("max_contacts"))
    out["stepper"] = physics.findtext("ode/solver/type")
    out["quick_iterations"] = int(physics.findtext("ode/solver/iters"))
    for key in ("cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"):
        out[key] = float(physics.findtext(f"ode/constraints/{key}"))
    if surface is None:
        return out
    out["friction_direction"] = "wheel_x" if values.get("friction/ode/fdir1") == "1 0 0" else "plane"
    if "contact/ode/kp" in values:
        out["contact_kp"] = 1.0 / (1.0 / float(values["contact/ode/kp"]) + 1.0 / GROUND_KP)
        out["contact_kd"] = float(values["contact/ode/kd"]) + GROUND_KD
    if "friction/ode/slip1" in values:
        out["contact_slip"] = float(values["friction/ode/slip1"]) * CONTACTS_PER_WHEEL
    if "friction/ode/mu" in values:
        mu, mu2 = float(values["friction/ode/mu"]), float(values["friction/ode/mu2"])
        if mu != ground_mu:
            out["surface_mu"] = mu
        if mu2 != mu:
            out["friction_ratio"] = mu2 / mu
    if "contact/ode/max_vel" in values:
        out["contact_max_vel"] = float(values["contact/ode/max_vel"])
    if "contact/ode/min_depth" in values:
        out["contact_min_depth"] = float(values["contact/ode/min_depth"])
    return out

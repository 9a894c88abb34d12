"""The settings to paste: a simulator's profile written in that simulator's own format, and read back.

Each format has a writer (adapter settings -> the text a user pastes, every value with its meaning, its source
and the figure it gave here; :func:`write_profile_file` is the entry point) and a reader (that text -> the adapter
settings it sets), so a test can load a written file into simpick's engines and check it reproduces the profile.
tests/test_simulator_files.py reads every file with the simulator's own reader where one installs here
(sdformat, MuJoCo, Drake, Newton, Genesis) and checks the names of the others against
:mod:`simpick.engines.simulator_names`. Formats:

* ``sdf``: Gazebo and Gazebo Classic: the world's ``<physics>`` (an SDF file) and the wheels' ``<gazebo>`` tags
  (a URDF fragment to include in the robot's description)
* ``webots``: a WorldInfo node with its ContactProperties (a .wbt fragment)
* ``mjcf``: an MJCF file with the ``<option>`` and the wheel x ground ``<pair>`` elements
* ``drake``: a MultibodyPlantConfig YAML and the wheels' ``drake:`` proximity tags
* ``coppeliasim``: a Lua snippet setting the Bullet engine parameters
* ``isaaclab``, ``newton``, ``genesis``: Python configuration blocks
"""

from __future__ import annotations

import ast
import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping

# Gazebo Classic combines the two surfaces of a contact (ODEPhysics.cc:1107-1115): kp in series, kd summed; the
# ground keeps the SDF defaults (kp 1e12, kd 1)
GROUND_KP, GROUND_KD = 1.0e12, 1.0
# and sums slip1/slip2 over the surfaces, then multiplies by the pair's contact count (ODEPhysics.cc:1172-1186):
# two contacts per wheel on level ground (ODE's cylinder collider here)
CONTACTS_PER_WHEEL = 2
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


# --- Gazebo and Gazebo Classic: SDF physics and URDF <gazebo> tags ---
#
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
                comments += _meanings(entries, (key,))
    world_text = xml_comment([*title, *comments]) + _tostring(sdf) + "\n"

    values = surface_values(engine, settings, ground_mu)
    texts = {"world.sdf": world_text}
    if values:
        robot = ET.Element("robot", name="simpick_wheel_tags")
        for link in wheels:
            gazebo = ET.SubElement(robot, "gazebo", reference=link)
            ET.SubElement(gazebo, "collision").append(_surface_element(values))
        notes = [
            "each wheel's <gazebo reference> carries a <collision><surface> that sdformat's URDF parser copies into "
            "every collision of the link (parser_urdf.cc), where Gazebo reads it",
            *_meanings(
                entries,
                (
                    "friction_direction",
                    "contact_kp",
                    "contact_kd",
                    "contact_slip",
                    "surface_mu",
                    "friction_ratio",
                    "contact_max_vel",
                    "contact_min_depth",
                    *[k for keys in SURFACE.values() for k in keys[:1]],
                ),
            ),
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


# --- Webots: WorldInfo and ContactProperties ---

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


def write_webots(settings: Mapping, entries: Mapping | None, title: list[str], ground_mu: float = GROUND_MU) -> dict:
    notes = _meanings(entries, ("cfm", "erp", "friction_ratio", *WEBOTS_FIELDS.values()))
    ratio = float(settings.get("friction_ratio") or 1.0)
    lines = [
        "WorldInfo {",
        "  basicTimeStep 1  # ms: the step simpick ran (Webots' default is 32)",
        f"  CFM {_num(settings['cfm'])}",
        f"  ERP {_num(settings['erp'])}",
        "  contactProperties [",
        "    ContactProperties {",
        '      material1 "wheel"  # the wheels\' contactMaterial; material2 stays "default", the ground\'s',
    ]
    if ratio == 1.0:
        lines.append(
            f"      coulombFriction [ {_num(ground_mu)} ]  # the ground's coefficient "
            f"(simpick's validation: {ground_mu:g})"
        )
    else:
        lines += [
            f"      coulombFriction [ {_num(ratio * ground_mu)} {_num(ground_mu)} 0 ]  # across the wheel (along its "
            f"Cylinder's axis: friction_ratio {_num(ratio)} x the ground's {ground_mu:g}), along its rolling direction "
            "(the ground's), the ground's own share 0: material1's first friction direction on a Cylinder's side is "
            f"its axis ({WEBOTS_FRICTION_SOURCE}); the ground a Box, a Plane or a Cylinder, else Webots applies the "
            "first value alone",
            "      frictionRotation 0 0  # the first direction left on the wheel's axis",
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
        lines.append(f"      {field} {text}")
    lines += ["    }", "  ]", "}"]
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


# --- MuJoCo: MJCF option and pairs ---

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
    notes = _meanings(entries, ("integrator", "cone", "solver_iterations", "wheel_contact", "friction_ratio"))
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


# --- Drake: MultibodyPlantConfig YAML and the wheels' proximity tags ---


def write_drake(settings: Mapping, entries: Mapping | None, title: list[str]) -> dict[str, str]:
    model = "hydroelastic_with_fallback" if settings["contact_model"] == "hydroelastic" else "point"
    lines = [
        f"time_step: {_num(settings.get('time_step') or 0.001)}",
        f"contact_model: {model}",
        f"discrete_contact_approximation: {settings['discrete_approximation']}",
        f"stiction_tolerance: {_num(settings['stiction_tolerance'])}",
    ]
    notes = _meanings(entries, ("time_step", "contact_model", "discrete_approximation", "stiction_tolerance"))
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
        entries, ("hydroelastic_modulus", "mesh_resolution", "wheel_dissipation", "mu_dynamic", "mu_static")
    )
    # the fragment alone is not a document (the drake: prefix is declared by the robot's <robot> element):
    # it is given inside a <robot> that declares it, to paste the <drake:proximity_properties> element from
    robot = ET.Element("robot", {"name": "simpick_wheel_tags", "xmlns:drake": "http://drake.mit.edu"})
    robot.append(props)
    urdf = (
        xml_comment([*title, "paste <drake:proximity_properties> inside each wheel's <collision>", *tag_notes])
        + _tostring(robot)
        + "\n"
    )
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
    for key in ("mu_dynamic", "mu_static"):
        m = re.search(rf'drake:{key} value="([^"]+)"', tags)
        if m:
            out[key] = float(m.group(1))
    return out


# --- Python and Lua configuration blocks (Isaac Lab, Newton, Genesis, CoppeliaSim) ---
#
# Each block is Python a user runs: the configuration classes' keyword arguments as dicts, named after the
# class they go to, with the import that gives the class. The names are checked against each simulator's
# own classes where they install here (Newton, Genesis: tests/test_simulator_files.py in their venvs) and
# against SIMULATOR_NAMES (quoted from the source) where they do not (Isaac Lab, Webots, CoppeliaSim).

PHYSX_SOLVER = {"tgs": 1, "pgs": 0}


def _isaaclab(settings: Mapping) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of an Isaac Lab (PhysX) profile."""
    return [
        (
            "from isaaclab.sim import PhysxCfg",
            "PhysxCfg",
            {
                "solver_type": PHYSX_SOLVER[settings["solver"]],
                "bounce_threshold_velocity": settings["bounce_threshold"],
            },
        ),
        (
            "from isaaclab.sim.schemas import ArticulationRootPropertiesCfg",
            "ArticulationRootPropertiesCfg",
            {
                "solver_position_iteration_count": int(settings["position_iterations"]),
                "solver_velocity_iteration_count": int(settings["velocity_iterations"]),
            },
        ),
        (
            "from isaaclab.actuators import ImplicitActuatorCfg",
            "ImplicitActuatorCfg",
            {"stiffness": 0.0, "damping": settings["wheel_drive_damping"]},
        ),
    ]


def _newton(settings: Mapping, ground_mu: float) -> list[tuple[str, str, dict]]:
    """(import, class or call, {keyword: value}) of an Isaac Lab 3 (Newton) profile: SolverMuJoCo's keywords
    (Isaac Lab's MJWarpSolverCfg fields of the same names) and, with the tuned wheel contact, the MuJoCo pair
    attributes SolverMuJoCo registers on a ModelBuilder (ModelBuilder.add_custom_values, one call per wheel and
    ground shape, geom1 the ground's shape index, geom2 the wheel's)."""
    solver = {"cone": settings["mujoco_cone"]}
    blocks = []
    if settings["wheel_contact"] != "default":
        d, df = settings["wheel_contact_impedance"], settings["wheel_friction_impedance"]
        solver["impratio"] = float(_num(((1 - d) / d) / ((1 - df) / df)))
    blocks.append(("from newton.solvers import SolverMuJoCo", "SolverMuJoCo", solver))
    if settings["wheel_contact"] == "pairs":
        d = settings["wheel_contact_impedance"]
        blocks.append(
            (
                "import newton  # SolverMuJoCo.register_custom_attributes(builder) first",
                "newton.ModelBuilder.add_custom_values",
                {
                    "mujoco:pair_condim": 3,
                    "mujoco:pair_friction": (ground_mu, ground_mu, 0.0, 0.0, 0.0),
                    "mujoco:pair_solref": (MUJOCO_TIMECONST, 1.0),
                    "mujoco:pair_solreffriction": (float(_num(MUJOCO_TIMECONST * MUJOCO_DMAX / d)), 1.0),
                    "mujoco:pair_solimp": (d, d, 0.001, 0.5, 2.0),
                },
            )
        )
    return blocks


def _genesis(settings: Mapping) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of a Genesis profile; friction_cone takes Genesis's enum
    (gs.friction_cone), not its name (the options are strict: genesis/options/solvers.py RigidOptions)."""
    return [
        (
            "import genesis as gs",
            "gs.options.RigidOptions",
            {"friction_cone": _Code(f"gs.friction_cone.{settings['friction_cone']}")},
        ),
        ("import genesis as gs", "gs.morphs.URDF", {"default_armature": settings.get("default_armature")}),
    ]


class _Code(str):
    """A keyword's value written as code (an enum member), not as a literal."""

    def __repr__(self) -> str:
        return str(self)


PYTHON_BLOCKS = {"isaaclab": _isaaclab, "newton": _newton, "genesis": _genesis}
# Why an Isaac Lab 3 (Newton) file has no lateral/longitudinal friction ratio, as the calibration's search space
# says it (tests/test_simulator_files.py holds the two to the same words): the adapter has no such setting, so
# neither the tuned nor the calibrated profile carries one, and the pairs' two tangential frictions are equal
NEWTON_NO_RATIO = (
    "no friction ratio (both tangential frictions the ground's): resources/simulators/calibration.yaml, "
    "isaac_lab_newton, if_unbound: simpick's Newton adapter writes the pairs' friction isotropic (no friction_ratio "
    "setting), so no calibrated setting can be run; its calibrated row is its tuned profile"
)
# the adapter setting behind each keyword, for the reader (keyword -> setting)
PYTHON_KEYS = {
    "isaaclab": {
        "solver_type": "solver",
        "bounce_threshold_velocity": "bounce_threshold",
        "solver_position_iteration_count": "position_iterations",
        "solver_velocity_iteration_count": "velocity_iterations",
        "damping": "wheel_drive_damping",
    },
    "newton": {"cone": "mujoco_cone"},
    "genesis": {"friction_cone": "friction_cone", "default_armature": "default_armature"},
}


def python_blocks(fmt: str, settings: Mapping, ground_mu: float = GROUND_MU) -> list[tuple[str, str, dict]]:
    """(import, class, {keyword: value}) of a Python-configured simulator's profile."""
    if fmt == "newton":
        return _newton(settings, ground_mu)
    return PYTHON_BLOCKS[fmt](settings)


def _variable(call: str) -> str:
    """The dict's name in the file: the class or call's own name, lower case (PhysxCfg -> physxcfg_kwargs)."""
    return call.split(".")[-1].lower() + "_kwargs"


def write_python(
    fmt: str, settings: Mapping, entries: Mapping | None, title: list[str], ground_mu: float = GROUND_MU
) -> dict:
    lines: list[str] = []
    for imp, call, kwargs in python_blocks(fmt, settings, ground_mu):
        if imp not in lines:
            lines.append(imp)
        body = ", ".join(f"{k!r}: {v!r}" for k, v in kwargs.items())
        lines.append(f"{_variable(call)} = {{{body}}}  # {call}(**{_variable(call)})")
    notes = _meanings(entries, PYTHON_KEYS[fmt].values())
    if fmt == "newton" and settings.get("wheel_contact") == "pairs":
        notes.append(
            f"pair values: one add_custom_values call per wheel shape and ground shape, with 'mujoco:pair_geom1' "
            f"(the ground's shape) and 'mujoco:pair_geom2' (the wheel's); friction: the ground's ({ground_mu:g} here)"
        )
    if fmt == "newton":
        notes.append(NEWTON_NO_RATIO)
    return {"py": _header("#", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_python(fmt: str, text: str) -> dict:
    out: dict = {}
    keys = PYTHON_KEYS[fmt]
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict):
            for k, v in zip(node.value.keys, node.value.values, strict=True):
                key = ast.literal_eval(k)
                if key not in keys:
                    continue
                if isinstance(v, ast.Attribute):  # an enum member: its name
                    value = v.attr
                else:
                    value = ast.literal_eval(v)
                if fmt == "isaaclab" and key == "solver_type":
                    value = {n: s for s, n in PHYSX_SOLVER.items()}[value]
                out[keys[key]] = value
    if fmt == "newton":
        out["wheel_contact"] = (
            "pairs" if "mujoco:pair_solref" in text else ("decoupled" if "'impratio'" in text else "default")
        )
    return out


COPPELIASIM_CALLS = [
    "sim.setInt32Param",
    "sim.intparam_dynamic_engine",
    "sim.physics_bullet",
    "sim.setEngineInt32Param",
    "sim.bullet_global_constraintsolvingiterations",
]


def write_coppeliasim(settings: Mapping, entries: Mapping | None, title: list[str]) -> dict[str, str]:
    notes = _meanings(entries, ("solver_iterations", "time_step", "contact_stiffness", "contact_damping"))
    step = settings.get("time_step")
    lines = [
        "-- in a customization script of the scene (Lua), before the simulation starts",
        "sim.setInt32Param(sim.intparam_dynamic_engine, sim.physics_bullet)",
        "sim.setEngineInt32Param(sim.bullet_global_constraintsolvingiterations, -1, "
        f"{int(settings['solver_iterations'])})",
        *(
            [
                "-- the physics step: the engine steps dt / this many times per simulation step (simDyn)",
                f"sim.setFloatParam(sim.floatparam_physicstimestep, {_num(step)})",
            ]
            if step is not None
            else ["-- simpick ran a 1 ms physics step; CoppeliaSim's default is 5 ms (Dynamics dialog: dt)"]
        ),
    ]
    return {"lua": _header("--", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_coppeliasim(text: str) -> dict:
    m = re.search(r"constraintsolvingiterations, -1, (\d+)\)", text)
    out = {"solver_iterations": int(m.group(1))}
    step = re.search(r"floatparam_physicstimestep, ([0-9.eE+-]+)\)", text)
    if step:
        out["time_step"] = float(step.group(1))
    return out


def write_profile_file(
    fmt: str,
    engine: str,
    settings: Mapping,
    header: list[str],
    wheels: list[str],
    entries: Mapping | None = None,
    ground_mu: float = GROUND_MU,
) -> dict[str, str]:
    """{file suffix: text} of a profile in the simulator format ``fmt`` (the catalog's ``settings_format``).

    ``engine``: the adapter the profile runs on (its settings' names); ``settings``: the adapter's full settings
    (a settings model's dump); ``header``: the lines the file opens with (what it is, the data behind it, the
    command that regenerates it), written as the format's comments (an XML comment cannot hold ``--``: see
    :func:`xml_comment`); ``wheels``: the robot's driven wheel links (SDF <gazebo reference>) or geoms (MJCF
    pairs); ``entries``: the catalog's entries (setting -> (variant, CatalogSetting)), whose sources are
    written beside the values; ``ground_mu``: the ground's friction coefficient where the format states it."""
    if fmt == "sdf":
        return write_sdf(engine, settings, entries, header, wheels, ground_mu)
    if fmt == "webots":
        return write_webots(settings, entries, header, ground_mu)
    if fmt == "mjcf":
        return write_mjcf(settings, entries, header, wheels, ground_mu)
    if fmt == "drake":
        return write_drake(settings, entries, header)
    if fmt == "coppeliasim":
        return write_coppeliasim(settings, entries, header)
    if fmt in PYTHON_BLOCKS:
        return write_python(fmt, settings, entries, header, ground_mu)
    raise ValueError(
        f"no settings file format {fmt!r}; known: sdf, webots, mjcf, drake, coppeliasim, {', '.join(PYTHON_BLOCKS)}"
    )


def write(fmt: str, engine: str, settings: Mapping, entries: Mapping, title: list[str], wheels: list[str]) -> dict:
    """{file suffix: text} of a profile in ``fmt`` (:func:`write_profile_file` with the catalog's entries)."""
    return write_profile_file(fmt, engine, settings, title, wheels, entries)


def read(fmt: str, engine: str, texts: Mapping[str, str]) -> dict:
    """The adapter settings ``texts`` (suffix -> text, as :func:`write` gave them) set."""
    if fmt == "sdf":
        return read_sdf(engine, texts)
    if fmt == "webots":
        return read_webots(texts["wbt"])
    if fmt == "mjcf":
        return read_mjcf(texts["xml"])
    if fmt == "drake":
        return read_drake(texts)
    if fmt == "coppeliasim":
        return read_coppeliasim(texts["lua"])
    return read_python(fmt, texts["py"])

"""The settings to paste: a simulator's profile written in that simulator's own format, and read back.

Each format has a writer (adapter settings -> the text a user pastes, every value with its meaning, its source
and the figure it gave here) and a reader (that text -> the adapter settings it sets), so a test can load a
written file into simpick's engines and check it reproduces the profile. Formats:

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


def _num(x) -> str:
    return f"{float(x):.6g}"


def _header(comment: str, lines: list[str]) -> str:
    return "\n".join(f"{comment} {line}".rstrip() for line in lines) + "\n"


def _meaning(entries: Mapping, key: str) -> str:
    variant, s = entries[key]
    bits = [f"{key} = {s.value!r} ({variant})", f"source: {s.source}"]
    if s.note:
        bits.append(s.note)
    return "; ".join(bits)


# --- Gazebo and Gazebo Classic: SDF physics and URDF <gazebo> tags ---


def write_sdf(engine: str, settings: Mapping, entries: Mapping, title: list[str], wheels: list[str]) -> dict[str, str]:
    """{suffix: text}: ``world.sdf`` (the <physics> element) and ``wheels.urdf`` (the wheels' <gazebo> tags)."""
    sdf = ET.Element("sdf", version="1.7")
    world = ET.SubElement(sdf, "world", name="default")
    physics = ET.SubElement(world, "physics", name="simpick", type="ode" if engine == "ode" else "dart")
    ET.SubElement(physics, "max_step_size").text = "0.001"
    comments = []
    if engine == "ode":
        if "max_contacts" in entries:
            ET.SubElement(physics, "max_contacts").text = str(int(settings["max_contacts"]))
        ode = ET.SubElement(physics, "ode")
        solver = ET.SubElement(ode, "solver")
        ET.SubElement(solver, "type").text = settings["stepper"]
        ET.SubElement(solver, "iters").text = str(int(settings["quick_iterations"]))
        constraints = ET.SubElement(ode, "constraints")
        for key, tag in (
            ("cfm", "cfm"),
            ("erp", "erp"),
            ("contact_max_correcting_vel", "contact_max_correcting_vel"),
            ("contact_surface_layer", "contact_surface_layer"),
        ):
            ET.SubElement(constraints, tag).text = _num(settings[key])
        comments += [
            _meaning(entries, k)
            for k in (
                "stepper",
                "quick_iterations",
                "cfm",
                "erp",
                "contact_max_correcting_vel",
                "contact_surface_layer",
            )
            if k in entries
        ]
    else:
        dart = ET.SubElement(physics, "dart")
        ET.SubElement(ET.SubElement(dart, "solver"), "solver_type").text = settings["lcp_solver"]
        ET.SubElement(dart, "collision_detector").text = settings["collision_detector"]
        comments += [_meaning(entries, k) for k in ("lcp_solver", "collision_detector") if k in entries]
    ET.indent(sdf)
    world_text = _header("<!--", [*title, *comments]).replace("\n", " -->\n") + ET.tostring(sdf, encoding="unicode")

    robot = ET.Element("robot", name="simpick_wheel_tags")
    tag_comments = []
    for link in wheels:
        g = ET.SubElement(robot, "gazebo", reference=link)
        if engine == "ode":
            mu = settings.get("surface_mu")
            if mu is not None:
                ET.SubElement(g, "mu1").text = _num(mu)
                ET.SubElement(g, "mu2").text = _num(mu * settings.get("friction_ratio", 1.0))
            elif settings.get("friction_ratio", 1.0) != 1.0:
                ET.SubElement(g, "mu1").text = "1.0"
                ET.SubElement(g, "mu2").text = _num(settings["friction_ratio"])
            if settings.get("friction_direction") == "wheel_x":
                ET.SubElement(g, "fdir1").text = "1 0 0"
            if settings.get("contact_kp") is not None:
                kp = 1.0 / (1.0 / settings["contact_kp"] - 1.0 / GROUND_KP)
                ET.SubElement(g, "kp").text = _num(kp)
                ET.SubElement(g, "kd").text = _num(max(settings.get("contact_kd", 1.0) - GROUND_KD, 0.0))
            if settings.get("contact_slip", 0.0) > 0:
                slip = settings["contact_slip"] / CONTACTS_PER_WHEEL
                ET.SubElement(g, "slip1").text = _num(slip)
                ET.SubElement(g, "slip2").text = _num(slip)
    if engine == "ode":
        tag_comments += [
            _meaning(entries, k)
            for k in ("friction_direction", "contact_kp", "contact_kd", "contact_slip", "surface_mu")
            if k in entries
        ]
        tag_comments.append(
            f"kp/kd: the wheel's own values; Gazebo puts them in series with (adds them to) the ground's "
            f"{GROUND_KP:g} / {GROUND_KD:g}. slip1/slip2: the per-contact slip / {CONTACTS_PER_WHEEL} (Gazebo "
            "multiplies by the pair's contact count)"
        )
    ET.indent(robot)
    wheels_text = _header("<!--", [*title, *tag_comments]).replace("\n", " -->\n") + ET.tostring(
        robot, encoding="unicode"
    )
    texts = {"world.sdf": world_text + "\n"}
    if engine == "ode":  # dartpy binds none of the wheels' SDF surface tags that gz-physics reads (catalog: differs)
        texts["wheels.urdf"] = wheels_text + "\n"
    return texts


def read_sdf(engine: str, texts: Mapping[str, str]) -> dict:
    """The adapter settings a world.sdf / wheels.urdf pair sets (the inverse of :func:`write_sdf`)."""
    out: dict = {}
    physics = ET.fromstring(texts["world.sdf"]).find("world/physics")
    if engine == "ode":
        if physics.find("max_contacts") is not None:
            out["max_contacts"] = int(physics.findtext("max_contacts"))
        out["stepper"] = physics.findtext("ode/solver/type")
        out["quick_iterations"] = int(physics.findtext("ode/solver/iters"))
        for key in ("cfm", "erp", "contact_max_correcting_vel", "contact_surface_layer"):
            out[key] = float(physics.findtext(f"ode/constraints/{key}"))
        g = ET.fromstring(texts["wheels.urdf"]).find("gazebo") if "wheels.urdf" in texts else None
        if g is not None:
            out["friction_direction"] = "wheel_x" if g.findtext("fdir1") == "1 0 0" else "plane"
            if g.find("kp") is not None:
                kp = float(g.findtext("kp"))
                out["contact_kp"] = 1.0 / (1.0 / kp + 1.0 / GROUND_KP)
                out["contact_kd"] = float(g.findtext("kd")) + GROUND_KD
            else:
                out["contact_kp"], out["contact_kd"] = 1.0 / (2.0 / GROUND_KP), 2.0 * GROUND_KD
            if g.find("slip1") is not None:
                out["contact_slip"] = float(g.findtext("slip1")) * CONTACTS_PER_WHEEL
            if g.find("mu1") is not None:
                mu1, mu2 = float(g.findtext("mu1")), float(g.findtext("mu2"))
                if mu1 < 1.0:
                    out["surface_mu"] = mu1
                if mu2 != mu1:
                    out["friction_ratio"] = mu2 / mu1
    else:
        out["lcp_solver"] = physics.findtext("dart/solver/solver_type")
        out["collision_detector"] = physics.findtext("dart/collision_detector")
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


def write_webots(settings: Mapping, entries: Mapping, title: list[str]) -> dict[str, str]:
    notes = [_meaning(entries, k) for k in ("cfm", "erp", *WEBOTS_FIELDS.values()) if k in entries]
    lines = [
        "WorldInfo {",
        "  basicTimeStep 1  # ms: the step simpick ran (Webots' default is 32)",
        f"  CFM {_num(settings['cfm'])}",
        f"  ERP {_num(settings['erp'])}",
        "  contactProperties [",
        "    ContactProperties {",
        '      material2 "wheel"  # the wheels\' contactMaterial',
        "      coulombFriction [ 0.8 ]  # the ground's coefficient (simpick's validation: 0.8; real classes: config)"
        if settings.get("friction_ratio", 1.0) == 1.0  # two values: along the wheel Cylinder's U, then across it
        else f"      coulombFriction [ 0.8 {_num(0.8 * settings['friction_ratio'])} ]  # the ground's, rolling and across",
    ]
    for field, key in WEBOTS_FIELDS.items():
        value = settings[key]
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
    return out


# --- MuJoCo: MJCF option and pairs ---

MUJOCO_TIMECONST, MUJOCO_DMAX = 0.02, 0.95  # the adapter's (simpick.engines.mujoco_engine)


def write_mjcf(settings: Mapping, entries: Mapping, title: list[str], wheels: list[str]) -> dict[str, str]:
    root = ET.Element("mujoco", model="simpick settings")
    option = ET.SubElement(
        root,
        "option",
        integrator={"euler": "Euler", "rk4": "RK4"}.get(settings["integrator"], settings["integrator"]),
        cone=settings["cone"],
        iterations=str(int(settings["solver_iterations"])),
    )
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
                solimp=f"{_num(d)} {_num(d)} 0.001 0.5 2",
                solref=f"{MUJOCO_TIMECONST} 1",
                solreffriction=f"{_num(MUJOCO_TIMECONST * MUJOCO_DMAX / d)} 1",
                # two tangential frictions where the profile sets a ratio (across the wheel capsule, then rolling)
                **({"friction": f"{_num(0.8 * settings['friction_ratio'])} 0.8 0 0 0"} if settings.get("friction_ratio", 1.0) != 1.0 else {}),
            )
    ET.indent(root)
    notes = [_meaning(entries, k) for k in ("integrator", "cone", "solver_iterations", "wheel_contact") if k in entries]
    notes.append("pairs: geom2 names the robot's wheel geoms, geom1 the ground; a pair's friction is the ground's")
    return {
        "xml": _header("<!--", [*title, *notes]).replace("\n", " -->\n") + ET.tostring(root, encoding="unicode") + "\n"
    }


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
    return out


# --- Drake: MultibodyPlantConfig YAML and the wheels' proximity tags ---


def write_drake(settings: Mapping, entries: Mapping, title: list[str]) -> dict[str, str]:
    model = "hydroelastic_with_fallback" if settings["contact_model"] == "hydroelastic" else "point"
    lines = [
        f"time_step: {_num(settings.get('time_step') or 0.001)}",
        f"contact_model: {model}",
        f"discrete_contact_approximation: {settings['discrete_approximation']}",
        f"stiction_tolerance: {_num(settings['stiction_tolerance'])}",
    ]
    notes = [
        _meaning(entries, k)
        for k in ("time_step", "contact_model", "discrete_approximation", "stiction_tolerance")
        if k in entries
    ]
    yaml_text = (
        _header("#", [*title, "MultibodyPlantConfig (pydrake.multibody.plant)", *notes]) + "\n".join(lines) + "\n"
    )
    props = ET.Element("drake:proximity_properties")
    if settings["contact_model"] == "hydroelastic":
        ET.SubElement(props, "drake:compliant_hydroelastic")
        ET.SubElement(props, "drake:hydroelastic_modulus", value=_num(settings["hydroelastic_modulus"]))
    ET.SubElement(props, "drake:hunt_crossley_dissipation", value=_num(settings["wheel_dissipation"]))
    ET.indent(props)
    tag_notes = [_meaning(entries, k) for k in ("hydroelastic_modulus", "wheel_dissipation") if k in entries]
    urdf = (
        _header("<!--", [*title, "inside each wheel's <collision>", *tag_notes]).replace("\n", " -->\n")
        + ET.tostring(props, encoding="unicode")
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
    return out


# --- Python and Lua configuration blocks (Isaac Lab, Newton, Genesis, CoppeliaSim) ---

PYTHON_CALLS = {
    # format -> [(call written, {keyword: adapter setting})]
    "isaaclab": [
        ("isaaclab.sim.PhysxCfg", {"solver_type": "solver", "bounce_threshold_velocity": "bounce_threshold"}),
        (
            "isaaclab.sim.schemas.ArticulationRootPropertiesCfg",
            {
                "solver_position_iteration_count": "position_iterations",
                "solver_velocity_iteration_count": "velocity_iterations",
            },
        ),
        ("isaaclab.actuators.ImplicitActuatorCfg", {"damping": "wheel_drive_damping"}),
    ],
    "newton": [
        ("isaaclab_newton MJWarpSolverCfg", {"cone": "mujoco_cone"}),
        ("simpick wheel contact", {"wheel_contact": "wheel_contact"}),
    ],
    "genesis": [
        ("gs.options.RigidOptions", {"friction_cone": "friction_cone"}),
        ("gs.morphs.URDF", {"default_armature": "default_armature"}),
    ],
}
PHYSX_SOLVER = {"tgs": 1, "pgs": 0}


def write_python(fmt: str, settings: Mapping, entries: Mapping, title: list[str]) -> dict[str, str]:
    lines = []
    for call, keywords in PYTHON_CALLS[fmt]:
        args = []
        for kw, key in keywords.items():
            value = settings.get(key)
            if fmt == "isaaclab" and key == "solver":
                value = PHYSX_SOLVER[value]
            args.append(f"{kw}={value!r}")
        lines.append(f"# {call}")
        lines.append(f"{call.split()[-1].split('.')[-1]}_kwargs = dict({', '.join(args)})")
    notes = [_meaning(entries, k) for _, kws in PYTHON_CALLS[fmt] for k in kws.values() if k in entries]
    return {"py": _header("#", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_python(fmt: str, text: str) -> dict:
    out = {}
    tree = ast.parse(text)
    for node in tree.body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Call):
            for kw in node.value.keywords:
                for _, keywords in PYTHON_CALLS[fmt]:
                    if kw.arg in keywords:
                        value = ast.literal_eval(kw.value)
                        if fmt == "isaaclab" and kw.arg == "solver_type":
                            value = {v: k for k, v in PHYSX_SOLVER.items()}[value]
                        out[keywords[kw.arg]] = value
    return out


def write_coppeliasim(settings: Mapping, entries: Mapping, title: list[str]) -> dict[str, str]:
    notes = [
        _meaning(entries, k) for k in ("solver_iterations", "contact_stiffness", "contact_damping") if k in entries
    ]
    lines = [
        "-- in a customization script of the scene (Lua), before the simulation starts;",
        "-- sim.setEngineInt32Param(int paramId, int objectHandle, int int32Param): CoppeliaRobotics/lua sim-ce.lua",
        "-- simpick ran a 1 ms physics step; CoppeliaSim's default is 5 ms (Dynamics dialog: dt)",
        "sim.setInt32Param(sim.intparam_dynamic_engine, sim.physics_bullet)",
        "sim.setEngineInt32Param(sim.bullet_global_constraintsolvingiterations, -1, "
        f"{int(settings['solver_iterations'])})",
    ]
    return {"lua": _header("--", [*title, *notes]) + "\n".join(lines) + "\n"}


def read_coppeliasim(text: str) -> dict:
    m = re.search(r"constraintsolvingiterations, -1, (\d+)\)", text)
    return {"solver_iterations": int(m.group(1))}


def write(fmt: str, engine: str, settings: Mapping, entries: Mapping, title: list[str], wheels: list[str]) -> dict:
    """{file suffix: text} of a profile in ``fmt``."""
    if fmt == "sdf":
        return write_sdf(engine, settings, entries, title, wheels)
    if fmt == "webots":
        return write_webots(settings, entries, title)
    if fmt == "mjcf":
        return write_mjcf(settings, entries, title, wheels)
    if fmt == "drake":
        return write_drake(settings, entries, title)
    if fmt == "coppeliasim":
        return write_coppeliasim(settings, entries, title)
    return write_python(fmt, settings, entries, title)


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

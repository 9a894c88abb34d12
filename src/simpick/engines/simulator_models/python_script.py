"""What the Python models share (Newton: :mod:`.newton_script`, Genesis: :mod:`.genesis_script`): a simulator set up in
Python gets its model as a script, ``<stem>.py``, that builds the robot on flat ground with the simulator's own API
as simpick's adapter does, beside the robot's description, ``<stem>.urdf`` (the file the adapter loads), and that
drives it at a command (v, w) and prints the yaw-rate gain it measures.

A script imports only the simulator's own packages, numpy and the standard library: every value it sets is written
into it as data (its claims first, then the robot, the ground and the simulator's options), each value the one the
adapter sets, taken from the adapter's own functions; the settings fragment of the simulator
(:mod:`simpick.engines.simulator_files.python_setups`) is the part of them a user pastes into a set-up of their own,
and the script's options hold it (:func:`over_fragment`).
"""

from __future__ import annotations

import pprint
import xml.etree.ElementTree as ET
from collections.abc import Mapping, Sequence
from pathlib import Path

from simpick.engines.simulator_files.common import _header, _num
from simpick.engines.simulator_models.common import TurningClaim

# how every script measures a gain and what its command line does, after its engine's run(v, w, duration)
MAIN = '''

def wheel_speeds(v: float, w: float) -> list[float]:
    """Each driven wheel's joint speed, rad/s, in WHEELS' order, for a command (v m/s, w rad/s): the wheel's rim
    speed v - w x side x COMMAND_TRACK / 2 (side 1 on the left, y > 0; -1 on the right), times its axis sign,
    over its radius."""
    return [(v - w * wheel["side"] * COMMAND_TRACK / 2) * wheel["axis_sign"] / wheel["radius"] for wheel in WHEELS]


def body_z_rate(quat_wxyz, angular) -> float:
    """The yaw rate about the base's own z axis: the world angular velocity on the body's z axis."""
    w, x, y, z = (float(c) for c in quat_wxyz)
    axis = np.array([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)])
    return float(axis @ np.asarray(angular, dtype=float))


def yaw_rate_gain(v: float, w: float, duration: float) -> float:
    """The robot built at rest, (v, w) held from the first step for ``duration`` s: the mean of the base's yaw rate
    about its own z axis over the steps from half the run on, over w (simpick's validation, a yaw_gain case)."""
    rates = run(v, w, duration)
    return float(rates[len(rates) // 2 :].mean() / w)


def main(argv=None) -> None:
    import argparse
    import json

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--v", type=float, help="forward speed, m/s (with --w: this command alone)")
    parser.add_argument("--w", type=float, help="yaw rate commanded, rad/s, not 0")
    parser.add_argument("--duration", type=float, help="s (default: each claim's own; 6 s for --v/--w)")
    args = parser.parse_args(argv)
    if (args.v is None) != (args.w is None):
        parser.error("give --v and --w together")
    if args.v is not None:
        runs = [{"case": "command", "v": args.v, "w": args.w, "duration": args.duration or 6.0, "gain": None}]
    else:  # every claim, each at its own duration unless --duration
        runs = [dict(c, duration=args.duration or c["duration"]) for c in CLAIMS]
    for r in runs:
        gain = yaw_rate_gain(r["v"], r["w"], r["duration"])
        print(json.dumps({**{k: r[k] for k in ("case", "v", "w", "duration")}, "gain": gain, "claimed": r["gain"]}))


if __name__ == "__main__":
    main()
'''


class Code(str):
    """A value the script writes as code (an enum member of the simulator's), not as a literal."""

    def __repr__(self) -> str:
        return str(self)


def literal(value):
    """``value`` with numpy scalars and arrays as Python floats, lists and tuples as they were."""
    if isinstance(value, Code):
        return value
    if isinstance(value, Mapping):
        return {k: literal(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(literal(v) for v in value)
    if hasattr(value, "item"):
        return value.item()
    return value


def assign(name: str, value, comment: str = "") -> str:
    """``name = value`` as Python, the value pretty-printed (a long dict one key a line), after its comment."""
    head = "".join(f"# {line}\n" for line in comment.splitlines()) if comment else ""
    return f"{head}{name} = {pprint.pformat(literal(value), width=100, sort_dicts=False)}\n"


def over_fragment(fragment: Mapping, exact: Mapping, what: str) -> dict:
    """``fragment``, the keywords of a block of the simulator's settings fragment (``python_blocks`` of
    :mod:`simpick.engines.simulator_files.python_setups`, numbers to 6 digits), with the adapter's ``exact`` values
    and keywords over them; raises if the fragment holds a keyword the adapter does not pass or another value, so
    that the script and the fragment cannot part."""
    for key, value in fragment.items():
        if key not in exact:
            raise ValueError(f"{what}: the settings fragment's {key!r} is not what the adapter passes ({dict(exact)})")
        if _shown(value) != _shown(exact[key]):
            raise ValueError(f"{what}: the settings fragment's {key} = {value!r}, the adapter's {exact[key]!r}")
    return {**fragment, **exact}


def _shown(value) -> str:
    if isinstance(value, Code):
        return str(value)
    if isinstance(value, list | tuple):
        return ",".join(_shown(v) for v in value)
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return repr(value)
    return _num(value)


def standalone_urdf(path: str | Path) -> str:
    """The text of the robot's description the adapter loads; raises where it names another file (a mesh), which
    would not travel with the model."""
    text = Path(path).read_text()
    named = sorted({f"{e.tag} {e.get('filename')}" for e in ET.fromstring(text).iter() if e.get("filename")})
    if named:
        raise ValueError(f"{path} names files ({', '.join(named)}): its model would not run alone")
    return text


def claims_block(claims: Sequence[TurningClaim]) -> str:
    rows = [{"case": c.case, "v": c.v, "w": c.w, "duration": c.duration, "gain": c.gain} for c in claims]
    comment = (
        "The yaw-rate gains simpick's validation measured on simpick's adapter with this set-up (run_case): the robot\n"
        "at rest, (v m/s, w rad/s) held from the first step for duration s, the mean of the base's yaw rate about its\n"
        "own z axis over the second half of the run, over w. Running this file measures them again."
    )
    return assign("CLAIMS", rows, comment)


def wheels_block(spec_robot, track: float) -> str:
    wheels = [
        {
            "joint": w.joint,
            "side": 1.0 if w.side == "left" else -1.0,
            "axis_sign": float(w.axis_sign),
            "radius": w.radius,
        }
        for w in spec_robot.driven
    ]
    return assign(
        "COMMAND_TRACK",
        float(track),
        "m: the controller's effective track, by which a command's w is shared between the sides",
    ) + assign("WHEELS", wheels, "the driven wheels: joint, side (1 left, -1 right), axis sign, radius (m)")


def script(header: Sequence[str], doc: str, imports: str, data: Sequence[str], body: str) -> str:
    """The script: its header as comments, its docstring, the simulator's imports, its data (claims first) and its
    code, ending with :data:`MAIN`."""
    return (
        _header("#", list(header))
        + f'"""{doc}"""\n\n'
        + "from __future__ import annotations\n\n"
        + "from pathlib import Path\n\n"
        + imports
        + "\n\n"
        + "\n".join(data)
        + body
        + MAIN
    )


def claim_lines(claims: Sequence[TurningClaim]) -> list[str]:
    if not claims:
        return ["claims no yaw-rate gain: the study's validation has no turning case on this ground from heading 0"]
    runs = "; ".join(
        f"{c.case}: (v, w) = ({_num(c.v)}, {_num(c.w)}) for {_num(c.duration)} s, gain {c.gain:.4f}" for c in claims
    )
    return [f"claims (CLAIMS below, measured on simpick's adapter): {runs}"]

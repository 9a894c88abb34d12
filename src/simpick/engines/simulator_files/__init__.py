"""The settings to paste: a simulator's profile written in that simulator's own format, and read back.

Each format has a writer (adapter settings -> the text a user pastes, every value with its meaning, its source
and the figure it gave here; :func:`write_profile_file` is the entry point) and a reader (that text -> the adapter
settings it sets), so a test can load a written file into simpick's engines and check it reproduces the profile.
tests/test_simulator_files.py reads every file with the simulator's own reader where one installs here
(sdformat, MuJoCo, Drake, Newton, Genesis) and checks the names of the others against
:mod:`simpick.engines.simulator_names`. Formats, one module each:

* ``sdf`` (:mod:`.sdf`): Gazebo and Gazebo Classic: the world's ``<physics>`` (an SDF file) and the wheels'
  ``<gazebo>`` tags (a URDF fragment to include in the robot's description)
* ``webots`` (:mod:`.webots`): a WorldInfo node with its ContactProperties (a .wbt fragment)
* ``mjcf`` (:mod:`.mjcf`): an MJCF file with the ``<option>`` and the wheel x ground ``<pair>`` elements
* ``drake`` (:mod:`.drake`): a MultibodyPlantConfig YAML and the wheels' ``drake:`` proximity tags
* ``coppeliasim`` (:mod:`.coppeliasim`): a Lua snippet setting the Bullet engine parameters
* ``isaaclab``, ``newton``, ``genesis`` (:mod:`.python_setups`): Python configuration blocks

:mod:`.common` holds what they share (the numbers' and comments' text, a setting's meaning, the XML
serialisation, the ground's ``GROUND_MU``). This module dispatches a format's name to its writer
(:func:`write_profile_file`) and reader (:func:`read`): a new simulator format is one module with its
``write_<format>`` and ``read_<format>`` and one entry in each of the two.
"""

from __future__ import annotations

from collections.abc import Mapping

from simpick.engines.simulator_files.common import GROUND_MU, xml_comment
from simpick.engines.simulator_files.coppeliasim import read_coppeliasim, write_coppeliasim
from simpick.engines.simulator_files.drake import read_drake, write_drake
from simpick.engines.simulator_files.mjcf import read_mjcf, write_mjcf
from simpick.engines.simulator_files.python_setups import PYTHON_BLOCKS, read_python, write_python
from simpick.engines.simulator_files.sdf import read_sdf, write_sdf
from simpick.engines.simulator_files.webots import read_webots, write_webots

__all__ = [
    "GROUND_MU",
    "read",
    "read_coppeliasim",
    "read_drake",
    "read_mjcf",
    "read_python",
    "read_sdf",
    "read_webots",
    "write",
    "write_coppeliasim",
    "write_drake",
    "write_mjcf",
    "write_profile_file",
    "write_python",
    "write_sdf",
    "write_webots",
    "xml_comment",
]


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

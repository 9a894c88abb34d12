"""Gazebo Classic's per-body contact limits in the ODE adapter (OdeSettings.contact_max_vel, contact_min_depth):
the collision callback gives each contact the body's <min_depth> in place of the world's surface layer and
caps its correcting velocity at the body's <max_vel>, as Gazebo's ODE fork does per body."""

from __future__ import annotations

import ctypes
from types import SimpleNamespace

import numpy as np
import pytest

from conftest import tiny_config
from simpick.engines import _ode, get_engine
from simpick.engines.ode_contacts import surface_limits
from simpick.engines.ode_settings import OdeSettings
from simpick.inputs.robot import load_from_config
from simpick.studies.validation.cases import Setup, _commands, _scenario

REAL = ctypes.sizeof(_ode.dReal)
DEPTH = (_ode.dContact.geom.offset + _ode.dContactGeom.depth.offset) // REAL
ERP = (_ode.dContact.surface.offset + _ode.dSurfaceParameters.soft_erp.offset) // REAL


def _contact(depth: float):
    c = (_ode.dReal * (ctypes.sizeof(_ode.dContact) // REAL))()
    c[DEPTH] = depth
    return c


def test_a_contact_s_push_out_is_capped_at_the_body_s_max_vel_beyond_its_min_depth():
    settings = OdeSettings(contact_max_vel=0.01, contact_min_depth=0.002, contact_surface_layer=0.001, erp=0.2)
    limit = surface_limits(SimpleNamespace(settings=settings, dt=0.001, contact_erp=0.2))
    deep = _contact(0.005)
    limit(deep)
    # ODE 0.16 subtracts the world's layer from the depth it is given: the body's min_depth remains
    assert deep[DEPTH] - 0.001 == pytest.approx(0.005 - 0.002)
    # ERP x depth / step: 0.2 x 3 mm / 1 ms = 0.6 m/s uncapped; the body's 0.01 m/s
    assert deep[ERP] * (0.005 - 0.002) / 0.001 == pytest.approx(0.01)
    shallow = _contact(0.00201)  # 10 um beyond min_depth: 2 mm/s at the world's ERP, under the cap
    limit(shallow)
    assert shallow[ERP] == pytest.approx(0.2)
    assert surface_limits(SimpleNamespace(settings=OdeSettings(), dt=0.001, contact_erp=0.2)) is None


def _rest_height(tmp_path, **settings) -> float:
    config = tiny_config(tmp_path)
    setup = Setup(
        engine="ode",
        robot=load_from_config(config["robot"]),
        timestep=0.001,
        max_wheel_torque=config["robot"]["max_wheel_torque"],
        track=config["robot"]["track"],
        settings={"stepper": "quick", **settings},
    )
    record = get_engine("ode").simulate(_scenario(setup, 0.8), _commands(setup, [(1.5, 0.0, 0.0)]))
    return float(np.mean(record.position[-200:, 2]))


def test_a_body_s_min_depth_rests_the_robot_as_the_world_s_surface_layer_would(tmp_path):
    # the fork uses the body's min_depth in place of the world's layer: the same rest as ODE's own layer
    plain = _rest_height(tmp_path, contact_surface_layer=0.0)
    layer = _rest_height(tmp_path, contact_surface_layer=0.003)
    body = _rest_height(tmp_path, contact_surface_layer=0.0, contact_min_depth=0.003)
    assert body == pytest.approx(layer, abs=1e-9)
    assert plain - body > 5e-4  # measured: 1.03 mm lower (the cylinder collider's contacts, not the full 3 mm)
    # and the world's layer no longer counts once a body sets its own
    assert _rest_height(tmp_path, contact_surface_layer=0.003, contact_min_depth=0.0) == pytest.approx(plain, abs=1e-9)

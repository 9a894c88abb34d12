from pathlib import Path

import pytest

from simpick.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"


@pytest.fixture(scope="session")
def robot():
    return load_robot(ROOT / "resources" / "robot" / "husky_a200.urdf")


def flat_terrain(friction: float = 0.95) -> dict:
    """A terrain with no shapes: the robot drives on the ground plane alone."""
    return {"schema": "simpick.terrain/1", "name": "flat", "boxes": [], "spheres": [], "friction": friction}

"""The robot as rigid bodies and moving joints, fixed-joint chains folded into their moving link.

An adapter that builds the robot body by body rather than through its engine's URDF loader (ODE)
needs this model; it is built from the same joint tree and wheel records as the rest of the
robot's facts, and kept apart because only such adapters read it."""

from __future__ import annotations

import numpy as np

from simpick.errors import InputError
from simpick.inputs.robot.spec import Suspension, Wheel
from simpick.inputs.urdf import Body, RigidModel, Tree, joint_axis


def _rigid_model(
    tree: Tree, where: str, wheels: list[Wheel], snapped_axes: dict, suspension: tuple[Suspension, ...] = ()
) -> RigidModel:
    """The bodies and moving joints of ``tree``: each moving link with every link hung on it by
    fixed joints folded in (breadth first, in the description's joint order)."""

    def body_of(link: str) -> tuple[str, np.ndarray, np.ndarray]:
        """The moving link ``link`` belongs to, and ``link``'s frame in that link's frame."""
        pos, rot = np.zeros(3), np.eye(3)
        chain = []
        while link in tree.child_joint and tree.child_joint[link].get("type") == "fixed":
            chain.append(tree.child_joint[link])
            link = tree.child_joint[link].find("parent").get("link")
        for joint in reversed(chain):
            xyz, r = tree.origins[joint.get("name")]
            pos, rot = pos + rot @ xyz, rot @ r
        return link, pos, rot

    def body(link_name: str) -> Body:
        part = Body(link_name)
        queue = [(link_name, np.zeros(3), np.eye(3))]
        while queue:
            name, pos, rot = queue.pop(0)
            part.add(tree.links[name], pos, rot, where)
            for joint in tree.children[name]:
                if joint.get("type") == "fixed":
                    xyz, r = tree.origins[joint.get("name")]
                    queue.append((joint.find("child").get("link"), pos + rot @ xyz, rot @ r))
        return part

    def mount(joint) -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
        name = joint.get("name")
        parent, pos, rot = body_of(joint.find("parent").get("link"))
        xyz, r = tree.origins[name]
        if parent != joint.find("parent").get("link"):  # hung on a fixed chain: the chain folded in
            xyz, r = pos + rot @ xyz, rot @ r
        axis = snapped_axes.get(name)
        return parent, xyz, r, axis if axis is not None else joint_axis(joint, f"{where}: joint {name!r}")

    rockers, at = [], {}
    for sus in suspension:  # parents before children
        parent, xyz, r, axis = mount(tree.joints[sus.joint])
        at[sus.link] = len(rockers)
        rockers.append((xyz, r, axis, body(sus.link), at.get(parent, -1), sus))
    driven, wheel_parents = [], []
    for wheel in (w for w in wheels if w.driven):
        parent, xyz, r, axis = mount(tree.joints[wheel.joint])
        driven.append((xyz, r, axis, body(wheel.link)))
        wheel_parents.append(at.get(parent, -1))
    passive, index = [], {}
    moving = [w for w in wheels if not w.driven]
    names = []
    for w in moving:
        names += [w.joint] + ([w.swivel] if w.swivel else [])
    for name in names[::-1]:  # (caster joint, its swivel): the swivel first
        joint = tree.joints[name]
        parent, xyz, r, axis = mount(joint)
        if parent != tree.base and parent not in index:
            raise InputError(
                f"{where}: joint {name!r}", f"hangs on {parent!r}, which is neither the base nor a caster's swivel link"
            )
        child = joint.find("child").get("link")
        index[child] = len(passive)
        passive.append((xyz, r, axis, body(child), -1 if parent == tree.base else index[parent]))
    return RigidModel(body(tree.base), tuple(driven), tuple(passive), tuple(rockers), tuple(wheel_parents))

"""The names the settings files use for the simulators no reader installs here (Webots, CoppeliaSim, Isaac Lab),
each quoted from the simulator's own source with the version read: tests/test_simulator_files.py checks that
every name a written file uses is in its table (simpick.engines.simulator_files writes them)."""

from __future__ import annotations

_WEBOTS_CP = "cyberbotics/webots 0af94230 resources/nodes/ContactProperties.wrl (R2025a)"
_WEBOTS_WI = "cyberbotics/webots 079ae49d resources/nodes/WorldInfo.wrl (R2025a)"
_COPPELIA = (
    "CoppeliaRobotics/coppeliaSimLib 852b3f38 sourceCode/interfaces/luaScriptFunctions.cpp, its table of Lua names "
    "(CoppeliaSim 4.10)"
)
_ISAACLAB = "isaac-sim/IsaacLab (Isaac Lab 2.3)"

NAMES = {
    "webots": {
        "version": "Webots R2025a (cyberbotics/webots, resources/nodes)",
        "names": {
            "WorldInfo": f"{_WEBOTS_WI}:4 (the node)",
            "basicTimeStep": f"{_WEBOTS_WI}:12 (SFFloat, ms, default 32)",
            "CFM": f"{_WEBOTS_WI}:9 (SFFloat, ODE world constraint force mixing)",
            "ERP": f"{_WEBOTS_WI}:10 (SFFloat, ODE world error reduction)",
            "contactProperties": f"{_WEBOTS_WI}:26 (MFNode)",
            "ContactProperties": f"{_WEBOTS_CP}:3 (the node)",
            "material1": (
                f"{_WEBOTS_CP}:4 (SFString, default \"default\"); its solid's geometry gives ODE's first friction "
                "direction fdir1 (cyberbotics/webots eee8e098 src/webots/engine/WbSimulationCluster.cpp:262-268, "
                "283-289: 'respect the order: material1 -> material2')"
            ),
            "material2": f"{_WEBOTS_CP}:5 (SFString)",
            "coulombFriction": (
                f"{_WEBOTS_CP}:6 (MFFloat: one value, or one per friction direction); three values: mu along fdir1 = "
                "[0] + [2], mu2 across it = [1] + [2], material1 taking [0] and [1] (cyberbotics/webots eee8e098 "
                "src/webots/engine/WbSimulationCluster.cpp:303-305, 315-317); a Cylinder's first direction on its "
                "side is its axis (927d975a src/webots/nodes/WbCylinder.cpp:549-556)"
            ),
            "frictionRotation": (
                f"{_WEBOTS_CP}:7 (SFVec2f, rotation of the first friction direction: of material1's by the first "
                "angle, about the contact normal; WbSimulationCluster.cpp:277-282)"
            ),
            "bounce": f"{_WEBOTS_CP}:9 (SFFloat)",
            "bounceVelocity": f"{_WEBOTS_CP}:10 (SFFloat, m/s)",
            "forceDependentSlip": f"{_WEBOTS_CP}:11 (MFFloat, 'see ODE')",
            "softERP": f"{_WEBOTS_CP}:12 (SFFloat)",
            "softCFM": f"{_WEBOTS_CP}:13 (SFFloat)",
            "maxContactJoints": f"{_WEBOTS_CP}:18 (SFInt32)",
        },
    },
    "coppeliasim": {
        "version": "CoppeliaSim 4.10 (CoppeliaRobotics/coppeliaSimLib)",
        "names": {
            "sim.setInt32Param": f"{_COPPELIA} (sim.setInt32Param(int parameter, int intState))",
            "sim.intparam_dynamic_engine": (
                f'{_COPPELIA}: {{"sim.intparam_dynamic_engine", sim_intparam_dynamic_engine}}'
            ),
            "sim.physics_bullet": (
                f"{_COPPELIA} (the engine constant; Bullet 2.78 by default, dynamicsContainer.cpp:33-34)"
            ),
            "sim.setEngineInt32Param": (
                f"{_COPPELIA} (sim.setEngineInt32Param(int paramId, int objectHandle, int int32Param); "
                "CoppeliaRobotics/lua sim-ce.lua)"
            ),
            "sim.bullet_global_constraintsolvingiterations": (
                f'{_COPPELIA}: "sim_bullet_global_constraintsolvingiterations", '
                '"sim.bullet_global_constraintsolvingiterations"; read by CDynamicsContainer::getIterationCount'
            ),
            "sim.setFloatParam": f"{_COPPELIA} (sim.setFloatParam(int parameter, float floatState))",
            "sim.floatparam_physicstimestep": (
                f'{_COPPELIA}: {{"sim.floatparam_physicstimestep", sim_floatparam_physicstimestep}}; the physics '
                "step simDyn reads when it steps (CoppeliaRobotics/simDyn CRigidBodyContainerDyn::handleDynamics: "
                "passes = dt / that step)"
            ),
        },
    },
    "isaaclab": {
        "version": "Isaac Lab 2.3 (isaac-sim/IsaacLab source/isaaclab)",
        "names": {
            "isaaclab.sim.PhysxCfg": f"{_ISAACLAB} source/isaaclab/isaaclab/sim/simulation_cfg.py (class PhysxCfg)",
            "physxcfg.solver_type": f"{_ISAACLAB} simulation_cfg.py:37-44 (0: PGS, 1: TGS, the default)",
            "physxcfg.bounce_threshold_velocity": f"{_ISAACLAB} simulation_cfg.py:110 (m/s, default 0.5)",
            "isaaclab.sim.schemas.ArticulationRootPropertiesCfg": (
                f"{_ISAACLAB} source/isaaclab/isaaclab/sim/schemas/schemas_cfg.py (class ArticulationRootPropertiesCfg)"
            ),
            "articulationrootpropertiescfg.solver_position_iteration_count": (
                f"{_ISAACLAB} schemas_cfg.py; set so in isaaclab_assets robots/anymal.py (4)"
            ),
            "articulationrootpropertiescfg.solver_velocity_iteration_count": (
                f"{_ISAACLAB} schemas_cfg.py; set so in isaaclab_assets robots/anymal.py (0)"
            ),
            "isaaclab.actuators.ImplicitActuatorCfg": (
                f"{_ISAACLAB} source/isaaclab/isaaclab/actuators/actuator_cfg.py (class ImplicitActuatorCfg)"
            ),
            "implicitactuatorcfg.stiffness": f"{_ISAACLAB} isaaclab_assets robots/ridgeback_franka.py (stiffness=0.0)",
            "implicitactuatorcfg.damping": f"{_ISAACLAB} isaaclab_assets robots/ridgeback_franka.py (damping=1e5)",
        },
    },
}

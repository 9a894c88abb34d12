// gzphysics_run: one SDF world stepped through Gazebo's own physics layer (Ignition Physics 5 and
// sdformat 12, the physics layer of Gazebo Fortress), driven from Python over stdin/stdout
// (simpick.engines.gzphysics_engine).
//
// Every behaviour below is gz-sim's Physics system as Fortress ships it, read at gazebosim/gz-sim
// ign-gazebo6 aab5556f (src/systems/physics/Physics.cc, "Physics.cc" below; src/SdfEntityCreator.cc)
// and gazebosim/gz-physics ignition-physics5_5.1.0 20a9d692 (Debian's 5.1.0+ds1; "dartsim/..." below):
//
//   - the engine: the plugin library found by name in Ignition Physics' engine directory and loaded
//     with ignition::plugin::Loader, its first class implementing ForwardStep for FeaturePolicy3d
//     instantiated and asked for the features (Physics.cc:728, 755-800);
//   - the world: the sdformat DOM of the file handed to the plugin's ConstructSdfWorld, which builds
//     every model, link, collision (with its <surface>: dartsim/src/SDFFeatures.cc:803-876) and joint
//     (with its <limit><effort>: dartsim/src/SDFFeatures.cc:138-139). gz-sim builds the same entities
//     one at a time from its entity-component store with the same plugin calls (Physics.cc:871-883;
//     ConstructModel 1038, ConstructLink 1172, ConstructJoint 1515): the same constructors on the same DOM;
//   - the <physics><dart> options: gz-sim reads <collision_detector> and <solver><solver_type> only where
//     the element is written (src/SdfEntityCreator.cc:299-320) and sets them through the world's
//     CollisionDetector and Solver features (Physics.cc:912-960; dartsim/src/WorldFeatures.cc:40-138);
//     otherwise the world keeps ConstructEmptyWorld's ODE detector and DART's Dantzig solver
//     (dartsim/src/EntityManagementFeatures.cc:720-736);
//   - the wheels: a velocity command per joint every step through SetJointVelocityCommandFeature, as
//     Physics.cc:1993-2033 applies the JointVelocityCmd that gz-sim's DiffDrive (src/systems/diff_drive/
//     DiffDrive.cc:458-490) and JointController (src/systems/joint_controller/JointController.cc:238-250)
//     systems write each iteration. dartsim makes the joint a DART SERVO bounded by its effort limit
//     (dartsim/src/JointFeatures.cc:147-184), and DART clears the command after each step
//     (dartsim/src/SimulationFeatures.cc:69, World::step's default), so it is set before every step;
//   - the step: ForwardStep with the step size as a std::chrono::steady_clock::duration input
//     (Physics.cc:2430-2446); dartsim sets DART's time step from it (dartsim/src/SimulationFeatures.cc:55-66);
//   - the state: the link's FrameDataRelativeToWorld (pose, velocity of the link origin, angular
//     velocity; Physics.cc:2516) and the joints' GetVelocity (Physics.cc:3190).
//
// Usage:
//   gzphysics_run version                       the versions built against, one line
//   gzphysics_run convert ROBOT.urdf            the URDF as sdformat 12 converts it (SDF on stdout)
//   gzphysics_run run WORLD.sdf PLUGIN RECORDED BASE_LINK WHEEL_JOINT...
//       PLUGIN: the engine library's file name (libignition-physics-dartsim-plugin.so);
//       RECORDED: the model whose BASE_LINK is reported; the models named robot0, robot1, ... each
//       have the WHEEL_JOINTs, commanded in that order, robot after robot.
// Protocol of `run` (native-endian binary on stdin/stdout): after the world is built it writes one line
// "ready <models> <wheels>\n"; then per request one byte:
//   'R' int64 n, then n x (models x wheels) float64 commands: n steps, each answered with the recorded
//       base link's 13 + wheels float64 (position 3, quaternion w x y z, linear velocity 3, angular
//       velocity 3, the recorded model's wheel joint speeds), all n rows written after the last step, then
//       two float64: the wall and the process CPU seconds of the n steps (commands and stepping, no I/O);
//   'Q' or end of input: exit 0. Any error: a message on stderr and exit status 2.

#include <chrono>
#include <cstdint>
#include <ctime>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <ignition/physics/FeatureList.hh>
#include <ignition/physics/FeaturePolicy.hh>
#include <ignition/physics/ForwardStep.hh>
#include <ignition/physics/FrameSemantics.hh>
#include <ignition/physics/GetEntities.hh>
#include <ignition/physics/Joint.hh>
#include <ignition/physics/RequestEngine.hh>
#include <ignition/physics/RequestFeatures.hh>
#include <ignition/physics/World.hh>
#include <ignition/physics/config.hh>
#include <ignition/physics/sdf/ConstructWorld.hh>
#include <ignition/plugin/Loader.hh>
#include <sdf/Physics.hh>
#include <sdf/Root.hh>
#include <sdf/World.hh>
#include <sdf/parser.hh>
#include <sdf/sdf_config.h>

namespace physics = ignition::physics;

namespace
{
// What this program needs of every engine (gz-sim's MinimumFeatureList, Physics.cc:159-170, holds the
// same ForwardStep, LinkFrameSemantics and ConstructSdfWorld).
struct Features : physics::FeatureList<
    physics::ForwardStep,
    physics::sdf::ConstructSdfWorld,
    physics::GetModelFromWorld,
    physics::GetLinkFromModel,
    physics::GetJointFromModel,
    physics::LinkFrameSemantics,
    physics::GetBasicJointState,
    physics::SetJointVelocityCommandFeature>
{
};
// Optional, as gz-sim casts them where the engine has them (Physics.cc:912-960).
struct DetectorFeatures : physics::FeatureList<physics::CollisionDetector> {};
struct SolverFeatures : physics::FeatureList<physics::Solver> {};

using Engine = physics::Engine3dPtr<Features>;
using World = physics::World3dPtr<Features>;
using Link = physics::Link3dPtr<Features>;
using Joint = physics::Joint3dPtr<Features>;

[[noreturn]] void Fail(const std::string &_message)
{
  std::cerr << "gzphysics_run: " << _message << std::endl;
  std::exit(2);
}

void ReadExactly(void *_buffer, std::size_t _bytes)
{
  if (std::fread(_buffer, 1, _bytes, stdin) != _bytes)
    Fail("input ended inside a request");
}

int Convert(const std::string &_urdf)
{
  // sdformat's own URDF parser (sdf::readFile converts a URDF as it reads it), as gz-sim reads a URDF
  sdf::SDFPtr converted(new sdf::SDF());
  sdf::init(converted);
  sdf::Errors errors;
  if (!sdf::readFile(_urdf, converted, errors) || !errors.empty())
  {
    for (const auto &e : errors)
      std::cerr << e << std::endl;
    Fail("sdformat could not read " + _urdf);
  }
  std::cout << converted->Root()->ToString("");
  return 0;
}

Engine LoadEngine(const std::string &_pluginLib)
{
  // Physics.cc:755-800: the library found in the engine directory, loaded, the first class
  // implementing ForwardStep for 3d instantiated and asked for the features
  const std::string path =
      std::string(IGNITION_PHYSICS_ENGINE_INSTALL_DIR) + "/" + _pluginLib;
  ignition::plugin::Loader loader;
  if (loader.LoadLib(path).empty())
    Fail("unable to load the physics engine library " + path);
  const auto classNames = loader.PluginsImplementing<
      physics::ForwardStep::Implementation<physics::FeaturePolicy3d>>();
  for (const auto &className : classNames)
  {
    auto plugin = loader.Instantiate(className);
    if (!plugin)
      continue;
    auto engine =
        physics::RequestEngine<physics::FeaturePolicy3d, Features>::From(plugin);
    if (engine)
      return engine;
  }
  Fail("no engine in " + path + " has the features this program needs "
       "(ConstructSdfWorld, joint velocity commands, link frame data)");
}

void ApplyDartOptions(const World &_world, const sdf::World &_sdfWorld)
{
  // src/SdfEntityCreator.cc:287-320: the first <physics>, its <dart> options only where written;
  // Physics.cc:912-960: applied through the world's features where the engine has them
  const sdf::Physics *physicsDom = _sdfWorld.PhysicsByIndex(0);
  if (!physicsDom || !physicsDom->Element() ||
      !physicsDom->Element()->HasElement("dart"))
    return;
  auto dart = physicsDom->Element()->GetElement("dart");
  if (dart->HasElement("collision_detector"))
  {
    auto detector = physics::RequestFeatures<DetectorFeatures>::From(_world);
    if (!detector)
      Fail("the engine has no CollisionDetector feature for <collision_detector>");
    detector->SetCollisionDetector(dart->Get<std::string>("collision_detector"));
  }
  if (dart->HasElement("solver") &&
      dart->GetElement("solver")->HasElement("solver_type"))
  {
    auto solver = physics::RequestFeatures<SolverFeatures>::From(_world);
    if (!solver)
      Fail("the engine has no Solver feature for <solver_type>");
    solver->SetSolver(dart->GetElement("solver")->Get<std::string>("solver_type"));
  }
}

int Run(int _argc, char **_argv)
{
  if (_argc < 7)
    Fail("usage: gzphysics_run run WORLD.sdf PLUGIN RECORDED BASE_LINK WHEEL_JOINT...");
  const std::string worldFile = _argv[2], pluginLib = _argv[3];
  const std::string recorded = _argv[4], baseLink = _argv[5];
  const std::vector<std::string> wheelNames(_argv + 6, _argv + _argc);

  sdf::Root root;
  const sdf::Errors errors = root.Load(worldFile);
  if (!errors.empty())
  {
    for (const auto &e : errors)
      std::cerr << e << std::endl;
    Fail("sdformat refused " + worldFile);
  }
  const sdf::World *sdfWorld = root.WorldByIndex(0);
  if (!sdfWorld)
    Fail(worldFile + " has no <world>");
  // the step: <physics><max_step_size>, gz-sim's update period (sdformat's default 0.001 s)
  const sdf::Physics *physicsDom = sdfWorld->PhysicsByIndex(0);
  const double dt = physicsDom ? physicsDom->MaxStepSize() : 0.001;

  Engine engine = LoadEngine(pluginLib);
  World world = engine->ConstructWorld(*sdfWorld);
  if (!world)
    Fail("ConstructSdfWorld built no world from " + worldFile);
  ApplyDartOptions(world, *sdfWorld);

  // robot models robot0, robot1, ... in order, each model's wheel joints in command order
  std::vector<Joint> wheels;
  std::vector<Joint> recordedWheels;
  Link base;
  std::size_t models = 0;
  for (;; ++models)
  {
    auto model = world->GetModel("robot" + std::to_string(models));
    if (!model)
      break;
    for (const auto &name : wheelNames)
    {
      auto joint = model->GetJoint(name);
      if (!joint)
        Fail("model robot" + std::to_string(models) + " has no joint " + name);
      wheels.push_back(joint);
      if (model->GetName() == recorded)
        recordedWheels.push_back(joint);
    }
    if (model->GetName() == recorded)
    {
      base = model->GetLink(baseLink);
      if (!base)
        Fail("model " + recorded + " has no link " + baseLink);
    }
  }
  if (!base)
    Fail("no model named " + recorded + " (the robots must be robot0, robot1, ...)");

  physics::ForwardStep::Input input;
  physics::ForwardStep::State state;
  physics::ForwardStep::Output output;
  input.Get<std::chrono::steady_clock::duration>() =
      std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(dt));

  const std::size_t nWheels = wheels.size();
  const std::size_t row = 13 + recordedWheels.size();
  std::vector<double> commands, rows;
  std::cout << "ready " << models << " " << wheelNames.size() << std::endl;

  auto stepOnce = [&](const double *_command)
  {
    for (std::size_t i = 0; i < nWheels; ++i)
      wheels[i]->SetVelocityCommand(0, _command[i]);
    world->Step(output, state, input);
  };

  for (;;)
  {
    int request = std::fgetc(stdin);
    if (request == EOF || request == 'Q')
      return 0;
    std::int64_t n = 0;
    ReadExactly(&n, sizeof(n));
    if (n < 0)
      Fail("negative step count");
    if (request == 'R')
    {
      commands.resize(static_cast<std::size_t>(n) * nWheels);
      ReadExactly(commands.data(), commands.size() * sizeof(double));
      rows.resize(static_cast<std::size_t>(n) * row + 2);
      const auto wall0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();
      for (std::int64_t k = 0; k < n; ++k)
      {
        stepOnce(commands.data() + k * nWheels);
        const auto data = base->FrameDataRelativeToWorld();
        const Eigen::Quaterniond q(data.pose.linear());
        double *out = rows.data() + k * row;
        out[0] = data.pose.translation().x();
        out[1] = data.pose.translation().y();
        out[2] = data.pose.translation().z();
        out[3] = q.w(); out[4] = q.x(); out[5] = q.y(); out[6] = q.z();
        for (int i = 0; i < 3; ++i)
        {
          out[7 + i] = data.linearVelocity[i];
          out[10 + i] = data.angularVelocity[i];
        }
        for (std::size_t w = 0; w < recordedWheels.size(); ++w)
          out[13 + w] = recordedWheels[w]->GetVelocity(0);
      }
      rows[rows.size() - 2] = std::chrono::duration<double>(
          std::chrono::steady_clock::now() - wall0).count();
      rows[rows.size() - 1] =
          static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
      std::fwrite(rows.data(), sizeof(double), rows.size(), stdout);
      std::fflush(stdout);
    }
    else
    {
      Fail("unknown request byte " + std::to_string(request));
    }
  }
}
}  // namespace

int main(int _argc, char **_argv)
{
  if (_argc == 2 && std::string(_argv[1]) == "version")
  {
    std::cout << "ignition-physics " << IGNITION_PHYSICS_VERSION_FULL << ", sdformat "
              << SDF_VERSION_FULL << std::endl;
    return 0;
  }
  if (_argc >= 3 && std::string(_argv[1]) == "convert")
    return Convert(_argv[2]);
  if (_argc >= 2 && std::string(_argv[1]) == "run")
    return Run(_argc, _argv);
  Fail("usage: gzphysics_run convert ROBOT.urdf | run WORLD.sdf PLUGIN RECORDED BASE_LINK WHEEL_JOINT...");
}

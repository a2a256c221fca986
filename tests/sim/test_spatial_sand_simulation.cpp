// The 3-D RBF contact model in a simulation: the quadruped on a floating base trotting on 3-D sand
// (the sand fixture of spatial_sand.hpp, saved as a model file and loaded by the "rbf" factory), with
// the first-order (ne-pgm) and the zeroth-order (ne-zopgm) PGM: every step converges, the robot
// stands on the sand (sinks a little, does not fall through) and moves forward.
#include <gtest/gtest.h>

#include <cmath>

#include "contact_models/spatial_rbf_function.hpp"
#include "scene_simulation.hpp"
#include "spatial_sand.hpp"
#include "test_temp_dir.hpp"

namespace nmdp::test {
namespace {

TEST(SpatialSandSimulation, FloatingBaseTrotConvergesWithFirstAndZerothOrderPgm) {
  TempDir tmp;
  const std::string model = tmp.file("sand3d.h5");
  // Cut-off at the surface with a 5 mm band: zero force in the air.
  saveSpatialRbfModel(model, SpatialRbfFunction(sandSpatialRbf()), SpatialGeometry{0.0, 0.005});
  // The same trot on rigid ground (Coulomb) sets the height the robot settles to.
  double rigid_lowest = 1e9;
  {
    Simulation rigid = repositorySimulation("quadruped_trot_flat.json", {"duration=2.0"});
    Vec3 position, rpy;
    for (long i = 0; i < rigid.scheduledSteps(); ++i) {
      ASSERT_TRUE(rigid.step().converged);
      rigid.basePose(position, rpy);
      rigid_lowest = std::min(rigid_lowest, position.z());
    }
  }
  for (const auto& [method, code] : {std::pair{"ne-pgm", Method::NePgm}, std::pair{"ne-zopgm", Method::NeZopgm}}) {
    SCOPED_TRACE(method);
    Simulation sim = repositorySimulation(
        "quadruped_trot_flat.json", {"contacts.model={\"type\": \"rbf\", \"file\": \"" + model + "\"}",
                                     std::string("integrator.method=") + method, "duration=2.0"});
    ASSERT_NE(dynamic_cast<const SpatialWrenchModel*>(&sim.contactModel()), nullptr);
    ASSERT_EQ(sim.options().method, code);
    Vec3 start, rpy, position;
    sim.basePose(start, rpy);
    double lowest = start.z();
    for (long i = 0; i < sim.scheduledSteps(); ++i) {
      const StepStats stats = sim.step();
      ASSERT_TRUE(stats.converged) << "step " << i;
      sim.basePose(position, rpy);
      ASSERT_TRUE(position.allFinite() && rpy.allFinite()) << "step " << i;
      lowest = std::min(lowest, position.z());
    }
    std::cout << "[ info ] " << method << ": base moved " << (position - start).transpose() << " m, yaw " << rpy.z()
              << " rad, lowest base height " << lowest << " m (start " << start.z() << ", on rigid ground "
              << rigid_lowest << ")\n";
    // The sand carries the robot: the base comes within 5 cm of its lowest height on rigid ground
    // (the fixture is soft: the base reaches 4.2 cm below the rigid case), does not fall through,
    // and the trot carries it forward.
    EXPECT_GT(lowest, rigid_lowest - 0.05);
    EXPECT_GT(position.x() - start.x(), 0.02);
  }
}

}  // namespace
}  // namespace nmdp::test

// The largest inputs nmdp accepts, in one place. Each bound is far above any real robot, dataset or
// model (the note beside it gives the real sizes it is compared with) and far below what would
// exhaust memory or time, so a malformed or hostile file gets a message naming the limit instead
// of a crash, a hang or an allocation of gigabytes. Messages name the file, the field and the limit.
#pragma once
#include <cstdint>

namespace nmdp::limits {

// Text inputs read whole (scene, URDF, CSV, keyframes, RBF text, configuration): the largest real
// one is the RoboSimian URDF, about 60 kB; the sand samples are 40 kB.
constexpr std::uintmax_t kMaxTextFileBytes = std::uintmax_t{256} << 20;  // 256 MiB
// Mesh files read for foot detection (binary STL: 50 bytes a triangle): real feet are < 10 MB.
constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{512} << 20;  // 512 MiB

// Mesh bytes inlined into one page of nmdp view (all runs together): RoboSimian's STL meshes are
// 1.3 MB; beyond this a link is drawn from its primitives instead.
constexpr std::uintmax_t kMaxPageMeshBytes = std::uintmax_t{256} << 20;  // 256 MiB

// Nesting of JSON objects/arrays and of XML elements: real scenes nest 5 deep, URDFs 4.
constexpr int kMaxJsonDepth = 64;
constexpr int kMaxXmlDepth = 64;
// Characters of a path: PATH_MAX on Linux.
constexpr std::size_t kMaxPathLength = 4096;

// Robot descriptions: A1 has 18 links, RoboSimian 60; humanoids with hands about 100.
constexpr int kMaxLinks = 1000;
constexpr int kMaxJoints = 1000;
// Contact points of a scene (each a foot sphere; a legged robot has 4-8, a foot polygon 4 more each).
constexpr int kMaxContactPoints = 64;
// Wrench-space vertices of one contact (the sand models have 26, the Coulomb cone 6).
constexpr int kMaxVertices = 256;

// Heightfield cells (a 4096 x 4096 grid: 128 MiB of doubles).
constexpr std::int64_t kMaxHeightfieldCells = std::int64_t{1} << 24;
// RBF centres (the published sand model has 103; a fit builds a dense P x P system, 800 MB at 10^4).
constexpr std::int64_t kMaxRbfCentres = 10000;
// Magnitudes of an RBF model's numbers, so that every kernel value and their weighted sum stay far
// inside a double for features within them: centres (φ in m, β in rad; the sand model's lie within
// 0.2), weights and polynomial coefficients (the sand model's reach 3 x 10^4), the feature scaling
// and the kernel's epsilon (sand: 5, 1 and 1).
constexpr double kMaxRbfCentreCoordinate = 1e3;
// A loaded learned model must give finite wrenches and derivatives for features (φ in m, β in rad)
// up to this magnitude, which no contact reaches; an MLP whose weights could overflow a double
// there (a bound propagated through its layers) is refused.
constexpr double kMaxModelFeature = 1e3;
constexpr double kMaxModelOutputBound = 1e200;
constexpr double kMaxRbfWeight = 1e15;
constexpr double kMaxRbfScale = 1e6;
// Entries of one numeric array read from an HDF5 file (model weights, dataset columns): 10^8
// doubles is 800 MB; the sand MLP has 2 x 10^4 weights.
constexpr std::int64_t kMaxArrayEntries = std::int64_t{100} << 20;
// Force samples of one dataset (the sand data has 494, gen-rft's default 520).
constexpr std::int64_t kMaxForceSamples = std::int64_t{10} << 20;

// Steps of one run: every step index and row count stays exactly representable in a double
// (2^53) with room, and a step counter never overflows. A run this long is stopped by the disk
// long before (each row holds at least 100 bytes).
constexpr double kMaxSteps = 1e15;

// A rollout (sim/rollout.hpp): its threads (one simulation each; a machine has tens of cores) and
// the doubles of its result, B · (steps + 1) · (flat state size): 2^30 is 8 GiB (a batch of 1024
// runs of 1000 steps of a quadruped is 10^8); a larger one is split by the caller.
constexpr int kMaxRolloutThreads = 256;
constexpr std::int64_t kMaxRolloutStateEntries = std::int64_t{1} << 30;

// Material patches of one terrain and points of one patch polygon: a scene has a few pits and
// paths of tens of points; the overlap check compares every pair of edges (10^4 patches x points
// squared would take seconds).
constexpr int kMaxMaterialPatches = 256;
constexpr int kMaxPolygonPoints = 1000;

}  // namespace nmdp::limits

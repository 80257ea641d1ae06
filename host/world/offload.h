// host/world/offload.h: debris offloading. On the opencl backend a world whose moving bodies
// are not all on the device keeps the others (bodies with joints, or those outside the debris
// set) in a CPU world of their own, stepped by the reference pipeline while the device steps the
// rest; the CPU bodies are kinematic obstacles on the device (docs/debris.md).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "rubble/error.h"
#include "rubble/scene.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/obstacle.h"
#include "rubble/world.h"

namespace rubble {

struct WorldState;

/// No body of the CPU world.
inline constexpr std::uint32_t kNotOnCpu = 0xffffffffu;

/// The CPU half of an offloaded world and what ties it to the device half.
struct Offload {
    std::unique_ptr<World> cpu;                ///< the CPU-owned bodies and every static body
    std::vector<std::uint32_t> cpuToWorld;     ///< the CPU world's body i is the world's body
    std::vector<std::uint32_t> worldToCpu;     ///< per world body: its CPU index, or kNotOnCpu
    std::vector<std::uint8_t> kinematic;       ///< per world body: CPU-owned and dynamic
    std::vector<std::uint32_t> obstacles;      ///< CPU index of each obstacle, in world order
    std::vector<shared::ObstacleState> states; ///< this step's, one per obstacle
    /// Two-way coupling: what the device's rows put on each obstacle in the last step, applied
    /// to the CPU bodies at the start of the next.
    std::vector<shared::BodyImpulse> pending;
    Coupling coupling = Coupling::OneWay;
};

/// Whether the scene marks a debris set: some dynamic body has `debris: true`.
bool hasDebrisSet(const Scene& scene);

/// The solver the device runs for a scene on the opencl backend with particles. A scene with a
/// debris set steps its CPU bodies with PGS whatever it names, and the set with Jacobi
/// (docs/debris.md), so `pgs` there names the CPU half and the device takes jacobi; any other
/// scene keeps its solver (SimulationOptions::solverType: jacobi when it names none).
SolverType deviceSolver(const Scene& scene);

/// Per body of the scene: whether the device steps it on the opencl backend with particles. The
/// debris set when the scene has one, else every dynamic body that no joint joins; never a
/// static body. (With SAT the device steps every body.)
std::vector<std::uint8_t> deviceBodies(const Scene& scene);

/// The CPU world of the bodies the device does not step (and every static body), with their
/// joints, built as its own scene on the cpu backend with SAT and PGS. Errors: those of
/// World::create.
Result<std::unique_ptr<Offload>>
makeOffload(const Scene& scene, const std::vector<std::uint8_t>& onDevice, const RunOptions& run);

/// Applies the impulses pending from the last step to the CPU bodies (two-way coupling) and
/// fills this step's obstacle states from the CPU world.
void prepareObstacles(Offload& o);

/// Copies the CPU-owned bodies' state from the CPU world into the world's arrays.
void copyCpuBodies(const Offload& o, WorldState& s);

} // namespace rubble

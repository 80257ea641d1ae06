// host/gpu/kernel_table.cpp: the kernel signatures, in the order of KernelId.
#include "host/gpu/kernel_table.h"

namespace rubble::gpu {

const std::vector<KernelSignature>& kernelSignatures() {
    static const std::vector<KernelSignature> table = {
        {KernelId::IntegrateVelocities,
         "integrateVelocities",
         {"count", "momenta", "forces", "masses", "poses", "velocities", "gravity", "dt"}},
        {KernelId::AbsorbVelocityChange,
         "absorbVelocityChange",
         {"count", "momenta", "before", "after", "masses", "poses"}},
        {KernelId::IntegratePositions,
         "integratePositions",
         {"count", "poses", "velocities", "atStart", "momenta", "masses", "dt", "symplectic",
          "status"}},
        {KernelId::MeasureLayout, "measureLayout", {"out"}},
    };
    return table;
}

} // namespace rubble::gpu

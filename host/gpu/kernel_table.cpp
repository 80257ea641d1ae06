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
        {KernelId::TransformParticles,
         "transformParticles",
         {"count", "particles", "poses", "world"}},
        {KernelId::CollideParticles,
         "collideParticles",
         {"count", "staticCount", "inverseCellSize", "bits", "capacity", "order", "cellStart",
          "cellEnd", "world", "particles", "masses", "statics", "contacts", "status"}},
        {KernelId::ComputeCellKeys,
         "computeCellKeys",
         {"count", "inverseCellSize", "bits", "world", "keys", "values"}},
        {KernelId::SortHistogram,
         "sortHistogram",
         {"count", "chunk", "shift", "keys", "histogram"}},
        {KernelId::SortScatter,
         "sortScatter",
         {"count", "chunk", "shift", "keys", "values", "offsets", "keysOut", "valuesOut"}},
        {KernelId::ExclusiveScan, "exclusiveScan", {"count", "in", "out"}},
        {KernelId::FindCellRanges, "findCellRanges", {"count", "keys", "cellStart", "cellEnd"}},
        {KernelId::PermuteContacts, "permuteContacts", {"count", "order", "in", "out"}},
        {KernelId::ContactKeys, "contactKeys", {"count", "contacts", "keys", "values"}},
        {KernelId::CountBodyContacts,
         "countBodyContacts",
         {"count", "contacts", "masses", "bodyCount"}},
        {KernelId::FillBodyLists,
         "fillBodyLists",
         {"count", "contacts", "masses", "cursor", "bodyList"}},
        {KernelId::SortBodyLists, "sortBodyLists", {"bodies", "bodyStart", "bodyList"}},
        {KernelId::LinkPrevious, "linkPrevious", {"count", "previous", "head", "next"}},
        {KernelId::BuildJacobiRows,
         "buildJacobiRows",
         {"count", "contacts", "poses", "velocities", "masses", "surfaces", "bodyCount", "params",
          "warmStart", "head", "next", "previous", "previousRows", "rows"}},
        {KernelId::SolveJacobiRows,
         "solveJacobiRows",
         {"count", "rows", "velocities", "relaxation", "lastSweep", "status"}},
        {KernelId::GatherJacobi,
         "gatherJacobi",
         {"bodies", "rows", "bodyStart", "bodyList", "before", "masses", "poses", "velocities"}},
    };
    return table;
}

} // namespace rubble::gpu

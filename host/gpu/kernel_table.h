// host/gpu/kernel_table.h: every kernel of the program with its argument names, in signature
// order. Dispatch binds arguments in this order (host/gpu/dispatch.h checks the count) and
// tests/gpu/kernels_build_test compares it with what the device reports.
#pragma once

#include <string_view>
#include <vector>

namespace rubble::gpu {

enum class KernelId : unsigned {
    IntegrateVelocities,
    AbsorbVelocityChange,
    IntegratePositions,
    MeasureLayout,
    TransformParticles,
    CollideParticles,
    ComputeCellKeys,
    SortHistogram,
    SortScatter,
    ExclusiveScan,
    FindCellRanges,
    PermuteContacts,
    ContactKeys,
    CountBodyContacts,
    FillBodyLists,
    SortBodyLists,
    LinkPrevious,
    BuildJacobiRows,
    SolveJacobiRows,
    GatherJacobi,
    BuildLcpRows,
    AssembleDelassus,
    ScaleLcpRows,
    ProjectLcp,
    StoreLcpImpulses,
    ApplyExplosion,
    PlaceObstacles,
    SetKinematicVelocities,
    GatherObstacleImpulses,
    WakeTouched,
    MarkRestless,
    SleepBodies,
    PrepareJacobiBodies,
    GatherJacobiRows,
    ComputeAabbs,
    GridBounds,
    GridSetup,
    GridEntries,
    GatherCellBoxes,
    FindCellPairs,
    FindLargePairs,
    CountPairs,
    PlacePairs,
    SortPairLists,
    CollideShapes,
    SummarizePairs,
    BuildPgsRows,
    WarmStartPgs,
    SolvePgs,
    ApplyPushes,
    WakeTouchedPairs,
    MarkBounces,
    PushPgs,
    LayerPgs,
    BouncePgs,
    BounceMomenta,
    BeginColoring,
    RelaxLevels,
    ChooseColors,
    TakeColors,
    CountColors,
    ScanColors,
    PlaceColors,
    MarkRestlessPairs,
    PrepareJoints,
    ProjectJointGroups,
    ProjectJoints,
    JointVelocities,
    MarkRestlessJoints,
    VoteJointGroups,
    HoldJointGroups,
    WakeJointGroups,
    FillWords,
    ParticlePairs,
    MarkStillPairs,
    PlaceStillPairs,
    CarryStillPairs,
    WakeStillPairs,
    PrepareSoftContacts,
    BeginSoftStep,
    AddSoftForces,
    WarmStartSoft,
    SolveSoft,
    IntegrateSoft,
    BounceSoft,
    FinishSoftStep,
    PrepareIslands,
    MarkIslandWakeBodies,
    MarkIslandWakePairs,
    MarkIslandWakeJoints,
    WakeIslandBodies,
    MeasureIslandBodies,
    HookIslandGroups,
    UniteIslandPairs,
    UniteIslandJoints,
    GatherIslands,
    SleepIslands,
    SumBodyEnergy,
    Count
};

struct KernelSignature {
    KernelId id;
    std::string_view name;
    std::vector<std::string_view> args;
};

/// The table, indexed by KernelId.
const std::vector<KernelSignature>& kernelSignatures();

inline const KernelSignature& signatureOf(KernelId id) {
    return kernelSignatures()[static_cast<unsigned>(id)];
}

} // namespace rubble::gpu

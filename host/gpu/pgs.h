// host/gpu/pgs.h: projected Gauss-Seidel on the device (kernels/pgs*.cl) over the pair arrays,
// for SAT and for particles with PGS: each pair's summary, the host's plan of the step's
// elements into blocks (a CPU device) and colors, the rows of every manifold point with their
// warm start, the velocity sweeps with the split position pass, the restitution pass and the
// pushes. The CPU twin is PgsSolver (host/dynamics/pgs_solver.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "host/core/step_params.h"
#include "host/gpu/coloring.h"
#include "host/gpu/joints.h"
#include "host/gpu/pairs.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/pgs_row.h"

namespace rubble::gpu {

/// One launch of the device's sweeps over the elements [first, first + count) of the step's
/// order, by `mode` (RUBBLE_PGS_*): a color's, one per work-item; the last colors together on
/// one work-item (serial); or the blocks, one work-group each. A launch of the device's plan
/// (RUBBLE_PGS_COLOR, RUBBLE_PGS_OVERFLOW) names its color in `first` and reads its range on the
/// device; its count and points are last step's, for its size and the byte counts only.
struct PgsLaunch {
    cl_uint first = 0, count = 0, mode = RUBBLE_PGS_PER_ITEM;
    std::uint32_t points = 0; ///< rows, for the byte counts
    std::uint32_t blocks = 0; ///< RUBBLE_PGS_BLOCKS: how many
    std::uint32_t width = 0;  ///< RUBBLE_PGS_COLOR: work-items, striding over the color
    /// Work-items of the launch in groups of `group`.
    std::size_t items(std::size_t group) const {
        if (mode == RUBBLE_PGS_BLOCKS) return std::size_t(blocks) * group;
        if (mode == RUBBLE_PGS_COLOR) return width;
        return mode == RUBBLE_PGS_SERIAL || mode == RUBBLE_PGS_OVERFLOW ? group : count;
    }
};

class PgsSolve {
  public:
    /// `blocks`: the bodies cut into that many ranges, solved in order on one work-item each
    /// (0: colors only). `deviceColoring`: with no blocks, the device plans the colors
    /// (kernels/coloring.cl) and the host reads nothing for the plan. Errors: Device, Limit.
    Status create(StageQueue& q, std::uint32_t bodies, std::uint32_t blocks,
                  bool deviceColoring = false);

    /// Stage buildContactRows, before the plan: each body's inverse mass and world inverse
    /// inertia, each pair's summary (and the impulses kept by pairs that get no rows), the
    /// marks of the split position pass, the joints' rows.
    Status summarize(StageQueue& q, DeviceBodies& b, PairStore& pairs, DeviceJoints& joints,
                     const StepParams& params);
    /// Reads this round's pairs and their summaries, unless read already this round (the status
    /// block must have been read after the summaries). Errors: Device.
    Status readSummaries(StageQueue& q, const PairStore& pairs);
    /// The pairs with rows of the summaries read last: the contacts the islands join.
    void touching(std::vector<BodyPair>& out) const;
    /// The step's elements (joints, then pairs with rows) into blocks and colors, their records
    /// and the launches; uploads them (enqueued). Reads the summaries first, unless the device
    /// plans (devicePlans()). `st`: the status read after the summaries. Errors: Device, Limit.
    Status plan(StageQueue& q, const PairStore& pairs, const DeviceJoints& joints,
                const DeviceBodies& b, const DeviceStatus& st);
    /// Whether the device plans the colors (no blocks, and the device coloring chosen).
    bool devicePlans() const { return devicePlan_; }
    /// Takes back the last plan's turn of the levels (the device's plan): the step runs again
    /// from its start.
    void undoPlan() {
        if (devicePlan_) levelHalf_ ^= 1u;
    }
    /// The device's plan after the step (a finished queue): each color's first element, the
    /// overflow set's and the end, then the same in rows (RUBBLE_PGS_COLOR_STARTS_WORDS words),
    /// and each element's set by element index (the joints, then the pairs; pairs without rows
    /// RUBBLE_PGS_NOT_ELEMENT). Errors: Device.
    Result<std::vector<cl_uint>> downloadColorStarts(StageQueue& q) const;
    Result<std::vector<cl_uint>> downloadColorOf(StageQueue& q, std::uint32_t elements) const;
    /// The first `count` element records as the device holds them. Errors: Device.
    Result<std::vector<shared::PgsElement>> downloadElements(StageQueue& q,
                                                             std::uint32_t count) const;
    /// Stage buildContactRows, after the plan: the rows of every element's manifold points,
    /// warm-started.
    Status buildRows(StageQueue& q, DeviceBodies& b, PairStore& pairs, const StepParams& params);
    /// Stage solve: warm start, the velocity sweeps and the split position pass (in the sweeps'
    /// launches, unless a row may bounce: then after them), the layer pass; the momenta take up
    /// the velocity change. `st`: the status read after the summaries.
    Status solve(StageQueue& q, DeviceBodies& b, PairStore& pairs, DeviceJoints& joints,
                 const DeviceStatus& st, const StepParams& params);
    /// Whether the pushes follow integratePositions directly (a row pushed, none bounces).
    bool fusedPushes() const { return pushes_ && !bounces_; }
    /// After integratePositions, when a row may bounce: the restitution pass, then the bounces'
    /// impulses into the momenta and those bodies' velocities from them.
    Status bounce(StageQueue& q, DeviceBodies& b, const StepParams& params);
    /// After the restitution pass: the split position pass moves the bodies.
    Status applyPushes(StageQueue& q, DeviceBodies& b, float dt);

    // The step's plan, as the launches read it: the elements (the joints, then the pairs with
    // rows), their records in launch order, the blocks' starts and passes, the rows before
    // each record, the launches.
    std::span<const ColorElement> stepElements() const { return stepElements_; }
    std::span<const shared::PgsElement> elements() const { return elementsHost_; }
    std::span<const std::uint32_t> blockStarts() const { return blockStartsHost_; }
    std::span<const std::uint32_t> rowsBefore() const { return pointsHost_; }
    std::span<const PgsLaunch> launches() const { return launches_; }
    /// Rows of the step (the device's plan: last step's, for the byte counts).
    std::uint32_t rowCount() const { return rowCount_; }
    /// Rows the row buffers hold room for: the step's, or with the device's plan four per pair
    /// of the pairs' room.
    std::uint32_t rowRoom() const { return rowRoom_; }
    /// The entries of the build order: the pairs with rows among the step's elements (they
    /// follow the joints), or with the device's plan the pairs' room, those without rows marked
    /// RUBBLE_PGS_NO_ELEMENT.
    std::uint32_t pairElements() const { return buildCount_; }
    /// The step's plan and rows as the device holds them, for a solver that goes through the
    /// same elements in the same launches (the soft step, host/gpu/soft_step.h).
    struct RowBuffers {
        const Buffer& elements;   ///< PgsElement records in launch order
        const Buffer& buildOrder; ///< the pairs' elements in pair order
        const Buffer& blockStarts;
        const Buffer& normalRows;
        const Buffer& frictionRows;
        const Buffer& impulses; ///< per point: normal, two friction impulses and a spare, N s
    };
    RowBuffers rowBuffers() const {
        return {elements_,   buildOrder_,   devicePlan_ ? colorStarts_ : blockStarts_,
                normalRows_, frictionRows_, impulses_};
    }
    /// The coloring of the elements between blocks (every element on a GPU).
    const Coloring& coloring() const { return coloring_; }
    /// Reads this step's rows, packed in element order. Errors: Device.
    Result<std::vector<shared::PgsNormalRow>> downloadNormalRows(StageQueue& q) const;
    Result<std::vector<shared::PgsFrictionRows>> downloadFrictionRows(StageQueue& q) const;

  private:
    Status createDevicePlan(StageQueue& q, std::uint32_t bodies);
    Status planOnDevice(StageQueue& q, const PairStore& pairs, const DeviceJoints& joints,
                        const DeviceBodies& b, const DeviceStatus& st);
    Dispatch launch(StageQueue& q, KernelId id, const PgsLaunch& l) const;
    Dispatch rowLaunch(StageQueue& q, KernelId id, const PgsLaunch& l, const DeviceJoints& joints,
                       const DeviceBodies& b) const;
    std::uint32_t blocks_ = 0;
    Buffer elements_;   ///< this step's PgsElement records, block by block, then by color
    Buffer buildOrder_; ///< the pairs' elements (indices into elements) in pair order
    /// The blocks' first elements and the end of the last, then each block's passes over its
    /// elements' points.
    Buffer blockStarts_;
    Buffer normalRows_;    ///< PgsNormalRow per point, packed in element order
    Buffer frictionRows_;  ///< PgsFrictionRows per point, in the same order
    Buffer impulses_;      ///< per point: normal, two friction and push impulses, N s
    Buffer pushed_;        ///< per body: a pushing row moves it
    Buffer push_;          ///< per body: the push velocities (BodyVelocity)
    Buffer sweepResidual_; ///< per push sweep: the largest change, float bits
    Buffer bounce_;        ///< per point: the restitution pass's impulse, N s
    /// Per body: the velocities the sweeps left, on which the restitution pass sweeps.
    Buffer solved_;
    Buffer bounceResidual_; ///< per restitution sweep: the largest change, float bits
    // The layer pass's scratch: per body its layer and marks, the rows' lists, the histogram.
    Buffer layer_, loaded_, layerRows_, layerSorted_, layerHistogram_;
    bool bounces_ = false;         ///< this step: a row may bounce (the restitution pass runs)
    bool pushes_ = false;          ///< this step: the split position pass ran (applyPushes moves)
    std::uint32_t rowCount_ = 0;   ///< points with rows this step
    std::uint32_t rowRoom_ = 0;    ///< rows the row buffers were sized for this step
    std::uint32_t buildCount_ = 0; ///< entries of the build order this step
    /// Elements the records may hold this step: the step's, or the device plan's bound (joints
    /// and the pairs' room), whose records past the step's elements are zero when markBounces
    /// or the layer pass will read them.
    std::uint32_t elementRoom_ = 0;
    // The device's plan (host/gpu/pgs_device_plan.cpp): each element's color word, each body's
    // colors and claims, the counting sort's counts by (set, chunk), the color starts; last
    // step's color starts, read without waiting, for the launches' sizes.
    bool devicePlan_ = false;
    Buffer colorOf_, bodyColors_, claims_, chunkCounts_, colorStarts_;
    Buffer levels_[2];       ///< per body its support level, this step's and last step's
    unsigned levelHalf_ = 0; ///< which of levels_ is this step's
    std::vector<cl_uint> colorStartsHost_;
    bool colorStartsKnown_ = false;
    std::uint32_t jointCount_ = 0; ///< joints among this step's elements (they come first)
    // The plan on the host (host/gpu/pgs_plan.cpp).
    Coloring coloring_;
    std::vector<ColorElement> stepElements_; ///< the joints, then the pairs with rows
    std::vector<ColorElement> coloredPairs_; ///< the pairs with rows between blocks
    std::vector<std::uint32_t> coloredHost_; ///< the elements between blocks (indices)
    std::vector<std::uint32_t> placeHost_;   ///< each element's place in elementsHost_
    std::vector<std::uint32_t> blockOfHost_; ///< each element's block, or all ones: colored
    std::vector<std::uint32_t> blockStartsHost_, nextHost_, pointsHost_;
    std::vector<cl_uint> summariesHost_;
    std::vector<shared::BodyPairRecord> pairsHost_;
    bool summariesRead_ = false; ///< pairsHost_ and summariesHost_ hold this round's
    std::vector<shared::PgsElement> elementsHost_;
    std::vector<PgsLaunch> launches_; ///< this step's launches of each sweep
};

} // namespace rubble::gpu

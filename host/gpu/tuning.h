// host/gpu/tuning.h: the kernels' tuning parameters in one table (as CLBlast keeps its kernel
// parameters): what each means, its default on a device and who chooses it. The program's -D
// build options and the host's work sizes and launch modes are derived from it, nowhere else.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "host/gpu/device.h"
#include "rubble/error.h"
#include "rubble/shared/constants.h"

namespace rubble::gpu {

// The parameters, by name (WorkSizes' fields; tuningParameters() holds the same in code):
//
// name            -D                       default                          chosen by
// sortItems       RUBBLE_SORT_ITEMS        64 per compute unit, a power of  device: compute units
//                                          two in 256 - 4096
// broadGroup      RUBBLE_GROUP_BROAD       64, or the device's largest      device: largest group
//                                          work-group if smaller
// pairGroup       RUBBLE_GROUP_PAIRS       as broadGroup                    device: largest group
// contiguousItems RUBBLE_CONTIGUOUS_ITEMS  1 on a CPU device, 0 on a GPU    device: type
// jointDouble     RUBBLE_JOINT_DOUBLE      1 with fp64, else 0              device: fp64
// pgsBlocks       (launch mode: blocks)    4 per compute unit on a CPU      device: type, units
//                                          device, 0 (colors only) on a GPU
// pgsBlockBodies  (launch mode: blocks)    128                              timed: pyramid_20,
//                                                                           debris_1k solve
// serialElements  (launch mode: serial)    128                              timed: debris_16k
//                                                                           solve, colored
//
// A timed default is judged by the solve stage's ms/step of `rubble run SCENE --backend opencl
// --collision sat --metrics m.json` with the value changed (--pgs-blocks N for the block count,
// the constant below for the others); the figures belong in bench/results, not here.
//
// A sweep kernel of the device's Gauss-Seidel solve (kernels/pgs_sweep.cl) runs in one of three
// launch modes (RUBBLE_PGS_PER_ITEM, RUBBLE_PGS_SERIAL, RUBBLE_PGS_BLOCKS in
// rubble/shared/pgs_row.h): a color, one element per work-item, which every device runs; the
// serial tail, the last colors of a step together on one work-item once they hold no more than
// serialElements elements; and the blocks, pgsBlocks ranges of bodies each swept in order by
// one work-item, on a CPU device. The blocks always take their rows by point, the CPU's order.
//
// What a value other than the default changes (TuningEffect), as tests/gpu/tuning_test checks:
// sortItems, broadGroup, pairGroup, contiguousItems and serialElements only share the same work
// out differently among work-items and launches, and every trajectory keeps its bits (sortItems
// also regroups the float sum of the box widths that sizes the broad phase's columns, which
// decide where pairs are looked for, not which are found). jointDouble
// changes the precision of the joints' position projection (float against double), and
// pgsBlocks and pgsBlockBodies the order of the Gauss-Seidel updates: the same physics within a
// tolerance, not the same bits.

/// A PGS block holds at least this many bodies when the device chooses the count.
inline constexpr std::uint32_t kPgsBlockBodies = 128;
/// The last colors of a step go to one serial launch once together they hold no more elements.
inline constexpr std::uint32_t kSerialElements = 128;

/// The values of the tuning parameters one program is built and dispatched with.
struct WorkSizes {
    std::uint32_t sortItems = RUBBLE_SORT_ITEMS;   ///< work-items of a radix sort pass
    std::uint32_t broadGroup = RUBBLE_GROUP_BROAD; ///< work-group of the SAT broad phase
    std::uint32_t pairGroup = RUBBLE_GROUP_PAIRS;  ///< work-group of the pair kernels
    std::uint32_t contiguousItems = 0; ///< 1: a strided launch's work-items take runs of items
    std::uint32_t jointDouble = 0;     ///< 1: the joints' projection factors in double
    std::uint32_t pgsBlocks = 0;       ///< PGS blocks the device asks for (0: colors only)
    std::uint32_t pgsBlockBodies = kPgsBlockBodies; ///< least bodies of a block by default
    std::uint32_t serialElements = kSerialElements; ///< most elements of the serial tail
    /// Bytes of a JointReal on the device (the projection's matrices and solutions).
    std::uint32_t jointRealBytes() const { return jointDouble ? 8u : 4u; }
};

/// Who chooses a parameter's default.
enum class TuningSource {
    Device,      ///< derived from the device's limits or kind (clGetDeviceInfo)
    Measurement, ///< a constant picked by timing a named benchmark
};

/// What a value other than the default changes in a run's results.
enum class TuningEffect {
    Order,     ///< only which work-item or launch does which independent work: the same bits
    Precision, ///< float precision of some arithmetic: the same within a tolerance
    Solver,    ///< the order of dependent Gauss-Seidel updates: the same within a tolerance
};

/// One tuning parameter: a field of WorkSizes, how the kernels see it and who sets it.
struct TuningParameter {
    std::string_view name;           ///< the WorkSizes field
    std::uint32_t WorkSizes::*field; ///< where its value lives
    std::string_view define;         ///< the -D macro the kernels read; empty: host only
    bool flag;                       ///< 0 or 1 (-D without the `u` of a count)
    std::string_view meaning;
    std::string_view rule; ///< its default, as a rule
    TuningSource source;
    std::string_view chosenBy; ///< the device query or the benchmark behind the rule
    TuningEffect effect;
    std::uint32_t (*choose)(const DeviceInfo&); ///< the default on a device
};

/// Every parameter, in the order of the build options.
std::span<const TuningParameter> tuningParameters();

/// A value given for a parameter by name, in place of the device's default.
struct TuningValue {
    std::string_view name;
    std::uint32_t value = 0;
};

/// The defaults for a device, each parameter's `choose`.
WorkSizes workSizesFor(const DeviceInfo& device);

/// `sizes` with `values` in place of the defaults. Errors: BadInput at `tuning <name>` for a
/// name that is not a parameter, a flag other than 0 or 1, a count of 0, or a work-group larger
/// than the device takes.
Result<WorkSizes> tunedWorkSizes(WorkSizes sizes, std::span<const TuningValue> values,
                                 const DeviceInfo& device);

/// The blocks of the PGS solve for a world of `bodies` bodies on a device that asks for
/// `deviceBlocks` (WorkSizes::pgsBlocks; 0, a GPU, stays 0), each of at least `blockBodies`
/// bodies (one block below twice that).
std::uint32_t defaultPgsBlocks(std::uint32_t deviceBlocks, std::size_t bodies,
                               std::uint32_t blockBodies = kPgsBlockBodies);

/// Options every build of the program uses (the same text and options hit PoCL's binary cache).
inline constexpr const char* kBuildOptions = "-cl-kernel-arg-info -cl-std=CL1.2";

/// kBuildOptions followed by the parameters the kernels read, as -D definitions.
std::string buildOptionsFor(const WorkSizes& sizes);

} // namespace rubble::gpu

// host/gpu/tuning.cpp: the table of the kernels' tuning parameters and what is derived from it:
// the defaults on a device, values given in their place, and the program's -D build options.
#include "host/gpu/tuning.h"

#include <algorithm>
#include <array>

namespace rubble::gpu {
namespace {

// The largest power of two at most x (1 for x = 0).
std::uint32_t floorPow2(std::uint64_t x) {
    std::uint32_t p = 1;
    while (std::uint64_t(p) * 2 <= x && p < (1u << 30)) p *= 2;
    return p;
}

std::uint32_t units(const DeviceInfo& d) {
    return std::max<std::uint32_t>(1, d.computeUnits);
}

// Groups of 64, or the device's largest if smaller: a wavefront on AMD, two warps on NVIDIA,
// one vector loop of PoCL's CPU device. No kernel uses local memory beyond a few words, so
// CL_DEVICE_LOCAL_MEM_SIZE sets no limit.
std::uint32_t groupFor(const DeviceInfo& d) {
    return std::min<std::uint32_t>(64, floorPow2(std::max<std::uint64_t>(1, d.maxWorkGroupSize)));
}

const std::array<TuningParameter, 8> kTable = {{
    {"sortItems", &WorkSizes::sortItems, "RUBBLE_SORT_ITEMS", false,
     "work-items of a radix sort pass and of the broad phase's bounds, each over a chunk",
     "64 per compute unit, a power of two in 256 - 4096", TuningSource::Device,
     "CL_DEVICE_MAX_COMPUTE_UNITS", TuningEffect::Order,
     [](const DeviceInfo& d) {
         return std::clamp<std::uint32_t>(floorPow2(2 * std::uint64_t(units(d)) * 64 - 1), 256,
                                          4096);
     }},
    {"broadGroup", &WorkSizes::broadGroup, "RUBBLE_GROUP_BROAD", false,
     "work-group of the SAT broad phase's per-body and per-entry kernels",
     "64, or the device's largest work-group if smaller (a power of two)", TuningSource::Device,
     "CL_DEVICE_MAX_WORK_GROUP_SIZE", TuningEffect::Order, groupFor},
    {"pairGroup", &WorkSizes::pairGroup, "RUBBLE_GROUP_PAIRS", false,
     "work-group of the pair kernels: narrow phase, PGS summaries and sweeps, still pairs, sleep",
     "64, or the device's largest work-group if smaller (a power of two)", TuningSource::Device,
     "CL_DEVICE_MAX_WORK_GROUP_SIZE", TuningEffect::Order, groupFor},
    {"contiguousItems", &WorkSizes::contiguousItems, "RUBBLE_CONTIGUOUS_ITEMS", true,
     "a strided launch's work-item takes a run of consecutive items (1) or its group's items one "
     "group-width apart (0)",
     "1 on a CPU device (one core runs a group's work-items in turn), 0 on a GPU (adjacent lanes "
     "read adjacent items)",
     TuningSource::Device, "CL_DEVICE_TYPE", TuningEffect::Order,
     [](const DeviceInfo& d) { return std::uint32_t(d.cpu); }},
    {"jointDouble", &WorkSizes::jointDouble, "RUBBLE_JOINT_DOUBLE", true,
     "the joints' position projection factors its matrices in double (1), as the CPU's does, or "
     "in float (0)",
     "1 on a device with fp64, else 0", TuningSource::Device, "CL_DEVICE_DOUBLE_FP_CONFIG",
     TuningEffect::Precision, [](const DeviceInfo& d) { return std::uint32_t(d.fp64); }},
    {"pgsBlocks", &WorkSizes::pgsBlocks, "", false,
     "blocks of the PGS solve (launch mode RUBBLE_PGS_BLOCKS), each a range of bodies swept in "
     "order by one work-item; 0: every element colored (RunOptions::pgsBlocks overrides it)",
     "4 per compute unit on a CPU device, 0 on a GPU (a block runs on one lane)",
     TuningSource::Device, "CL_DEVICE_TYPE, CL_DEVICE_MAX_COMPUTE_UNITS", TuningEffect::Solver,
     [](const DeviceInfo& d) { return d.cpu ? 4 * units(d) : 0u; }},
    {"pgsBlockBodies", &WorkSizes::pgsBlockBodies, "", false,
     "least bodies of a PGS block when the device chooses the count: a smaller world runs in "
     "fewer blocks, one below twice this, sweeping its rows in the CPU's order",
     "128", TuningSource::Measurement,
     "solve stage of pyramid_20 and debris_1k with --pgs-blocks 1, 2, 4, 8 (rubble run "
     "--metrics)",
     TuningEffect::Solver, [](const DeviceInfo&) { return kPgsBlockBodies; }},
    {"serialElements", &WorkSizes::serialElements, "", false,
     "most elements of the serial tail (launch mode RUBBLE_PGS_SERIAL): the last colors of a "
     "step, once together they hold no more, run in color order in one launch on one work-item",
     "128", TuningSource::Measurement,
     "solve stage of debris_16k colored (--pgs-blocks 0, rubble run --metrics): a launch against "
     "the tail's serial work",
     TuningEffect::Order, [](const DeviceInfo&) { return kSerialElements; }},
}};

} // namespace

std::span<const TuningParameter> tuningParameters() {
    return kTable;
}

WorkSizes workSizesFor(const DeviceInfo& device) {
    WorkSizes w;
    for (const TuningParameter& p : kTable) w.*p.field = p.choose(device);
    return w;
}

Result<WorkSizes> tunedWorkSizes(WorkSizes sizes, std::span<const TuningValue> values,
                                 const DeviceInfo& device) {
    for (const TuningValue& v : values) {
        const auto p = std::find_if(kTable.begin(), kTable.end(),
                                    [&](const TuningParameter& t) { return t.name == v.name; });
        const std::string where = "tuning " + std::string(v.name);
        if (p == kTable.end()) {
            std::string names;
            for (const TuningParameter& t : kTable)
                names += (names.empty() ? "" : ", ") + std::string(t.name);
            return makeError(ErrorKind::BadInput, where,
                             "is not a tuning parameter; they are " + names);
        }
        if (p->flag && v.value > 1)
            return makeError(ErrorKind::BadInput, where,
                             "is 0 or 1, not " + std::to_string(v.value));
        const bool group = p->field == &WorkSizes::broadGroup || p->field == &WorkSizes::pairGroup;
        if ((group || p->field == &WorkSizes::sortItems) && v.value == 0)
            return makeError(ErrorKind::BadInput, where, "must be at least 1");
        if (group && v.value > device.maxWorkGroupSize)
            return makeError(ErrorKind::BadInput, where,
                             std::to_string(v.value) + " is more than the device's largest " +
                                 "work-group, " + std::to_string(device.maxWorkGroupSize));
        sizes.*p->field = v.value;
    }
    return sizes;
}

std::uint32_t defaultPgsBlocks(std::uint32_t deviceBlocks, std::size_t bodies,
                               std::uint32_t blockBodies) {
    if (deviceBlocks == 0) return 0;
    const std::size_t fit =
        std::max<std::size_t>(1, bodies / std::max<std::uint32_t>(1, blockBodies));
    return std::uint32_t(std::min<std::size_t>(deviceBlocks, fit));
}

std::string buildOptionsFor(const WorkSizes& sizes) {
    std::string options = kBuildOptions;
    for (const TuningParameter& p : kTable) {
        if (p.define.empty()) continue;
        options += " -D" + std::string(p.define) + "=" + std::to_string(sizes.*p.field) +
                   (p.flag ? "" : "u");
    }
    return options;
}

} // namespace rubble::gpu

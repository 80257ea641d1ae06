// host/gpu/profile.cpp: reading OpenCL profiling events into stage and kernel times.
#include "host/gpu/profile.h"

#include <algorithm>
#include <iterator>
#include <limits>

#include "host/core/clock.h"
#include "host/gpu/cl_check.h"

namespace rubble::gpu {
namespace {

constexpr unsigned kKernels = static_cast<unsigned>(KernelId::Count);
constexpr std::string_view kTransferNames[] = {"(write to device)", "(read from device)",
                                               "(copy on device)", "(fill on device)"};

static_assert(std::size(kDeviceStageFields) == static_cast<std::size_t>(DeviceStage::Count),
              "kDeviceStageFields has one entry per DeviceStage, in its order");

double& stageField(DeviceStageMs& s, DeviceStage stage) {
    return s.*kDeviceStageFields[static_cast<unsigned>(stage)].ms;
}

} // namespace

std::string_view stageName(DeviceStage stage) {
    return kDeviceStageFields[static_cast<unsigned>(stage)].name;
}

Result<DeviceClockSample> sampleClock(cl_command_queue queue, int tries) {
    // An idle queue: each marker runs as soon as it is enqueued, and the wait is short.
    RUBBLE_CL_CHECK(clFinish(queue));
    DeviceClockSample best;
    for (int t = 0; t < tries; ++t) {
        cl_event marker = nullptr;
        const std::int64_t before = steadyNs(Clock::now());
        RUBBLE_CL_CHECK(clEnqueueMarkerWithWaitList(queue, 0, nullptr, &marker));
        const std::int64_t after = steadyNs(Clock::now());
        cl_ulong queued = 0;
        const cl_int waited = clWaitForEvents(1, &marker);
        const cl_int read = waited != CL_SUCCESS
                                ? waited
                                : clGetEventProfilingInfo(marker, CL_PROFILING_COMMAND_QUEUED,
                                                          sizeof queued, &queued, nullptr);
        clReleaseEvent(marker);
        if (waited != CL_SUCCESS) return clError("clWaitForEvents", waited);
        if (read != CL_SUCCESS) return clError("clGetEventProfilingInfo", read);
        if (t == 0 || after - before < best.hostAfterNs - best.hostBeforeNs)
            best = DeviceClockSample{queued, before, after};
    }
    return best;
}

Profile::Profile() {
    totals_.resize(kKernels + static_cast<unsigned>(Transfer::Count));
    for (unsigned k = 0; k < kKernels; ++k) totals_[k].name = signatureOf(KernelId(k)).name;
    for (unsigned t = 0; t < static_cast<unsigned>(Transfer::Count); ++t)
        totals_[kKernels + t].name = kTransferNames[t];
}

Profile::~Profile() { discard(); }

cl_event* Profile::add(unsigned command, std::size_t bytes) {
    records_.push_back(Record{command, stage_, bytes, nullptr});
    return &records_.back().event;
}

cl_event* Profile::kernel(KernelId id) { return add(static_cast<unsigned>(id), 0); }

cl_event* Profile::transfer(Transfer kind, std::size_t bytes) {
    return add(kKernels + static_cast<unsigned>(kind), bytes);
}

void Profile::setLastBytes(std::size_t bytes) {
    if (!records_.empty()) records_.back().bytes = bytes;
}

void Profile::discard() {
    for (Record& r : records_)
        if (r.event) clReleaseEvent(r.event);
    records_.clear();
}

Result<DeviceTimes> Profile::collect(const TrafficCounts& counts) {
    DeviceTimes t;
    cl_ulong first = std::numeric_limits<cl_ulong>::max(), last = 0;
    Status failed;
    lastCommands_.clear();
    for (Record& r : records_) {
        if (!r.event || !failed.ok()) continue;
        cl_ulong queued = 0, submit = 0, start = 0, end = 0;
        failed = [&]() -> Status {
            if (keepCommands_) {
                RUBBLE_CL_CHECK(clGetEventProfilingInfo(r.event, CL_PROFILING_COMMAND_QUEUED,
                                                        sizeof queued, &queued, nullptr));
                RUBBLE_CL_CHECK(clGetEventProfilingInfo(r.event, CL_PROFILING_COMMAND_SUBMIT,
                                                        sizeof submit, &submit, nullptr));
            }
            RUBBLE_CL_CHECK(clGetEventProfilingInfo(r.event, CL_PROFILING_COMMAND_START,
                                                    sizeof start, &start, nullptr));
            RUBBLE_CL_CHECK(clGetEventProfilingInfo(r.event, CL_PROFILING_COMMAND_END, sizeof end,
                                                    &end, nullptr));
            return {};
        }();
        if (!failed.ok()) continue;
        if (keepCommands_)
            lastCommands_.push_back(DeviceCommand{totals_[r.command].name, stageName(r.stage),
                                                  queued, submit, start, end});
        const double ms = end > start ? double(end - start) * 1e-6 : 0.0;
        first = std::min(first, start);
        last = std::max(last, end);
        t.busyMs += ms;
        stageField(t.stages, r.stage) += ms;
        CommandTotals& total = totals_[r.command];
        total.ms += ms;
        total.launches += 1;
        total.bytes += r.bytes > 0 || r.command >= kKernels
                           ? r.bytes
                           : kernelBytes(KernelId(r.command), counts);
    }
    discard();
    if (!failed.ok()) lastCommands_.clear();
    RUBBLE_TRY(failed);
    if (last > first) t.spanMs = double(last - first) * 1e-6;
    return t;
}

void Profile::addTotals(const Profile& other) {
    for (std::size_t k = 0; k < totals_.size(); ++k) {
        totals_[k].ms += other.totals_[k].ms;
        totals_[k].launches += other.totals_[k].launches;
        totals_[k].bytes += other.totals_[k].bytes;
    }
}

std::vector<CommandTotals> Profile::totals() const {
    std::vector<CommandTotals> out;
    for (const CommandTotals& c : totals_)
        if (c.launches > 0) out.push_back(c);
    return out;
}

} // namespace rubble::gpu

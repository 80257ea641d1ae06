// host/gpu/stage_queue.cpp: the queue, profile and status block the device stages share.
#include "host/gpu/stage_queue.h"

#include <algorithm>
#include <cstring>

#include "host/core/math.h"

namespace rubble::gpu {

Status reserveGrowing(const Context& c, Buffer& b, std::size_t bytes, CallSite where) {
    if (b.bytes() >= bytes) return {};
    return b.reserve(c.context(), std::max<std::size_t>(bytes + bytes / 2, 4096), where);
}

Result<std::unique_ptr<StageQueue>> StageQueue::create(std::shared_ptr<Context> context) {
    std::unique_ptr<StageQueue> q(new StageQueue(std::move(context)));
    RUBBLE_TRY(q->status_.reserve(q->c().context(), RUBBLE_STATUS_COUNT * sizeof(cl_uint)));
    RUBBLE_TRY(q->roundStatus_.reserve(q->c().context(), RUBBLE_STATUS_COUNT * sizeof(cl_uint)));
    // A status block that stages run alone (twin tests) can read: all zero.
    const std::span<const cl_uint> zeros(q->statusHost_.data(), RUBBLE_STATUS_COUNT);
    RUBBLE_TRY(upload(q->c(), q->status_, zeros));
    RUBBLE_TRY(upload(q->c(), q->roundStatus_, zeros));
    RUBBLE_TRY(q->finish());
    return q;
}

std::size_t StageQueue::strideItems(std::uint32_t capacity, std::size_t group) const {
    const std::size_t units = std::max<std::uint32_t>(1, context_->device().computeUnits);
    return std::min(units * RUBBLE_STRIDE_GROUPS_PER_UNIT * group, roundUp(capacity, group));
}

Status StageQueue::copy(const Buffer& from, const Buffer& to, std::size_t bytes,
                        std::size_t fromOffset, std::size_t toOffset) {
    if (bytes == 0) return {};
    RUBBLE_CL_CHECK(clEnqueueCopyBuffer(context_->queue(), from.mem(), to.mem(), fromOffset,
                                        toOffset, bytes, 0, nullptr,
                                        profile_.transfer(Transfer::Copy, bytes)));
    return {};
}

Status StageQueue::finish() {
    profile_.countWait();
    RUBBLE_CL_CHECK(clFinish(context_->queue()));
    return {};
}

Status StageQueue::resetStatus(cl_uint capacity) {
    statusInit_ = {};
    statusInit_[RUBBLE_STATUS_NONFINITE] = 0xffffffffu;
    statusInit_[RUBBLE_STATUS_CAPACITY] = capacity;
    // Non-blocking: statusInit_ stays put until the step is met.
    return enqueueUpload(*context_, status_, std::span<const cl_uint>(statusInit_), &profile_);
}

namespace {

DeviceStatus statusOf(const cl_uint* slots) {
    DeviceStatus d;
    d.contacts = slots[RUBBLE_STATUS_CONTACTS];
    d.firstNonFinite = slots[RUBBLE_STATUS_NONFINITE];
    std::memcpy(&d.largestPenetration, &slots[RUBBLE_STATUS_PENETRATION], sizeof(float));
    std::memcpy(&d.solverResidual, &slots[RUBBLE_STATUS_RESIDUAL], sizeof(float));
    d.capacity = slots[RUBBLE_STATUS_CAPACITY];
    d.asleep = slots[RUBBLE_STATUS_ASLEEP];
    d.woken = slots[RUBBLE_STATUS_WOKEN];
    d.fellAsleep = slots[RUBBLE_STATUS_FELL_ASLEEP];
    d.pairs = slots[RUBBLE_STATUS_PAIRS];
    d.gridEntries = slots[RUBBLE_STATUS_GRID_ENTRIES];
    d.largeBodies = slots[RUBBLE_STATUS_LARGE];
    d.kept = slots[RUBBLE_STATUS_KEPT];
    d.carried = slots[RUBBLE_STATUS_CARRIED];
    d.impulses = slots[RUBBLE_STATUS_IMPULSES];
    d.pushes = slots[RUBBLE_STATUS_PUSHED] != 0;
    d.bounces = slots[RUBBLE_STATUS_BOUNCES] != 0;
    d.layers = slots[RUBBLE_STATUS_LAYERS] != 0;
    std::memcpy(&d.energy, &slots[RUBBLE_STATUS_ENERGY], sizeof(float));
    std::memcpy(&d.energyScale, &slots[RUBBLE_STATUS_ENERGY_SCALE], sizeof(float));
    return d;
}

} // namespace

DeviceStatus StageQueue::lastStatus() const {
    return statusOf(statusHost_.data());
}

DeviceStatus StageQueue::roundStatus() const {
    return statusOf(statusHost_.data() + RUBBLE_STATUS_COUNT);
}

Status StageQueue::keepRoundStatus() {
    return copy(status_, roundStatus_, RUBBLE_STATUS_COUNT * sizeof(cl_uint));
}

void StageQueue::assumeStatus(const DeviceStatus& d) {
    cl_uint* slots = statusHost_.data();
    slots[RUBBLE_STATUS_CONTACTS] = d.contacts;
    slots[RUBBLE_STATUS_NONFINITE] = d.firstNonFinite;
    std::memcpy(&slots[RUBBLE_STATUS_PENETRATION], &d.largestPenetration, sizeof(float));
    std::memcpy(&slots[RUBBLE_STATUS_RESIDUAL], &d.solverResidual, sizeof(float));
    slots[RUBBLE_STATUS_CAPACITY] = d.capacity;
    slots[RUBBLE_STATUS_ASLEEP] = d.asleep;
    slots[RUBBLE_STATUS_WOKEN] = d.woken;
    slots[RUBBLE_STATUS_FELL_ASLEEP] = d.fellAsleep;
    slots[RUBBLE_STATUS_PAIRS] = d.pairs;
    slots[RUBBLE_STATUS_GRID_ENTRIES] = d.gridEntries;
    slots[RUBBLE_STATUS_LARGE] = d.largeBodies;
    slots[RUBBLE_STATUS_KEPT] = d.kept;
    slots[RUBBLE_STATUS_CARRIED] = d.carried;
    slots[RUBBLE_STATUS_IMPULSES] = d.impulses;
    slots[RUBBLE_STATUS_PUSHED] = d.pushes;
    slots[RUBBLE_STATUS_BOUNCES] = d.bounces;
    slots[RUBBLE_STATUS_LAYERS] = d.layers;
}

Result<DeviceStatus> StageQueue::readStatus() {
    // Timed: in a step it is the device's work while the host waits (a read outside a step is
    // dropped with the records at the next step).
    RUBBLE_TRY(download(*context_, status_,
                        std::span<cl_uint>(statusHost_.data(), RUBBLE_STATUS_COUNT), &profile_));
    return lastStatus();
}

Status StageQueue::enqueueStatusRead() {
    // Non-blocking: statusHost_ stays put until the step is met.
    RUBBLE_TRY(enqueueDownload(*context_, status_,
                               std::span<cl_uint>(statusHost_.data(), RUBBLE_STATUS_COUNT),
                               &profile_));
    RUBBLE_TRY(enqueueDownload(*context_, roundStatus_,
                               std::span<cl_uint>(statusHost_.data() + RUBBLE_STATUS_COUNT,
                                                  RUBBLE_STATUS_COUNT),
                               &profile_));
    RUBBLE_CL_CHECK(clFlush(context_->queue()));
    return {};
}

Status StageQueue::writeStatusSlot(std::uint32_t slot, cl_uint value) {
    statusHost_[slot] = value;
    profile_.countWait();
    return writeBytes(*context_, status_, slot * sizeof(cl_uint), &value, sizeof value, Wait::Done);
}

} // namespace rubble::gpu

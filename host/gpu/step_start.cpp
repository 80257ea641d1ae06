// host/gpu/step_start.cpp: the device state a step starts from, kept on the device.
#include "host/gpu/step_start.h"

namespace rubble::gpu {

Status StepStart::keep(StageQueue& q, std::span<const Buffer* const> state) {
    kept_.assign(state.begin(), state.end());
    if (copies_.size() < kept_.size()) copies_.resize(kept_.size());
    for (std::size_t i = 0; i < kept_.size(); ++i) {
        RUBBLE_TRY(copies_[i].reserve(q.c().context(), kept_[i]->bytes()));
        RUBBLE_TRY(q.copy(*kept_[i], copies_[i], kept_[i]->bytes()));
    }
    return {};
}

Status StepStart::restore(StageQueue& q) {
    for (std::size_t i = 0; i < kept_.size(); ++i)
        RUBBLE_TRY(q.copy(copies_[i], *kept_[i], kept_[i]->bytes()));
    return {};
}

} // namespace rubble::gpu

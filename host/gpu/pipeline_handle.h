// host/gpu/pipeline_handle.h: the owning pointer to a device pipeline that WorldState holds
// without seeing the OpenCL types.
#pragma once

#include <memory>

namespace rubble::gpu {

class Pipeline;

struct PipelineDeleter {
    void operator()(Pipeline* p) const;
};

using PipelineHandle = std::unique_ptr<Pipeline, PipelineDeleter>;

} // namespace rubble::gpu

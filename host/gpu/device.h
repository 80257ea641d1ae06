// host/gpu/device.h: the OpenCL platforms and devices of this machine, and the choice of one by
// RunOptions::device (`rubble devices` lists them).
#pragma once

#include <CL/cl.h>

#include <cstdint>
#include <string>
#include <vector>

#include "rubble/error.h"

namespace rubble::gpu {

/// One device of one platform; `index` counts every device of every platform in order.
struct DeviceInfo {
    std::uint32_t index = 0;
    std::string platform;     ///< platform name
    std::string name;         ///< device name
    std::string version;      ///< CL_DEVICE_VERSION
    std::string driver;       ///< CL_DRIVER_VERSION
    std::uint32_t computeUnits = 0;
    std::uint64_t globalMemory = 0; ///< bytes
    std::uint64_t maxAllocation = 0; ///< bytes, largest single buffer
    std::uint64_t maxWorkGroupSize = 0; ///< CL_DEVICE_MAX_WORK_GROUP_SIZE, work-items
    std::uint64_t localMemory = 0;      ///< CL_DEVICE_LOCAL_MEM_SIZE, bytes per work-group
    bool cpu = false;                   ///< CL_DEVICE_TYPE_CPU: cores, not lanes by the thousand
    bool fp64 = false;                  ///< CL_DEVICE_DOUBLE_FP_CONFIG not 0: double precision
    cl_platform_id platformId = nullptr;
    cl_device_id id = nullptr;
};

/// Every device of every platform. Errors: NotSupported when there is no OpenCL platform (the
/// message says how to install PoCL), Device for a failing query.
Result<std::vector<DeviceInfo>> listDevices();

/// The device `spec` names: empty for the first, a number for that index, else the first whose
/// "platform device" name contains spec (case-insensitive). Errors: BadInput at `--device`
/// listing the devices there are, or those of listDevices().
Result<DeviceInfo> chooseDevice(const std::string& spec);

} // namespace rubble::gpu

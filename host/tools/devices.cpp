// host/tools/devices.cpp: the OpenCL devices of this machine as a host program sees them
// (`rubble devices` prints them; the Python package returns them).
#include "host/gpu/device.h"
#include "rubble/tools.h"

namespace rubble {

Result<std::vector<DeviceDesc>> openClDevices() {
    Result<std::vector<gpu::DeviceInfo>> devices = gpu::listDevices();
    RUBBLE_TRY(devices);
    std::vector<DeviceDesc> out;
    for (const gpu::DeviceInfo& d : *devices)
        out.push_back(DeviceDesc{d.index, d.platform, d.name, d.version, d.driver, d.computeUnits,
                                 d.globalMemory, d.maxAllocation});
    return out;
}

} // namespace rubble

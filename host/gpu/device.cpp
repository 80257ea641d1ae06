// host/gpu/device.cpp: enumerating OpenCL devices and choosing one.
#include "host/gpu/device.h"

#include <algorithm>
#include <cctype>

#include "host/gpu/cl_check.h"

namespace rubble::gpu {
namespace {

constexpr cl_int kPlatformNotFound = -1001; // CL_PLATFORM_NOT_FOUND_KHR, from the ICD loader

Error noPlatform() {
    return makeError(ErrorKind::NotSupported, "--backend opencl",
                     "no OpenCL platform is installed on this machine; install PoCL, the CPU "
                     "OpenCL device, with `apt-get install pocl-opencl-icd` (scripts/setup.sh "
                     "does), or a GPU vendor's OpenCL driver");
}

template <class Query, class Object>
Result<std::string> infoString(Query query, Object object, cl_uint param) {
    std::size_t size = 0;
    RUBBLE_CL_CHECK(query(object, param, 0, nullptr, &size));
    std::string s(size, '\0');
    RUBBLE_CL_CHECK(query(object, param, size, s.data(), nullptr));
    while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
    return s;
}

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower((unsigned char)c));
    return s;
}

} // namespace

Result<std::vector<DeviceInfo>> listDevices() {
    cl_uint platformCount = 0;
    const cl_int err = clGetPlatformIDs(0, nullptr, &platformCount);
    if (err == kPlatformNotFound || (err == CL_SUCCESS && platformCount == 0)) return noPlatform();
    RUBBLE_CL_CHECK(err);
    std::vector<cl_platform_id> platforms(platformCount);
    RUBBLE_CL_CHECK(clGetPlatformIDs(platformCount, platforms.data(), nullptr));
    std::vector<DeviceInfo> devices;
    for (cl_platform_id p : platforms) {
        Result<std::string> platformName = infoString(clGetPlatformInfo, p, CL_PLATFORM_NAME);
        RUBBLE_TRY(platformName);
        cl_uint count = 0;
        const cl_int e = clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &count);
        if (e == CL_DEVICE_NOT_FOUND) continue;
        RUBBLE_CL_CHECK(e);
        std::vector<cl_device_id> ids(count);
        RUBBLE_CL_CHECK(clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr));
        for (cl_device_id id : ids) {
            DeviceInfo d;
            d.index = std::uint32_t(devices.size());
            d.platform = *platformName;
            d.platformId = p;
            d.id = id;
            Result<std::string> name = infoString(clGetDeviceInfo, id, CL_DEVICE_NAME);
            Result<std::string> version = infoString(clGetDeviceInfo, id, CL_DEVICE_VERSION);
            Result<std::string> driver = infoString(clGetDeviceInfo, id, CL_DRIVER_VERSION);
            RUBBLE_TRY(name);
            RUBBLE_TRY(version);
            RUBBLE_TRY(driver);
            d.name = *name;
            d.version = *version;
            d.driver = *driver;
            cl_uint units = 0;
            cl_ulong memory = 0, allocation = 0;
            RUBBLE_CL_CHECK(clGetDeviceInfo(id, CL_DEVICE_MAX_COMPUTE_UNITS, sizeof units, &units,
                                            nullptr));
            RUBBLE_CL_CHECK(clGetDeviceInfo(id, CL_DEVICE_GLOBAL_MEM_SIZE, sizeof memory, &memory,
                                            nullptr));
            RUBBLE_CL_CHECK(clGetDeviceInfo(id, CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof allocation,
                                            &allocation, nullptr));
            std::size_t group = 0;
            cl_ulong local = 0;
            RUBBLE_CL_CHECK(
                clGetDeviceInfo(id, CL_DEVICE_MAX_WORK_GROUP_SIZE, sizeof group, &group, nullptr));
            RUBBLE_CL_CHECK(
                clGetDeviceInfo(id, CL_DEVICE_LOCAL_MEM_SIZE, sizeof local, &local, nullptr));
            d.computeUnits = units;
            d.globalMemory = memory;
            d.maxAllocation = allocation;
            d.maxWorkGroupSize = group;
            d.localMemory = local;
            cl_device_type type = 0;
            RUBBLE_CL_CHECK(clGetDeviceInfo(id, CL_DEVICE_TYPE, sizeof type, &type, nullptr));
            d.cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
            // A device without double precision reports no FP config for it (or fails the
            // query, as an OpenCL 1.0 device may): float then.
            cl_device_fp_config doubles = 0;
            if (clGetDeviceInfo(id, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof doubles, &doubles,
                                nullptr) != CL_SUCCESS)
                doubles = 0;
            d.fp64 = doubles != 0;
            devices.push_back(std::move(d));
        }
    }
    if (devices.empty()) return noPlatform();
    return devices;
}

Result<DeviceInfo> chooseDevice(const std::string& spec) {
    Result<std::vector<DeviceInfo>> devices = listDevices();
    RUBBLE_TRY(devices);
    if (spec.empty()) return devices->front();
    const bool isIndex = std::all_of(spec.begin(), spec.end(),
                                     [](char c) { return std::isdigit((unsigned char)c) != 0; });
    for (const DeviceInfo& d : *devices) {
        if (isIndex ? std::to_string(d.index) == spec
                    : lower(d.platform + " " + d.name).find(lower(spec)) != std::string::npos)
            return d;
    }
    std::string there;
    for (const DeviceInfo& d : *devices)
        there += (there.empty() ? "" : ", ") + std::to_string(d.index) + " \"" + d.name + "\" (" +
                 d.platform + ")";
    return makeError(ErrorKind::BadInput, "--device",
                     "no OpenCL device matches \"" + spec + "\"; the devices are: " + there +
                         " (by index or a part of the name; `rubble devices` lists them)");
}

} // namespace rubble::gpu

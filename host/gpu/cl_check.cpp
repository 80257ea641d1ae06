// host/gpu/cl_check.cpp: OpenCL error codes by name, and the errors RUBBLE_CL_CHECK returns.
#include "host/gpu/cl_check.h"

#include <cctype>
#include <string>

namespace rubble::gpu {

const char* clErrorName(cl_int code) {
    switch (code) {
#define RUBBLE_CL_CODE(c)                                                                          \
    case c: return #c;
        RUBBLE_CL_CODE(CL_SUCCESS)
        RUBBLE_CL_CODE(CL_DEVICE_NOT_FOUND)
        RUBBLE_CL_CODE(CL_DEVICE_NOT_AVAILABLE)
        RUBBLE_CL_CODE(CL_COMPILER_NOT_AVAILABLE)
        RUBBLE_CL_CODE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        RUBBLE_CL_CODE(CL_OUT_OF_RESOURCES)
        RUBBLE_CL_CODE(CL_OUT_OF_HOST_MEMORY)
        RUBBLE_CL_CODE(CL_PROFILING_INFO_NOT_AVAILABLE)
        RUBBLE_CL_CODE(CL_MEM_COPY_OVERLAP)
        RUBBLE_CL_CODE(CL_BUILD_PROGRAM_FAILURE)
        RUBBLE_CL_CODE(CL_MAP_FAILURE)
        RUBBLE_CL_CODE(CL_MISALIGNED_SUB_BUFFER_OFFSET)
        RUBBLE_CL_CODE(CL_EXEC_STATUS_ERROR_FOR_EVENTS_IN_WAIT_LIST)
        RUBBLE_CL_CODE(CL_COMPILE_PROGRAM_FAILURE)
        RUBBLE_CL_CODE(CL_LINK_PROGRAM_FAILURE)
        RUBBLE_CL_CODE(CL_KERNEL_ARG_INFO_NOT_AVAILABLE)
        RUBBLE_CL_CODE(CL_INVALID_VALUE)
        RUBBLE_CL_CODE(CL_INVALID_DEVICE_TYPE)
        RUBBLE_CL_CODE(CL_INVALID_PLATFORM)
        RUBBLE_CL_CODE(CL_INVALID_DEVICE)
        RUBBLE_CL_CODE(CL_INVALID_CONTEXT)
        RUBBLE_CL_CODE(CL_INVALID_QUEUE_PROPERTIES)
        RUBBLE_CL_CODE(CL_INVALID_COMMAND_QUEUE)
        RUBBLE_CL_CODE(CL_INVALID_HOST_PTR)
        RUBBLE_CL_CODE(CL_INVALID_MEM_OBJECT)
        RUBBLE_CL_CODE(CL_INVALID_BINARY)
        RUBBLE_CL_CODE(CL_INVALID_BUILD_OPTIONS)
        RUBBLE_CL_CODE(CL_INVALID_PROGRAM)
        RUBBLE_CL_CODE(CL_INVALID_PROGRAM_EXECUTABLE)
        RUBBLE_CL_CODE(CL_INVALID_KERNEL_NAME)
        RUBBLE_CL_CODE(CL_INVALID_KERNEL_DEFINITION)
        RUBBLE_CL_CODE(CL_INVALID_KERNEL)
        RUBBLE_CL_CODE(CL_INVALID_ARG_INDEX)
        RUBBLE_CL_CODE(CL_INVALID_ARG_VALUE)
        RUBBLE_CL_CODE(CL_INVALID_ARG_SIZE)
        RUBBLE_CL_CODE(CL_INVALID_KERNEL_ARGS)
        RUBBLE_CL_CODE(CL_INVALID_WORK_DIMENSION)
        RUBBLE_CL_CODE(CL_INVALID_WORK_GROUP_SIZE)
        RUBBLE_CL_CODE(CL_INVALID_WORK_ITEM_SIZE)
        RUBBLE_CL_CODE(CL_INVALID_GLOBAL_OFFSET)
        RUBBLE_CL_CODE(CL_INVALID_EVENT_WAIT_LIST)
        RUBBLE_CL_CODE(CL_INVALID_EVENT)
        RUBBLE_CL_CODE(CL_INVALID_OPERATION)
        RUBBLE_CL_CODE(CL_INVALID_BUFFER_SIZE)
        RUBBLE_CL_CODE(CL_INVALID_GLOBAL_WORK_SIZE)
        RUBBLE_CL_CODE(CL_INVALID_PROPERTY)
#undef RUBBLE_CL_CODE
    case -1001: return "CL_PLATFORM_NOT_FOUND_KHR";
    default: return "unknown";
    }
}

Error clError(const char* expression, cl_int code) {
    // The first `cl...(` in the checked text is the call.
    const std::string text = expression;
    std::string call = text;
    for (std::size_t i = 0; i + 2 < text.size(); ++i) {
        if (text.compare(i, 2, "cl") != 0 || (i > 0 && (std::isalnum((unsigned char)text[i - 1]) ||
                                                        text[i - 1] == '_')))
            continue;
        std::size_t j = i + 2;
        while (j < text.size() && (std::isalnum((unsigned char)text[j]) || text[j] == '_')) ++j;
        if (j < text.size() && text[j] == '(' && j > i + 2) {
            call = text.substr(i, j - i);
            break;
        }
    }
    return makeError(ErrorKind::Device, call,
                     std::string("failed with ") + clErrorName(code) + " (" +
                         std::to_string(code) + ")");
}

} // namespace rubble::gpu

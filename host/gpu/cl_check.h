// host/gpu/cl_check.h: RUBBLE_CL_CHECK, through which every OpenCL call goes: a failure returns
// a Device error naming the call and the error code from the enclosing function.
#pragma once

#include <CL/cl.h>

#include "rubble/error.h"

namespace rubble::gpu {

/// The name of an OpenCL error code (`CL_OUT_OF_RESOURCES`), or "unknown".
const char* clErrorName(cl_int code);

/// A Device error for a failed call; `expression` is the checked text, from which the name of
/// the OpenCL function is taken.
Error clError(const char* expression, cl_int code);

} // namespace rubble::gpu

/// Evaluates an expression yielding a cl_int; returns clError(...) unless it is CL_SUCCESS.
/// Calls that report through an errcode_ret argument are checked as `(x = clCreate...(..., &err),
/// err)`.
#define RUBBLE_CL_CHECK(call)                                                                      \
    do {                                                                                           \
        const cl_int rubbleClStatus_ = (call);                                                     \
        if (rubbleClStatus_ != CL_SUCCESS) return ::rubble::gpu::clError(#call, rubbleClStatus_);  \
    } while (0)

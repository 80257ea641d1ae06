// host/gpu/buffer.cpp: device buffers and kernel dispatch.
#include "host/gpu/buffer.h"

#include "host/core/assert.h"
#include "host/gpu/memory.h"

namespace rubble::gpu {

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        mem_ = o.mem_;
        context_ = o.context_;
        bytes_ = o.bytes_;
        o.mem_ = nullptr;
        o.bytes_ = 0;
    }
    return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
    if (!mem_) return;
    clReleaseMemObject(mem_);
    forgetBuffer(context_, mem_);
    releaseBuffer(context_, bytes_);
    mem_ = nullptr;
    bytes_ = 0;
}

Status Buffer::reserve(cl_context context, std::size_t bytes, CallSite where) {
    bytes = std::max<std::size_t>(bytes, 16);
    if (mem_ && bytes_ >= bytes) return {};
    // Checked before the old buffer goes: a buffer that does not fit leaves this one as it was.
    RUBBLE_TRY(admitBuffer(context, bytes, mem_ ? bytes_ : 0));
    if (mem_) {
        clReleaseMemObject(mem_); // its bytes were taken off by admitBuffer
        forgetBuffer(context, mem_);
        mem_ = nullptr;
        bytes_ = 0;
    }
    cl_int err = CL_SUCCESS;
    mem_ = clCreateBuffer(context, CL_MEM_READ_WRITE, bytes, nullptr, &err);
    if (err != CL_SUCCESS) {
        mem_ = nullptr;
        releaseBuffer(context, bytes);
        return clError("clCreateBuffer", err);
    }
    context_ = context;
    bytes_ = bytes;
    nameBuffer(context, mem_, bytes, where);
    return {};
}

namespace {
// writeBytes and readBytes: one OpenCL call or the other, the rest alike.
Status copyBytes(const Context& c, const Buffer& b, Transfer kind, std::size_t offset, void* data,
                 std::size_t bytes, Wait wait, Profile* profile) {
    if (bytes == 0) return {};
    cl_event* event = profile ? profile->transfer(kind, bytes) : nullptr;
    const cl_bool blocking = wait == Wait::Done ? CL_TRUE : CL_FALSE;
    if (profile && blocking) profile->countWait();
    const bool write = kind == Transfer::Write;
    const cl_int status =
        write ? clEnqueueWriteBuffer(c.queue(), b.mem(), blocking, offset, bytes, data, 0, nullptr,
                                     event)
              : clEnqueueReadBuffer(c.queue(), b.mem(), blocking, offset, bytes, data, 0, nullptr,
                                    event);
    if (status != CL_SUCCESS)
        return clError(write ? "clEnqueueWriteBuffer" : "clEnqueueReadBuffer", status);
    return {};
}
} // namespace

Status writeBytes(const Context& c, const Buffer& b, std::size_t offset, const void* data,
                  std::size_t bytes, Wait wait, Profile* profile) {
    // clEnqueueWriteBuffer only reads `data`.
    return copyBytes(c, b, Transfer::Write, offset, const_cast<void*>(data), bytes, wait, profile);
}

Status readBytes(const Context& c, const Buffer& b, std::size_t offset, void* data,
                 std::size_t bytes, Wait wait, Profile* profile) {
    return copyBytes(c, b, Transfer::Read, offset, data, bytes, wait, profile);
}

Status fill(const Context& c, const Buffer& b, cl_uint value, std::size_t bytes,
            Profile* profile) {
    return fillRange(c, b, value, 0, bytes, profile);
}

Status fillRange(const Context& c, const Buffer& b, cl_uint value, std::size_t offset,
                 std::size_t bytes, Profile* profile) {
    if (bytes == 0) return {};
    RUBBLE_ASSERT(bytes % sizeof value == 0 && offset % sizeof value == 0 &&
                  offset + bytes <= b.bytes());
    cl_event* event = profile ? profile->transfer(Transfer::Fill, bytes) : nullptr;
    // kernels/grid.cl fillWords, whose writes every checker sees (clEnqueueFillBuffer's are
    // invisible to Oclgrind). A range from a word other than 0 runs at that global offset, the
    // kernel's count being where it ends.
    cl_kernel k = c.kernel(KernelId::FillWords);
    const std::size_t first = offset / sizeof value;
    const cl_uint count = cl_uint(first + bytes / sizeof value);
    const cl_mem out = b.mem();
    RUBBLE_CL_CHECK(clSetKernelArg(k, 0, sizeof count, &count));
    RUBBLE_CL_CHECK(clSetKernelArg(k, 1, sizeof value, &value));
    RUBBLE_CL_CHECK(clSetKernelArg(k, 2, sizeof out, &out));
    const std::size_t local = 64, global = (bytes / sizeof value + local - 1) / local * local;
    const std::size_t* at = first > 0 ? &first : nullptr;
    RUBBLE_CL_CHECK(
        clEnqueueNDRangeKernel(c.queue(), k, 1, at, &global, &local, 0, nullptr, event));
    return {};
}

Dispatch& Dispatch::bind(std::size_t size, const void* value) {
    if (!status_.ok()) return *this;
    status_ = [&]() -> Status {
        RUBBLE_CL_CHECK(clSetKernelArg(kernel_, next_, size, value));
        return {};
    }();
    ++next_;
    return *this;
}

Status Dispatch::run(std::size_t count, std::size_t group) {
    RUBBLE_TRY(status_);
    // Argument order is the kernel signature's: a dispatch that binds too few or too many is a
    // bug in rubble, caught here before the device sees it.
    RUBBLE_ASSERT(next_ == signatureOf(id_).args.size());
    const std::size_t global = roundUp(count, group);
    cl_event* event = profile_ ? profile_->kernel(id_) : nullptr;
    RUBBLE_CL_CHECK(clEnqueueNDRangeKernel(c_.queue(), kernel_, 1, nullptr, &global, &group, 0,
                                           nullptr, event));
    return {};
}

} // namespace rubble::gpu

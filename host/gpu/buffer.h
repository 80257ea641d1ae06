// host/gpu/buffer.h: device buffers that grow and free themselves, host copies in and out, and
// the one-dimensional dispatch of a kernel with its arguments in signature order.
#pragma once

#include <CL/cl.h>

#include <cstddef>
#include <span>
#include <vector>

#include "host/gpu/cl_check.h"
#include "host/gpu/context.h"
#include "host/gpu/memory.h"
#include "host/gpu/profile.h"

namespace rubble::gpu {

/// A cl_mem that keeps its size, released when destroyed. Move-only.
class Buffer {
  public:
    Buffer() = default;
    Buffer(Buffer&& o) noexcept : mem_(o.mem_), context_(o.context_), bytes_(o.bytes_) {
        o.mem_ = nullptr;
        o.bytes_ = 0;
    }
    Buffer& operator=(Buffer&& o) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;
    ~Buffer();

    /// Makes the buffer hold at least `bytes` (at least 16); a larger buffer loses its contents.
    /// The context's ledger names it by `where`, the call (host/gpu/memory.h, deviceBuffers).
    /// Errors: Limit when the device or the process has no room for it (host/gpu/memory.h; the
    /// buffer then keeps what it held), Device.
    Status reserve(cl_context context, std::size_t bytes, CallSite where = CallSite::here());
    cl_mem mem() const { return mem_; }
    std::size_t bytes() const { return bytes_; }

  private:
    void release();
    cl_mem mem_ = nullptr;
    cl_context context_ = nullptr; ///< whose ledger counts it
    std::size_t bytes_ = 0;
};

/// How a copy between host and device memory waits.
enum class Wait { Done, Queued };

/// The copy of `bytes` host bytes into a buffer from byte `offset` on (writeBytes), or of the
/// buffer's bytes from `offset` on into host memory (readBytes): with Wait::Done the call
/// returns once it is made; with Wait::Queued it is only enqueued, and the host memory must stay
/// put until the queue has run it. `profile` (optional) times it. Nothing is enqueued for 0
/// bytes.
Status writeBytes(const Context& c, const Buffer& b, std::size_t offset, const void* data,
                  std::size_t bytes, Wait wait, Profile* profile = nullptr);
Status readBytes(const Context& c, const Buffer& b, std::size_t offset, void* data,
                 std::size_t bytes, Wait wait, Profile* profile = nullptr);

/// Blocking copy of a host array into the start of a buffer (reserved to fit, named by
/// `where`).
template <class T>
Status upload(const Context& c, Buffer& b, std::span<const T> data,
              CallSite where = CallSite::here()) {
    RUBBLE_TRY(b.reserve(c.context(), data.size_bytes(), where));
    return writeBytes(c, b, 0, data.data(), data.size_bytes(), Wait::Done);
}

/// The same, of a whole vector.
template <class T>
Status upload(const Context& c, Buffer& b, const std::vector<T>& data,
              CallSite where = CallSite::here()) {
    return upload(c, b, std::span<const T>(data), where);
}

/// Non-blocking copy of a host array into the start of a buffer that already holds it: `data`
/// must stay put until the queue has run the copy; `profile` (optional) times it.
template <class T>
Status enqueueUpload(const Context& c, const Buffer& b, std::span<const T> data, Profile* profile) {
    return writeBytes(c, b, 0, data.data(), data.size_bytes(), Wait::Queued, profile);
}

/// Non-blocking copy of the start of a buffer into a host array, which must stay put until the
/// queue has run it; `profile` (optional) times it.
template <class T>
Status enqueueDownload(const Context& c, const Buffer& b, std::span<T> data, Profile* profile) {
    return readBytes(c, b, 0, data.data(), data.size_bytes(), Wait::Queued, profile);
}

/// Blocking copy of the start of a buffer into a host array; `profile` (optional) times it.
template <class T>
Status download(const Context& c, const Buffer& b, std::span<T> data, Profile* profile = nullptr) {
    return readBytes(c, b, 0, data.data(), data.size_bytes(), Wait::Done, profile);
}

/// Blocking copy of the first `count` elements of a buffer into a new vector.
template <class T>
Result<std::vector<T>> download(const Context& c, const Buffer& b, std::size_t count) {
    std::vector<T> data(count);
    RUBBLE_TRY(download(c, b, std::span(data)));
    return data;
}

/// Fills the first `bytes` of a buffer with a repeated 32-bit value; `profile` (optional) times it.
Status fill(const Context& c, const Buffer& b, cl_uint value, std::size_t bytes,
            Profile* profile = nullptr);

/// Fills `bytes` of a buffer from byte `offset` (both multiples of 4) with a repeated 32-bit
/// value: the status block's counters.
Status fillRange(const Context& c, const Buffer& b, cl_uint value, std::size_t offset,
                 std::size_t bytes, Profile* profile = nullptr);

/// The smallest multiple of `group` that holds `count`, at least one group.
inline std::size_t roundUp(std::size_t count, std::size_t group) {
    return count == 0 ? group : (count + group - 1) / group * group;
}

/// Binds a kernel's arguments in signature order and enqueues it; run() fails with the first
/// error of the binding, and asserts that every argument of the signature was bound. With a
/// Profile, the kernel's event is kept for its device time.
class Dispatch {
  public:
    Dispatch(const Context& c, KernelId id, Profile* profile = nullptr)
        : c_(c), id_(id), kernel_(c.kernel(id)), profile_(profile) {}
    template <class T> Dispatch& arg(const T& value) { return bind(sizeof value, &value); }
    Dispatch& arg(const Buffer& b) {
        const cl_mem m = b.mem();
        return bind(sizeof m, &m);
    }
    /// Binds the arguments `bind(*this)` binds: a run of arguments several kernels share.
    template <class F> Dispatch& with(F&& bind) {
        bind(*this);
        return *this;
    }
    /// Enqueues `count` work-items in groups of `group` (the global size rounded up).
    Status run(std::size_t count, std::size_t group);

  private:
    Dispatch& bind(std::size_t size, const void* value);
    const Context& c_;
    KernelId id_;
    cl_kernel kernel_;
    Profile* profile_;
    cl_uint next_ = 0;
    Status status_;
};

} // namespace rubble::gpu

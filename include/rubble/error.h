// include/rubble/error.h: errors that the outside can cause, and the Result/Status that carry them.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace rubble {

/// What went wrong, so that a caller can decide (the command line maps BadInput and
/// NotSupported to exit status 2, Numerical to 3, Limit to 4).
enum class ErrorKind {
    BadInput,     ///< a scene file, mesh, option or API argument is invalid
    NotSupported, ///< the input asks for a feature that is specified but not built
    Io,           ///< a file could not be read or written
    Device,       ///< an OpenCL call or kernel build failed
    Numerical,    ///< the simulation produced a non-finite state or blew up
    Limit,        ///< a step needs more than rubble allows it (pairs, contacts, particles,
                  ///< memory): docs/scene-format.md, "Limits"
    Interrupted,  ///< a stop was requested (RunOptions::stop) and the step stopped between stages
    Internal,     ///< a broken invariant that escaped the asserts
};

/// One error: its kind, where it happened (`scenes/a.json: bodies[3].mass`, `clBuildProgram`)
/// and what was expected, in a full sentence.
struct Error {
    ErrorKind kind = ErrorKind::Internal;
    std::string where;
    std::string message;

    /// The error as one line, `where: message`.
    std::string describe() const { return where.empty() ? message : where + ": " + message; }
};

/// Builds an Error; `where` names the file and field, or the call.
inline Error makeError(ErrorKind kind, std::string where, std::string message) {
    return Error{kind, std::move(where), std::move(message)};
}

/// Success or an Error.
class [[nodiscard]] Status {
  public:
    Status() = default;
    Status(Error e) : error_(std::move(e)), ok_(false) {}
    /// True when no error happened.
    bool ok() const { return ok_; }
    explicit operator bool() const { return ok_; }
    /// The error; only valid when !ok().
    const Error& error() const { return error_; }

  private:
    Error error_;
    bool ok_ = true;
};

/// A value of type T or an Error.
template <class T> class [[nodiscard]] Result {
  public:
    Result(T value) : v_(std::move(value)) {}
    Result(Error e) : v_(std::move(e)) {}
    /// True when a value is held.
    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }
    /// The value; only valid when ok().
    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T* operator->() { return &std::get<0>(v_); }
    const T* operator->() const { return &std::get<0>(v_); }
    T& operator*() & { return std::get<0>(v_); }
    const T& operator*() const& { return std::get<0>(v_); }
    /// The error; only valid when !ok().
    const Error& error() const { return std::get<1>(v_); }
    /// The status without the value.
    Status status() const { return ok() ? Status() : Status(error()); }

  private:
    std::variant<T, Error> v_;
};

} // namespace rubble

/// Returns the error of a Status or Result expression from the enclosing function.
#define RUBBLE_TRY(expr)                                                                           \
    do {                                                                                           \
        if (auto&& rubbleStatus_ = (expr); !rubbleStatus_.ok()) return rubbleStatus_.error();      \
    } while (0)

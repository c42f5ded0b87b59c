// SPDX-License-Identifier: MIT
/// @file error.h
/// Errors as values: every fallible library call returns a Result<T> or a Status the caller checks.
#pragma once

#include <cerrno>
#include <string>
#include <utility>
#include <variant>

namespace infocus {

/// What kind of failure an Error reports; the CLI maps it to an exit status.
enum class ErrorKind {
    Usage,        ///< The caller asked for something invalid (bad option, unknown source string).
    NotFound,     ///< A file, device or camera does not exist.
    Io,           ///< Reading or writing failed (errno is kept in Error::sysErrno).
    Corrupt,      ///< Data exists but is damaged or truncated.
    Unsupported,  ///< Valid request the source or build cannot satisfy (format, backend).
    Device,       ///< A camera device failed (ioctl, disconnect).
    EndOfStream,  ///< A source has no more frames; not a failure for loops over sources.
};

/// A failure: what went wrong, on what, and what to do, in one human-readable message.
struct Error {
    ErrorKind kind = ErrorKind::Io;
    std::string message;  ///< Full sentence(s) for the user; no trailing newline.
    int sysErrno = 0;     ///< errno of the failing system call, 0 if none.
};

/// Builds an Error of @p kind with @p message.
inline Error makeError(ErrorKind kind, std::string message, int sysErrno = 0) {
    return Error{kind, std::move(message), sysErrno};
}

/// A value or an Error (a small std::expected for C++20).
template <typename T>
class [[nodiscard]] Result {
public:
    Result(T value) : v_(std::move(value)) {}      // NOLINT: implicit by design, like expected
    Result(Error error) : v_(std::move(error)) {}  // NOLINT

    /// True when a value is held.
    bool ok() const { return v_.index() == 0; }
    explicit operator bool() const { return ok(); }

    /// The value; only valid when ok().
    T& value() & { return std::get<0>(v_); }
    const T& value() const& { return std::get<0>(v_); }
    T&& value() && { return std::get<0>(std::move(v_)); }
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

    /// The error; only valid when !ok().
    const Error& error() const { return std::get<1>(v_); }

private:
    std::variant<T, Error> v_;
};

/// Success or an Error, for calls with no value to return.
class [[nodiscard]] Status {
public:
    Status() = default;
    Status(Error error) : err_(std::move(error)), failed_(true) {}  // NOLINT

    bool ok() const { return !failed_; }
    explicit operator bool() const { return ok(); }
    /// The error; only valid when !ok().
    const Error& error() const { return err_; }

private:
    Error err_;
    bool failed_ = false;
};

}  // namespace infocus

// SPDX-License-Identifier: MIT
// Shared parts of the Python module: library errors as Python exceptions, and the registration
// functions each file of src/py provides.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <limits>
#include <mutex>
#include <optional>
#include <string>

#include "infocus/error.h"
#include "infocus/frame.h"
#include "infocus/image.h"
#include "infocus/optics.h"

namespace infocus::py {

namespace pb = pybind11;

/// Raises @p e as a Python exception: ValueError for what the caller asked or gave (usage, a
/// missing file, damaged or unsupported data), OSError for a failing device or file system.
[[noreturn]] void raise(const Error& e);

/// The value of @p r, or raise(r.error()).
template <typename T>
T take(Result<T>&& r) {
    if (!r) raise(r.error());
    return std::move(r).value();
}

/// NaN for an empty optional: NumPy arrays of measurements mark "no value" with NaN.
inline double orNan(const std::optional<double>& v) {
    return v ? *v : std::numeric_limits<double>::quiet_NaN();
}

/// Calls a Python progress callback (done, total) from any thread, taking the GIL; a callback
/// that raises stops being called and its exception is raised when the long call returns.
class Progress {
public:
    explicit Progress(pb::object callback) : callback_(std::move(callback)) {}
    /// Reports @p done of @p total (0: unknown); safe from any thread.
    void operator()(uint64_t done, uint64_t total);
    /// Raises the callback's exception, if it raised; call with the GIL held.
    void rethrow();
    bool empty() const { return callback_.is_none(); }

private:
    pb::object callback_;
    std::mutex mutex_;  // one call at a time, in order of the counts
    std::optional<pb::error_already_set> error_;
};

/// infocus.Lens: a thin lens and what a depth reading needs beside it (SI units).
struct Lens {
    optics::ThinLens thin;
    std::optional<double> pixelPitch;     ///< metres per pixel of the analysed image
    std::optional<double> coc;            ///< circle of confusion, metres
    std::optional<double> focusDistance;  ///< metres from the lens (may be ∞)
    std::string name;                     ///< the preset's name, empty when given by hand
};

/// infocus.Frame: a frame of a source with its 8-bit luma (a view into the frame where the
/// format allows), kept alive together.
struct PyFrame {
    Frame frame;
    Luma8 luma;
    uint64_t index = 0;  ///< order among the frames its source delivered
};

void registerAnalysis(pb::module_& m);
void registerSource(pb::module_& m);
void registerOptics(pb::module_& m);
void registerStack(pb::module_& m);

}  // namespace infocus::py

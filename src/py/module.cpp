// SPDX-License-Identifier: MIT
// The extension `infocus._infocus`: thin bindings of the library (src/py/*.cpp register its parts);
// the package `infocus` (src/py/infocus/__init__.py) re-exports them.
#include <Python.h>

#include "infocus_config.h"
#include "py_infocus.h"

namespace infocus::py {

void raise(const Error& e) {
    switch (e.kind) {
        case ErrorKind::Io:
        case ErrorKind::Device:
            // The file system or a camera failed, not the caller's input.
            PyErr_SetString(PyExc_OSError, e.message.c_str());
            throw pb::error_already_set();
        case ErrorKind::EndOfStream:
            throw pb::stop_iteration(e.message);
        default:
            throw pb::value_error(e.message);
    }
}

void Progress::operator()(uint64_t done, uint64_t total) {
    std::lock_guard lock(mutex_);
    pb::gil_scoped_acquire gil;
    if (error_) return;
    try {
        callback_(done, total);
    } catch (pb::error_already_set& e) {
        error_ = std::move(e);
    }
}

void Progress::rethrow() {
    if (error_) throw std::move(*error_);
}

}  // namespace infocus::py

PYBIND11_MODULE(_infocus, m) {
    m.doc() =
        "Per-region sharpness and blur width of camera frames, and the thin-lens optics that "
        "turn blur into distance (the library behind the `infocus` command).";
    m.attr("__version__") = INFOCUS_VERSION;
    infocus::py::registerOptics(m);
    infocus::py::registerSource(m);
    infocus::py::registerAnalysis(m);
    infocus::py::registerStack(m);
}

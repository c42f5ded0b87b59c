// SPDX-License-Identifier: MIT
// infocus.open: any source string as a Python iterator of frames, with its focus control.
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "infocus/luma.h"
#include "infocus/source.h"
#include "py_infocus.h"

namespace infocus::py {

namespace {

// infocus.Source: an open source, its luma converter and its frame count.
struct PySource {
    std::string text;
    std::unique_ptr<FrameSource> source;
    LumaConverter converter;
    uint64_t delivered = 0;

    FrameSource& open() {
        if (!source)
            throw pb::value_error("source '" + text +
                                  "' is closed; open it again with infocus.open('" + text + "')");
        return *source;
    }
    void close() {
        if (!source) return;
        pb::gil_scoped_release release;  // a camera may take a moment to stop
        source->stop();
        source.reset();
    }
};

// infocus.FocusControl: the lens control of a source, valid while the source is open.
struct PyFocus {
    pb::object owner;  // the PySource, kept alive with the control

    FocusControl& control() const {
        PySource& s = owner.cast<PySource&>();
        FocusControl* c = s.open().focusControl();
        if (!c) throw pb::value_error("source '" + s.text + "' has no focus control");
        return *c;
    }
};

pb::dict infoDict(const SourceInfo& i) {
    pb::dict d;
    d["source"] = i.sourceString;
    d["device"] = i.device;
    d["driver"] = i.driver;
    d["format"] = pixelFormatName(i.format);
    d["width"] = i.size.width;
    d["height"] = i.size.height;
    d["fps"] = i.fps;
    d["live_camera"] = i.liveCamera;
    d["frame_count"] = i.frameCount ? pb::cast(*i.frameCount) : pb::none();
    d["transfer"] =
        i.transfer.curve ? pb::cast(transferFunctionName(*i.transfer.curve)) : pb::none();
    return d;
}

pb::object nextFrame(PySource& s) {
    FrameSource& src = s.open();
    for (;;) {
        std::optional<Result<Frame>> f;
        std::optional<Result<Luma8>> luma;
        {
            pb::gil_scoped_release release;  // a camera blocks until its next frame
            f = src.next();
            if (*f) luma = s.converter.toLuma8(**f);
        }
        if (!*f && f->error().kind == ErrorKind::EndOfStream) throw pb::stop_iteration();
        const Error* damaged = !*f ? &f->error() : (!*luma ? &luma->error() : nullptr);
        if (damaged && damaged->kind == ErrorKind::Corrupt) {
            // As `infocus analyze` does: a damaged frame is told and skipped, the next is read.
            if (PyErr_WarnEx(PyExc_RuntimeWarning,
                             ("skipped a damaged frame: " + damaged->message).c_str(), 1) != 0)
                throw pb::error_already_set();
            continue;
        }
        if (damaged) raise(*damaged);
        auto frame = std::make_unique<PyFrame>();
        frame->frame = std::move(**f);
        frame->luma = std::move(**luma);
        frame->index = s.delivered++;
        return pb::cast(std::move(frame));
    }
}

}  // namespace

void registerSource(pb::module_& m) {
    pb::class_<PyFrame>(m, "Frame",
                        "A frame of a source: its 8-bit luma as a read-only NumPy view, its "
                        "time, sequence and lens position. infocus.analyze measures it as the "
                        "command line does (from the frame's own pixels).")
        .def_property_readonly(
            "luma",
            [](pb::object self) {
                const PyFrame& f = self.cast<const PyFrame&>();
                // The view keeps the Frame object, and so the pixels, alive.
                pb::array_t<uint8_t> a({f.luma.height, f.luma.width},
                                       {static_cast<pb::ssize_t>(f.luma.stride), pb::ssize_t{1}},
                                       f.luma.data, self);
                pb::detail::array_proxy(a.ptr())->flags &=
                    ~pb::detail::npy_api::NPY_ARRAY_WRITEABLE_;
                return a;
            },
            "8-bit luma, shape (height, width), a read-only view (no copy).")
        .def_property_readonly(
            "timestamp",
            [](const PyFrame& f) { return static_cast<double>(f.frame.timestampNs) * 1e-9; },
            "Capture time, seconds (CLOCK_MONOTONIC for cameras).")
        .def_property_readonly(
            "timestamp_ns", [](const PyFrame& f) { return f.frame.timestampNs; },
            "Capture time, nanoseconds.")
        .def_property_readonly(
            "sequence", [](const PyFrame& f) { return f.frame.sequence; },
            "The source's frame counter; gaps are dropped frames.")
        .def_property_readonly(
            "index", [](const PyFrame& f) { return f.index; },
            "Order of the frame among those this Source delivered, from 0.")
        .def_property_readonly(
            "lens", [](const PyFrame& f) { return f.frame.lens; },
            "Where the lens was (LensPosition), or None.")
        .def_property_readonly(
            "exposure", [](const PyFrame& f) { return f.frame.exposureS; },
            "Exposure time, seconds, or None.")
        .def_property_readonly(
            "format", [](const PyFrame& f) { return pixelFormatName(f.frame.format); },
            "Pixel format as delivered ('GREY', 'MJPEG', 'YUYV', ...).")
        .def_property_readonly(
            "origin", [](const PyFrame& f) { return f.frame.origin; },
            "The file the frame came from, where the source says ('' otherwise).")
        .def_property_readonly(
            "width", [](const PyFrame& f) { return f.frame.size.width; }, "Pixels.")
        .def_property_readonly(
            "height", [](const PyFrame& f) { return f.frame.size.height; }, "Pixels.")
        .def("__repr__", [](const PyFrame& f) {
            return "<infocus.Frame " + std::to_string(f.index) + " " +
                   pixelFormatName(f.frame.format) + " " + std::to_string(f.frame.size.width) +
                   "x" + std::to_string(f.frame.size.height) + ">";
        });

    pb::class_<FocusRange>(m, "FocusRange", "What a focus control moves and how.")
        .def_readonly("min", &FocusRange::min)
        .def_readonly("max", &FocusRange::max)
        .def_readonly("step", &FocusRange::step, "Smallest meaningful change; 0: continuous.")
        .def_readonly("default", &FocusRange::defaultValue)
        .def_readonly("unit", &FocusRange::unit, "'dioptre', 'v4l2', ...");

    pb::class_<PyFocus>(m, "FocusControl", "Moves the lens of an open source.")
        .def_property_readonly(
            "range", [](const PyFocus& f) { return f.control().range(); }, "The FocusRange.")
        .def(
            "get", [](const PyFocus& f) { return take(f.control().get()); },
            "The current LensPosition.")
        .def(
            "set",
            [](const PyFocus& f, double value) {
                FocusControl& c = f.control();
                Status st;
                {
                    pb::gil_scoped_release release;
                    st = c.set(value);
                }
                if (!st) raise(st.error());
            },
            pb::arg("value"),
            "Moves the lens to `value` (native unit, clamped and rounded to the step); frames "
            "show the move after settle_frames.")
        .def_property_readonly(
            "settle_frames", [](const PyFocus& f) { return f.control().settleFrames(); },
            "Frames to skip after a move.");

    pb::class_<PySource>(m, "Source",
                         "An open source: iterate it for Frames; close() (or a with block) "
                         "releases the camera or file.")
        .def("__iter__", [](pb::object self) { return self; })
        .def("__next__", &nextFrame)
        .def_property_readonly(
            "info", [](PySource& s) { return infoDict(s.open().info()); },
            "What the source delivers: source string, driver, format, size, fps, frame count.")
        .def_property_readonly(
            "focus",
            [](pb::object self) -> pb::object {
                PySource& s = self.cast<PySource&>();
                if (!s.open().focusControl()) return pb::none();
                return pb::cast(PyFocus{self});
            },
            "The FocusControl, or None when the source cannot move its lens.")
        .def_property_readonly(
            "stats",
            [](PySource& s) {
                const SourceStats st = s.open().stats();
                pb::dict d;
                d["delivered"] = st.delivered;
                d["dropped"] = st.dropped;
                d["errors"] = st.errors;
                return d;
            },
            "Frames delivered, dropped and damaged so far.")
        .def_property_readonly(
            "closed", [](const PySource& s) { return !s.source; }, "True after close().")
        .def("close", &PySource::close, "Stops the source; safe to call twice.")
        .def("__enter__", [](pb::object self) { return self; })
        .def("__exit__",
             [](PySource& s, const pb::object&, const pb::object&, const pb::object&) {
                 s.close();
                 return false;
             })
        .def("__repr__", [](const PySource& s) {
            return "<infocus.Source '" + s.text + "'" + (s.source ? "" : " closed") + ">";
        });

    m.def(
        "open",
        [](const std::string& text) {
            auto s = std::make_unique<PySource>();
            s->text = text;
            std::optional<Error> error;
            {
                pb::gil_scoped_release release;  // opening a camera takes time
                auto src = openSource(text);
                if (!src) {
                    error = src.error();
                } else if (auto st = (*src)->start(); !st) {
                    error = st.error();
                } else {
                    s->source = std::move(*src);
                }
            }
            if (error) raise(*error);
            return s;
        },
        pb::arg("source"),
        "Opens a source string (v4l2:/dev/video0, libcamera:0, sim:..., a recording, a video, "
        "an image, a directory or glob of images) and starts it.");
}

}  // namespace infocus::py

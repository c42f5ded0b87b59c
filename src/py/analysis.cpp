// SPDX-License-Identifier: MIT
// infocus.analyze and infocus.analyze_source: NumPy arrays and frames in, Analysis objects out.
// The measuring is the library's (Analyzer, depthMap); this file maps types and releases the GIL.
#include <pybind11/stl.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "infocus/analysis.h"
#include "infocus/depth_map.h"
#include "infocus/luma.h"
#include "infocus/output.h"
#include "infocus/pipeline.h"
#include "infocus/source.h"
#include "infocus/synth.h"
#include "py_infocus.h"

namespace infocus::py {

namespace {

// A 2-D array checked for what a frame can be: its pixels, size, strides and element type.
struct ArrayFrame {
    enum class Type { U8, U16, F32 };
    const uint8_t* data = nullptr;
    int width = 0, height = 0;
    ptrdiff_t rowStride = 0, colStride = 0;  // bytes
    Type type = Type::U8;
};

std::string shapeText(const pb::array& a) {
    std::string s = "(";
    for (pb::ssize_t i = 0; i < a.ndim(); ++i)
        s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

ArrayFrame describe(const pb::handle& obj) {
    if (!pb::isinstance<pb::array>(obj))
        throw pb::type_error(
            "frame: expected a 2-D NumPy array (uint8, uint16 or float32) or an "
            "infocus.Frame, got " +
            std::string(pb::str(obj.get_type().attr("__name__"))));
    const auto a = pb::reinterpret_borrow<pb::array>(obj);
    ArrayFrame d;
    if (a.dtype().equal(pb::dtype::of<uint8_t>()))
        d.type = ArrayFrame::Type::U8;
    else if (a.dtype().equal(pb::dtype::of<uint16_t>()))
        d.type = ArrayFrame::Type::U16;
    else if (a.dtype().equal(pb::dtype::of<float>()))
        d.type = ArrayFrame::Type::F32;
    else
        throw pb::type_error("frame: dtype " + std::string(pb::str(a.dtype())) +
                             " is not a luma type; give uint8, uint16 (full 16-bit range) or "
                             "float32 (grey levels 0-255), e.g. frame.astype(np.float32)");
    if (a.ndim() != 2)
        throw pb::value_error("frame: shape " + shapeText(a) +
                              " is not a 2-D image; give one luma plane of shape (height, width), "
                              "e.g. cv2.cvtColor(img, cv2.COLOR_BGR2GRAY)");
    if (a.shape(0) == 0 || a.shape(1) == 0)
        throw pb::value_error("frame: shape " + shapeText(a) +
                              " is empty; give an image at least one pixel wide and high");
    if (!withinFrameLimit(a.shape(1), a.shape(0)) || a.shape(0) > kMaxFrameSide * int64_t{16} ||
        a.shape(1) > kMaxFrameSide * int64_t{16})
        throw pb::value_error("frame: shape " + shapeText(a) + " is past the limit of " +
                              maxFrameSizeText() + " pixels; crop or scale the image down");
    if (a.strides(0) < 0 || a.strides(1) < 0)
        throw pb::value_error(
            "frame: negative strides (a flipped view such as a[::-1]); pass "
            "np.ascontiguousarray(frame)");
    d.data = static_cast<const uint8_t*>(a.data());
    d.height = static_cast<int>(a.shape(0));
    d.width = static_cast<int>(a.shape(1));
    d.rowStride = a.strides(0);
    d.colStride = a.strides(1);
    return d;
}

template <typename T>
T pixel(const ArrayFrame& d, int x, int y) {
    T v;
    std::memcpy(&v, d.data + y * d.rowStride + x * d.colStride, sizeof(T));
    return v;
}

// The frame the library measures for @p d: the array's own memory where its layout is one the
// library reads (rows of packed uint8, or of packed little-endian uint16), else a copy. Float
// grey levels are rounded to 8 bits as the synthetic generator's are. Runs without the GIL.
Result<Frame> toFrame(const ArrayFrame& d) {
    const Size size{d.width, d.height};
    if (d.type == ArrayFrame::Type::F32) {
        Image<float> img(d.width, d.height);
        for (int y = 0; y < d.height; ++y)
            for (int x = 0; x < d.width; ++x) {
                const float v = pixel<float>(d, x, y);
                if (!std::isfinite(v))
                    return makeError(
                        ErrorKind::Usage,
                        "frame: pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is " +
                            (std::isnan(v) ? "NaN" : "infinite") +
                            "; replace missing pixels first, e.g. np.nan_to_num(frame)");
                img.at(x, y) = v;
            }
        return frameFromLuma(synth::toLuma8(img).view());
    }
    const bool u8 = d.type == ArrayFrame::Type::U8;
    const ptrdiff_t elem = u8 ? 1 : 2;
    const bool packedRows = d.colStride == elem && d.rowStride >= elem * d.width &&
                            d.rowStride % elem == 0 &&
                            (u8 || std::endian::native == std::endian::little);
    if (packedRows) {
        Frame f;
        f.format = u8 ? PixelFormat::GREY : PixelFormat::Y16;
        f.size = size;
        f.numPlanes = 1;
        f.planes[0] = Plane{d.data, static_cast<size_t>(d.rowStride),
                            static_cast<size_t>(d.rowStride) * (d.height - 1) +
                                static_cast<size_t>(elem) * d.width};
        return f;
    }
    auto f = allocateFrame(u8 ? PixelFormat::GREY : PixelFormat::Y16, size);
    if (!f) return f.error();
    uint8_t* out = mutablePlane(*f, 0);
    const size_t stride = f->planes[0].stride;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x) {
            if (u8) {
                out[y * stride + x] = pixel<uint8_t>(d, x, y);
            } else {
                const uint16_t v = pixel<uint16_t>(d, x, y);  // Y16 is little-endian
                out[y * stride + 2 * x] = static_cast<uint8_t>(v & 0xff);
                out[y * stride + 2 * x + 1] = static_cast<uint8_t>(v >> 8);
            }
        }
    return f;
}

// infocus.Analysis: one frame's measurements, with its depths where a lens was given.
struct PyAnalysis {
    FrameAnalysis a;
    int cols = 0, rows = 0;
    std::optional<DepthMap> depth;
    std::optional<double> focusDistance;  // the focus the depths were read with, metres
};

PyAnalysis wrap(FrameAnalysis a) {
    PyAnalysis p;
    for (const RegionResult& r : a.regions) {
        p.cols = std::max(p.cols, r.col + 1);
        p.rows = std::max(p.rows, r.row + 1);
    }
    p.a = std::move(a);
    return p;
}

// A (rows, cols) array of @p value over the regions.
template <typename T>
pb::array_t<T> gridOf(const PyAnalysis& p, const std::function<T(size_t)>& value) {
    pb::array_t<T> out({p.rows, p.cols});
    auto m = out.template mutable_unchecked<2>();
    for (size_t i = 0; i < p.a.regions.size(); ++i)
        m(p.a.regions[i].row, p.a.regions[i].col) = value(i);
    return out;
}

pb::array regionField(const PyAnalysis& p, std::optional<double> RegionResult::*field) {
    return gridOf<double>(p, [&](size_t i) {
        const RegionResult& r = p.a.regions[i];
        return r.status == RegionStatus::Ok ? orNan(r.*field) : orNan(std::nullopt);
    });
}

pb::object statusGrid(const PyAnalysis& p, bool reason) {
    pb::array out(pb::dtype("O"), std::vector<pb::ssize_t>{p.rows, p.cols});
    auto obj = out.mutable_data();
    for (const RegionResult& r : p.a.regions) {
        const pb::str s(reason ? r.statusReason : std::string(regionStatusName(r.status)));
        auto** cell = static_cast<PyObject**>(obj) + r.row * p.cols + r.col;
        Py_XDECREF(*cell);
        *cell = s.inc_ref().ptr();
    }
    return out;
}

struct Request {
    AnalysisOptions options;
    std::optional<Lens> lens;
};

Request request(std::pair<int, int> grid, const std::string& metric, bool blur,
                const std::optional<std::vector<std::array<int, 4>>>& roi,
                const std::optional<Lens>& lens, const std::string& transfer, unsigned threads) {
    Request q;
    q.options.threads = threads;
    q.options.cols = grid.first;
    q.options.rows = grid.second;
    q.options.metric = metric;
    q.options.measureBlur = blur;
    if (roi)
        for (const auto& r : *roi)
            q.options.rois.push_back(Rect{r[0], r[1], r[2], r[3]});
    if (transfer == "auto") {
        q.options.transferFromSource = true;
    } else if (const auto tf = transferFunctionFromName(transfer)) {
        q.options.transfer = *tf;
    } else {
        throw pb::value_error("transfer=" + transfer + ": use linear, srgb, rec709 or auto");
    }
    if (lens && !lens->pixelPitch)
        throw pb::value_error(
            "lens: give the pixel pitch of the analysed image, e.g. infocus.Lens(4.74e-3, 1.8, "
            "pixel_pitch=1.4e-6) (for a downscaled image, the sensor pitch times the scale)");
    q.lens = lens;
    // A grid or ROI the analyser refuses is the caller's mistake, told before any pixel is read.
    take(Analyzer::create(q.options));
    return q;
}

// The depths of @p p's regions through @p lens; the focus comes from the lens, else from the
// frame's lens position in dioptres.
Status addDepth(PyAnalysis& p, const Lens& lens) {
    std::optional<double> focus = lens.focusDistance;
    if (!focus) focus = focusFromLensPosition(p.a);
    if (!focus)
        return makeError(
            ErrorKind::Usage,
            "lens: give the focus distance, e.g. infocus.Lens(..., focus=0.5) (frame " +
                std::to_string(p.a.frame) + " carries no lens position in dioptres)");
    if (!(*focus > lens.thin.focalLength))
        return makeError(ErrorKind::Usage,
                         "lens: the focus distance " + std::to_string(*focus) +
                             " m is at or inside the focal length; focus farther");
    p.focusDistance = focus;
    p.depth = depthMap(p.a, optics::CameraGeometry{lens.thin, *focus, *lens.pixelPitch,
                                                   0.5 * p.a.width, 0.5 * p.a.height});
    return {};
}

PyAnalysis analyzeOne(const pb::object& frame, const Request& q) {
    std::optional<ArrayFrame> arr;
    const PyFrame* pf = nullptr;
    if (pb::isinstance<PyFrame>(frame))
        pf = &frame.cast<const PyFrame&>();
    else
        arr = describe(frame);
    std::optional<Result<FrameAnalysis>> a;
    {
        // The array is kept alive by the caller's reference for the whole call.
        pb::gil_scoped_release release;
        auto analyzer = Analyzer::create(q.options);
        if (!analyzer) {
            a = analyzer.error();
        } else if (pf) {
            a = (*analyzer)->analyze(pf->frame, pf->index);
        } else {
            auto f = toFrame(*arr);
            a = f ? (*analyzer)->analyze(*f, 0) : Result<FrameAnalysis>(f.error());
        }
    }
    PyAnalysis p = wrap(take(std::move(*a)));
    if (q.lens)
        if (auto st = addDepth(p, *q.lens); !st) raise(st.error());
    return p;
}

pb::object lensPositionOrNone(const std::optional<LensPosition>& lens) {
    return lens ? pb::cast(*lens) : pb::none();
}

}  // namespace

void registerAnalysis(pb::module_& m) {
    pb::class_<LensPosition>(m, "LensPosition",
                             "Where the lens was focused for a frame: the control's native value "
                             "and unit, and dioptres where known.")
        .def(pb::init([](double value, std::string unit, std::optional<double> dioptres) {
                 return LensPosition{value, std::move(unit), dioptres};
             }),
             pb::arg("value"), pb::arg("unit"), pb::arg("dioptres") = pb::none())
        .def_readonly("value", &LensPosition::value, "Value in the control's unit.")
        .def_readonly("unit", &LensPosition::unit, "'dioptre', 'v4l2' (driver steps), ...")
        .def_readonly("dioptres", &LensPosition::dioptres, "The position in dioptres, or None.")
        .def("__repr__", [](const LensPosition& l) {
            return "LensPosition(" + std::to_string(l.value) + ", '" + l.unit + "')";
        });

    pb::class_<PyAnalysis>(m, "Analysis",
                           "One frame's measurements: (rows, cols) arrays per region, NaN where "
                           "a region has no value, and the frame's own fields.")
        .def_property_readonly(
            "sharpness",
            [](const PyAnalysis& p) {
                return gridOf<double>(p, [&](size_t i) {
                    const RegionResult& r = p.a.regions[i];
                    return r.status == RegionStatus::Ok ? r.sharpness : orNan(std::nullopt);
                });
            },
            "Focus measure per region (NaN where dark or clipped).")
        .def_property_readonly(
            "edge_width_px",
            [](const PyAnalysis& p) { return regionField(p, &RegionResult::edgeWidthPx); },
            "10-90 % edge rise per region, pixels.")
        .def_property_readonly(
            "blur_sigma_px",
            [](const PyAnalysis& p) { return regionField(p, &RegionResult::blurSigmaPx); },
            "Gaussian-equivalent blur sigma per region, pixels.")
        .def_property_readonly(
            "blur_width_px",
            [](const PyAnalysis& p) { return regionField(p, &RegionResult::blurWidthPx); },
            "Disc-equivalent blur diameter per region, pixels.")
        .def_property_readonly(
            "confidence",
            [](const PyAnalysis& p) {
                return gridOf<double>(p, [&](size_t i) {
                    const RegionResult& r = p.a.regions[i];
                    return r.status == RegionStatus::Ok ? r.confidence : 0.0;
                });
            },
            "Trust in the blur fields, 0-1 (0 where they are NaN).")
        .def_property_readonly(
            "status", [](const PyAnalysis& p) { return statusGrid(p, false); },
            "'ok', 'dark' or 'clipped' per region.")
        .def_property_readonly(
            "status_reason", [](const PyAnalysis& p) { return statusGrid(p, true); },
            "Why a region is not 'ok' ('' where it is).")
        .def_property_readonly(
            "rects",
            [](const PyAnalysis& p) {
                pb::array_t<int> out({p.rows, p.cols, 4});
                auto m = out.mutable_unchecked<3>();
                for (const RegionResult& r : p.a.regions) {
                    m(r.row, r.col, 0) = r.rect.x;
                    m(r.row, r.col, 1) = r.rect.y;
                    m(r.row, r.col, 2) = r.rect.w;
                    m(r.row, r.col, 3) = r.rect.h;
                }
                return out;
            },
            "Each region as x, y, w, h in pixels: shape (rows, cols, 4).")
        .def_property_readonly(
            "frame_sharpness",
            [](const PyAnalysis& p) -> std::optional<double> {
                if (!p.a.regions.empty() && !hasMeasurableRegion(p.a)) return std::nullopt;
                return p.a.frameSharpness;
            },
            "Whole-frame score of the 'ok' regions; None when no region is 'ok'.")
        .def_property_readonly(
            "noise_sigma", [](const PyAnalysis& p) { return p.a.noiseSigma; },
            "White-noise sigma removed from the scores, grey levels; None without an estimate.")
        .def_property_readonly(
            "noise_reason", [](const PyAnalysis& p) { return p.a.noiseReason; },
            "Why noise_sigma is None ('' otherwise).")
        .def_property_readonly(
            "frame", [](const PyAnalysis& p) { return p.a.frame; },
            "Index of the frame in the analysed stream (0 for an array).")
        .def_property_readonly(
            "timestamp_ns", [](const PyAnalysis& p) { return p.a.timestampNs; },
            "Capture time, ns.")
        .def_property_readonly(
            "lens", [](const PyAnalysis& p) { return lensPositionOrNone(p.a.lens); },
            "The frame's LensPosition, or None.")
        .def_property_readonly(
            "width", [](const PyAnalysis& p) { return p.a.width; }, "Frame width, pixels.")
        .def_property_readonly(
            "height", [](const PyAnalysis& p) { return p.a.height; }, "Frame height, pixels.")
        .def_property_readonly(
            "metric", [](const PyAnalysis& p) { return p.a.metric; }, "The focus operator.")
        .def_property_readonly(
            "sharpening_halo", [](const PyAnalysis& p) { return p.a.sharpeningHalo; },
            "Median halo fraction of the regions' edges (in-camera sharpening), or None.")
        .def_property_readonly(
            "focus_distance_m", [](const PyAnalysis& p) { return p.focusDistance; },
            "Focus the depths were read with, metres; None without a lens.")
        .def_property_readonly(
            "depth_near_m",
            [](const PyAnalysis& p) -> pb::object {
                if (!p.depth) return pb::none();
                return gridOf<double>(p, [&](size_t i) {
                    const auto& roots = p.depth->regions[i].roots;
                    return roots ? roots->nearRoot : orNan(std::nullopt);
                });
            },
            "Per region, the depth of its blur in front of the focus, metres (NaN where "
            "unused); None without a lens.")
        .def_property_readonly(
            "depth_far_m",
            [](const PyAnalysis& p) -> pb::object {
                if (!p.depth) return pb::none();
                return gridOf<double>(p, [&](size_t i) {
                    const auto& roots = p.depth->regions[i].roots;
                    return roots ? orNan(roots->farRoot) : orNan(std::nullopt);
                });
            },
            "Per region, the depth of its blur behind the focus, metres (inf at infinity, NaN "
            "where there is none); None without a lens.")
        .def(
            "to_json", [](const PyAnalysis& p) { return toJsonLine(p.a); },
            "The frame as the JSONL line `infocus analyze` writes.")
        .def("__repr__", [](const PyAnalysis& p) {
            return "<infocus.Analysis frame " + std::to_string(p.a.frame) + ", " +
                   std::to_string(p.a.width) + "x" + std::to_string(p.a.height) + ", " +
                   std::to_string(p.cols) + "x" + std::to_string(p.rows) + " regions>";
        });

    m.def(
        "analyze",
        [](const pb::object& frame, std::pair<int, int> grid, const std::string& metric, bool blur,
           const std::optional<std::vector<std::array<int, 4>>>& roi,
           const std::optional<Lens>& lens, const std::string& transfer, unsigned threads) {
            return analyzeOne(frame, request(grid, metric, blur, roi, lens, transfer, threads));
        },
        pb::arg("frame"), pb::arg("grid") = std::pair<int, int>{16, 9}, pb::arg("metric") = "teng",
        pb::arg("blur") = true, pb::arg("roi") = pb::none(), pb::arg("lens") = pb::none(),
        pb::arg("transfer") = "linear", pb::arg("threads") = 0,
        "Measures one frame (a 2-D uint8, uint16 or float32 array, or an infocus.Frame): "
        "sharpness and blur per region of a (cols, rows) grid or of the ROIs [(x, y, w, h), ...]; "
        "with a Lens, the depths of the blur too. The blur is shared over `threads` threads (0: "
        "one per core). The GIL is released while it measures.");

    m.def(
        "analyze_source",
        [](const std::string& source, std::pair<int, int> grid, const std::string& metric,
           bool blur, const std::optional<std::vector<std::array<int, 4>>>& roi,
           const std::optional<Lens>& lens, const std::string& transfer, uint64_t frames,
           unsigned jobs, unsigned threads, const pb::object& progress) {
            const Request q = request(grid, metric, blur, roi, lens, transfer, threads);
            Progress report(progress);
            std::vector<FrameAnalysis> results;
            StreamOptions stream;
            stream.jobs = jobs > 0 ? jobs : defaultJobs();
            if (!report.empty())
                stream.progress = [&](uint64_t done, uint64_t total) { report(done, total); };
            Status st;
            {
                pb::gil_scoped_release release;
                st = analyzeSource(
                    source, q.options, frames,
                    [&](const FrameAnalysis& a) -> Status {
                        results.push_back(a);
                        return {};
                    },
                    {}, {}, stream);
            }
            report.rethrow();
            if (!st) raise(st.error());
            pb::list out;
            for (FrameAnalysis& a : results) {
                PyAnalysis p = wrap(std::move(a));
                if (q.lens)
                    if (auto s = addDepth(p, *q.lens); !s) raise(s.error());
                out.append(pb::cast(std::move(p)));
            }
            return out;
        },
        pb::arg("source"), pb::arg("grid") = std::pair<int, int>{16, 9}, pb::arg("metric") = "teng",
        pb::arg("blur") = true, pb::arg("roi") = pb::none(), pb::arg("lens") = pb::none(),
        pb::arg("transfer") = "linear", pb::arg("frames") = 0, pb::arg("jobs") = 0,
        pb::arg("threads") = 0, pb::arg("progress") = pb::none(),
        "Measures every frame of a source (up to `frames`, 0: all) as `infocus analyze --jobs` "
        "does (jobs 0: the machine's cores; each job's blur on `threads` threads, 0: its share "
        "of the cores), and returns a list of Analysis; progress(done, total) is called as "
        "frames are done (total 0 when unknown).");
}

}  // namespace infocus::py

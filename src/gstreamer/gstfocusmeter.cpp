// SPDX-License-Identifier: MIT
#include "gstfocusmeter.h"

#include <gst/video/gstvideometa.h>
#include <gst/video/video.h>

#include <atomic>
#include <charconv>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "focus_worker.h"
#include "infocus/metrics.h"

GST_DEBUG_CATEGORY_STATIC(gst_focus_meter_debug);
#define GST_CAT_DEFAULT gst_focus_meter_debug

namespace {

using infocus::FocusOperator;
using infocus::PixelFormat;
using infocus::Rect;
using infocus::TransferFunction;
using infocus::gst::FocusReading;
using infocus::gst::FocusWorker;
using infocus::gst::LumaSource;
using infocus::gst::MeterSettings;

constexpr const char* kDefaultGrid = "16x9";
constexpr int kDefaultBlurSearch = infocus::kLiveBlurSearchesPerFrame;
constexpr int kMaxBlurSearch = 65536;
constexpr double kMaxFocalLengthMm = 10000.0;
constexpr double kMaxFNumber = 1024.0;
constexpr double kMaxPixelPitchUm = 1000.0;
// As level's: people read ten messages a second; interval=0 asks for every frame.
constexpr guint64 kDefaultIntervalNs = GST_SECOND / 10;

// Every format whose luma the library reads; the caps string and the names in messages.
#define FOCUSMETER_FORMATS "{ GRAY8, GRAY16_LE, I420, NV12, YUY2, UYVY, RGB, BGR, RGBx, BGRx }"
constexpr const char* kFormatList =
    "GRAY8, GRAY16_LE, I420, NV12, YUY2, UYVY, RGB, BGR, RGBx, BGRx";

GstStaticPadTemplate sinkTemplate = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(GST_VIDEO_CAPS_MAKE(FOCUSMETER_FORMATS)));
GstStaticPadTemplate srcTemplate = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(GST_VIDEO_CAPS_MAKE(FOCUSMETER_FORMATS)));

enum {
    PROP_0,
    PROP_GRID,
    PROP_ROI,
    PROP_METRIC,
    PROP_BLUR,
    PROP_BLUR_SEARCH,
    PROP_TRANSFER,
    PROP_FOCAL_LENGTH,
    PROP_F_NUMBER,
    PROP_PIXEL_PITCH,
    PROP_FOCUS_DISTANCE,
    PROP_INTERVAL,
    PROP_POST_MESSAGES,
    PROP_ATTACH_META,
    PROP_SKIP_FRAMES,
};

// The operators as a GEnum, so that gst-inspect-1.0 lists them (values = FocusOperator).
GType metricEnumType() {
    static GType type = 0;
    if (g_once_init_enter(&type)) {
        static const GEnumValue values[] = {
            {int(FocusOperator::Lapv), "Variance of the Laplacian", "lapv"},
            {int(FocusOperator::Lapm), "Sum-modified Laplacian", "lapm"},
            {int(FocusOperator::Teng), "Tenengrad (Sobel gradient energy)", "teng"},
            {int(FocusOperator::Tenv), "Tenengrad variance", "tenv"},
            {int(FocusOperator::Brenner), "Brenner", "brenner"},
            {int(FocusOperator::Glvn), "Normalised grey-level variance", "glvn"},
            {int(FocusOperator::Dctr), "DCT high-frequency ratio", "dctr"},
            {0, nullptr, nullptr},
        };
        g_once_init_leave(&type, g_enum_register_static("GstFocusMeterMetric", values));
    }
    return type;
}

GType transferEnumType() {
    static GType type = 0;
    if (g_once_init_enter(&type)) {
        static const GEnumValue values[] = {
            {int(TransferFunction::Linear), "Grey level proportional to light", "linear"},
            {int(TransferFunction::Srgb), "sRGB (most webcams, JPEG)", "srgb"},
            {int(TransferFunction::Rec709), "ITU-R BT.709 (HD video)", "rec709"},
            {0, nullptr, nullptr},
        };
        g_once_init_leave(&type, g_enum_register_static("GstFocusMeterTransfer", values));
    }
    return type;
}

// The whole integers of @p text split at @p sep, or nullopt.
std::optional<std::vector<int>> integers(std::string_view text, char sep) {
    std::vector<int> out;
    while (true) {
        const size_t end = text.find(sep);
        const std::string_view part = text.substr(0, end);
        int v = 0;
        const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
        if (part.empty() || ec != std::errc() || ptr != part.data() + part.size())
            return std::nullopt;
        out.push_back(v);
        if (end == std::string_view::npos) return out;
        text.remove_prefix(end + 1);
    }
}

std::optional<std::pair<int, int>> parseGrid(std::string_view text) {
    const auto v = integers(text, 'x');
    if (!v || v->size() != 2) return std::nullopt;
    const int c = (*v)[0], r = (*v)[1];
    if (c < 1 || r < 1 || c > infocus::kMaxGridSide || r > infocus::kMaxGridSide)
        return std::nullopt;
    return std::pair{c, r};
}

// "x,y,w,h" regions separated by ';'; empty text: no region (the grid).
std::optional<std::vector<Rect>> parseRois(std::string_view text) {
    std::vector<Rect> out;
    if (text.empty()) return out;
    while (true) {
        const size_t end = text.find(';');
        const auto v = integers(text.substr(0, end), ',');
        if (!v || v->size() != 4 || (*v)[0] < 0 || (*v)[1] < 0 || (*v)[2] < 1 || (*v)[3] < 1)
            return std::nullopt;
        out.push_back(Rect{(*v)[0], (*v)[1], (*v)[2], (*v)[3]});
        if (end == std::string_view::npos) return out;
        text.remove_prefix(end + 1);
    }
}

// Why @p cols × @p rows or @p rois cannot measure a @p width × @p height frame; empty: they can.
std::string regionsMisfit(int cols, int rows, const std::vector<Rect>& rois, int width,
                          int height) {
    const std::string frame = std::to_string(width) + "x" + std::to_string(height);
    if (rois.empty()) {
        if (infocus::gridRegions(width, height, cols, rows).empty())
            return "grid " + std::to_string(cols) + "x" + std::to_string(rows) +
                   " has more cells than the " + frame +
                   " frame has pixels; set a grid of at most " + frame;
        return {};
    }
    for (const Rect& r : rois)
        if (infocus::intersect(r, {0, 0, width, height}) != r)
            return "roi " + std::to_string(r.x) + "," + std::to_string(r.y) + "," +
                   std::to_string(r.w) + "," + std::to_string(r.h) + " reaches outside the " +
                   frame + " frame; keep x + w within " + std::to_string(width) +
                   " and y + h within " + std::to_string(height);
    return {};
}

// Which library format holds the bytes the analysis needs of @p format, and how many bytes a
// line of them takes: planar YUV hands over its Y plane alone, as a GREY frame.
std::optional<std::pair<PixelFormat, size_t>> lumaLayout(GstVideoFormat format, int width) {
    const auto w = static_cast<size_t>(width);
    switch (format) {
        case GST_VIDEO_FORMAT_GRAY8:
        case GST_VIDEO_FORMAT_I420:
        case GST_VIDEO_FORMAT_NV12:
            return std::pair{PixelFormat::GREY, w};
        case GST_VIDEO_FORMAT_GRAY16_LE:
            return std::pair{PixelFormat::Y16, 2 * w};
        case GST_VIDEO_FORMAT_YUY2:
            return std::pair{PixelFormat::YUYV, 2 * w};
        case GST_VIDEO_FORMAT_UYVY:
            return std::pair{PixelFormat::UYVY, 2 * w};
        case GST_VIDEO_FORMAT_RGB:
            return std::pair{PixelFormat::RGB24, 3 * w};
        case GST_VIDEO_FORMAT_BGR:
            return std::pair{PixelFormat::BGR24, 3 * w};
        case GST_VIDEO_FORMAT_RGBx:
            return std::pair{PixelFormat::RGBX, 4 * w};
        case GST_VIDEO_FORMAT_BGRx:
            return std::pair{PixelFormat::BGRX, 4 * w};
        default:
            return std::nullopt;
    }
}

// The element's C++ state, beside its GObject instance.
struct State {
    // Properties, under the object lock.
    std::string grid = kDefaultGrid;
    int cols = 16, rows = 9;
    std::string roi;
    std::vector<Rect> rois;
    FocusOperator metric = infocus::kDefaultOperator;
    bool blur = true;
    int blurSearch = kDefaultBlurSearch;
    TransferFunction transfer = TransferFunction::Linear;
    double focalLengthMm = 0.0, fNumber = 0.0, pixelPitchUm = 0.0, focusDistanceM = 0.0;
    guint64 interval = kDefaultIntervalNs;
    // Read by the analysis thread, which takes no lock the streaming thread waits for.
    std::atomic<bool> postMessages = true;
    std::atomic<bool> attachMeta = false;
    bool skipFrames = true;
    std::shared_ptr<const MeterSettings> settings;  // rebuilt when a property changes

    // Streaming thread.
    GstVideoInfo info{};
    bool haveInfo = false;
    std::optional<std::pair<PixelFormat, size_t>> layout;
    uint64_t frames = 0;                             // buffers seen since start
    GstClockTime lastOffered = GST_CLOCK_TIME_NONE;  // for interval
    bool warnedBuffer = false;
    bool warnedCaps = false;  // accept-caps queries repeat: one warning per start

    std::unique_ptr<FocusWorker> worker;
    std::mutex readingMutex;  // the newest reading, for attach-meta
    std::shared_ptr<const FocusReading> newest;
    bool warnedAnalysis = false;  // analysis thread
};

}  // namespace

struct _GstFocusMeter {
    GstBaseTransform parent;
    State* s;
};

G_DEFINE_TYPE(GstFocusMeter, gst_focus_meter, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(focusmeter, "focusmeter", GST_RANK_NONE, GST_TYPE_FOCUS_METER)

namespace {

// Builds the analysis settings from the properties. Called with the object lock held.
void rebuildSettings(State& s) {
    auto m = std::make_shared<MeterSettings>();
    m->analysis.cols = s.cols;
    m->analysis.rows = s.rows;
    m->analysis.rois = s.rois;
    m->analysis.metric = std::string(infocus::operatorName(s.metric));
    m->analysis.measureBlur = s.blur;
    m->analysis.blurSearchesPerFrame = s.blurSearch;
    m->analysis.blurSearchBudgetS = s.blurSearch > 0 ? infocus::kLiveBlurSearchBudgetS : 0.0;
    m->analysis.transfer = s.transfer;
    if (s.focalLengthMm > 0 && s.fNumber > 0)
        m->lens = infocus::optics::ThinLens{s.focalLengthMm * 1e-3, s.fNumber};
    if (s.pixelPitchUm > 0) m->pixelPitchM = s.pixelPitchUm * 1e-6;
    if (s.focusDistanceM > 0) m->focusDistanceM = s.focusDistanceM;
    s.settings = std::move(m);
}

void addDoubles(GstStructure* st, const char* name, const std::vector<double>& values) {
    G_GNUC_BEGIN_IGNORE_DEPRECATIONS
    // GValueArray, as `level` posts its arrays: bindings read it as a list.
    GValueArray* array = g_value_array_new(static_cast<guint>(values.size()));
    GValue v = G_VALUE_INIT;
    g_value_init(&v, G_TYPE_DOUBLE);
    for (const double x : values) {
        g_value_set_double(&v, x);
        g_value_array_append(array, &v);
    }
    g_value_unset(&v);
    GValue a = G_VALUE_INIT;
    g_value_init(&a, g_value_array_get_type());
    g_value_take_boxed(&a, array);
    gst_structure_take_value(st, name, &a);
    G_GNUC_END_IGNORE_DEPRECATIONS
}

void addStrings(GstStructure* st, const char* name, const std::vector<std::string>& values) {
    G_GNUC_BEGIN_IGNORE_DEPRECATIONS
    GValueArray* array = g_value_array_new(static_cast<guint>(values.size()));
    GValue v = G_VALUE_INIT;
    g_value_init(&v, G_TYPE_STRING);
    for (const auto& x : values) {
        g_value_set_string(&v, x.c_str());
        g_value_array_append(array, &v);
    }
    g_value_unset(&v);
    GValue a = G_VALUE_INIT;
    g_value_init(&a, g_value_array_get_type());
    g_value_take_boxed(&a, array);
    gst_structure_take_value(st, name, &a);
    G_GNUC_END_IGNORE_DEPRECATIONS
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The `infocus` message of one reading (docs/gstreamer.md, Messages).
GstStructure* readingStructure(const FocusReading& r) {
    const auto t = [](int64_t ns) {
        return ns >= 0 ? static_cast<GstClockTime>(ns) : GST_CLOCK_TIME_NONE;
    };
    GstStructure* st = gst_structure_new(
        "infocus", "timestamp", G_TYPE_UINT64, t(r.times.timestampNs), "stream-time", G_TYPE_UINT64,
        t(r.times.streamTimeNs), "running-time", G_TYPE_UINT64, t(r.times.runningTimeNs),
        "duration", G_TYPE_UINT64, t(r.times.durationNs), "frame", G_TYPE_UINT64,
        static_cast<guint64>(r.frame), "skipped", G_TYPE_UINT64, static_cast<guint64>(r.skipped),
        "width", G_TYPE_INT, r.analysis.width, "height", G_TYPE_INT, r.analysis.height, "metric",
        G_TYPE_STRING, r.analysis.metric.c_str(), "score", G_TYPE_DOUBLE, r.score,
        "percent-of-peak", G_TYPE_DOUBLE, r.percentOfPeak, "cols", G_TYPE_INT, r.cols, "rows",
        G_TYPE_INT, r.rows, nullptr);
    std::vector<double> sharpness, blur, confidence;
    std::vector<std::string> status;
    for (const auto& reg : r.analysis.regions) {
        const bool ok = reg.status == infocus::RegionStatus::Ok;
        // As `infocus analyze` writes them: a region that is not Ok has no score or blur.
        sharpness.push_back(ok ? reg.sharpness : kNaN);
        blur.push_back(ok && reg.blurWidthPx ? *reg.blurWidthPx : kNaN);
        confidence.push_back(ok ? reg.confidence : 0.0);
        status.emplace_back(infocus::regionStatusName(reg.status));
    }
    addDoubles(st, "sharpness", sharpness);
    addDoubles(st, "blur-width-px", blur);
    addDoubles(st, "confidence", confidence);
    addStrings(st, "status", status);
    if (r.inFocusDistanceM)
        gst_structure_set(st, "in-focus-distance", G_TYPE_DOUBLE, *r.inFocusDistanceM, nullptr);
    if (!r.depthNearM.empty()) {
        addDoubles(st, "depth-near", r.depthNearM);
        addDoubles(st, "depth-far", r.depthFarM);
    }
    return st;
}

// Called on the analysis thread.
void publish(GstFocusMeter* self, const FocusReading& r) {
    State& s = *self->s;
    const bool post = s.postMessages;
    const bool meta = s.attachMeta;
    if (meta) {
        auto copy = std::make_shared<FocusReading>(r);
        std::lock_guard lock(s.readingMutex);
        s.newest = std::move(copy);
    }
    if (post)
        gst_element_post_message(GST_ELEMENT(self),
                                 gst_message_new_element(GST_OBJECT(self), readingStructure(r)));
}

// Called on the analysis thread: one warning per stream, the rest in the debug log.
void analysisFailed(GstFocusMeter* self, const infocus::Error& e) {
    State& s = *self->s;
    if (s.warnedAnalysis) {
        GST_DEBUG_OBJECT(self, "frame not analysed: %s", e.message.c_str());
        return;
    }
    s.warnedAnalysis = true;
    GST_ELEMENT_WARNING(self, STREAM, FAILED, ("focusmeter could not analyse a frame"),
                        ("%s; the stream goes on, later failures are in the debug log "
                         "(GST_DEBUG=focusmeter:5)",
                         e.message.c_str()));
}

// One GstVideoRegionOfInterestMeta per region of the newest reading.
void attachMeta(GstFocusMeter* self, GstBuffer* buf) {
    State& s = *self->s;
    std::shared_ptr<const FocusReading> r;
    {
        std::lock_guard lock(s.readingMutex);
        r = s.newest;
    }
    if (!r) return;
    for (size_t i = 0; i < r->analysis.regions.size(); ++i) {
        const auto& reg = r->analysis.regions[i];
        GstVideoRegionOfInterestMeta* m = gst_buffer_add_video_region_of_interest_meta(
            buf, "infocus", static_cast<guint>(reg.rect.x), static_cast<guint>(reg.rect.y),
            static_cast<guint>(reg.rect.w), static_cast<guint>(reg.rect.h));
        m->id = static_cast<gint>(i);
        const bool ok = reg.status == infocus::RegionStatus::Ok;
        GstStructure* p = gst_structure_new(
            "infocus", "frame", G_TYPE_UINT64, static_cast<guint64>(r->frame), "col", G_TYPE_INT,
            reg.col, "row", G_TYPE_INT, reg.row, "sharpness", G_TYPE_DOUBLE,
            ok ? reg.sharpness : kNaN, "blur-width-px", G_TYPE_DOUBLE,
            ok && reg.blurWidthPx ? *reg.blurWidthPx : kNaN, "confidence", G_TYPE_DOUBLE,
            ok ? reg.confidence : 0.0, "status", G_TYPE_STRING,
            std::string(infocus::regionStatusName(reg.status)).c_str(), nullptr);
        gst_video_region_of_interest_meta_add_param(m, p);
    }
}

void setProperty(GObject* object, guint id, const GValue* value, GParamSpec* pspec) {
    GstFocusMeter* self = GST_FOCUS_METER(object);
    State& s = *self->s;
    bool passthroughChanged = false;
    bool attach = false;
    GST_OBJECT_LOCK(self);
    switch (id) {
        case PROP_GRID: {
            const char* text = g_value_get_string(value);
            const auto g = parseGrid(text ? text : "");
            std::string misfit;
            if (g && s.haveInfo && s.rois.empty())
                misfit = regionsMisfit(g->first, g->second, {}, GST_VIDEO_INFO_WIDTH(&s.info),
                                       GST_VIDEO_INFO_HEIGHT(&s.info));
            if (!g || !misfit.empty()) {
                g_warning("focusmeter: grid '%s' refused (%s); keeping %s", text ? text : "",
                          g ? misfit.c_str() : infocus::gridLimitText().c_str(), s.grid.c_str());
                break;
            }
            s.grid = text;
            s.cols = g->first;
            s.rows = g->second;
            break;
        }
        case PROP_ROI: {
            const char* text = g_value_get_string(value);
            const auto r = parseRois(text ? text : "");
            std::string misfit;
            if (r && s.haveInfo && !r->empty())
                misfit = regionsMisfit(s.cols, s.rows, *r, GST_VIDEO_INFO_WIDTH(&s.info),
                                       GST_VIDEO_INFO_HEIGHT(&s.info));
            if (!r || !misfit.empty()) {
                g_warning("focusmeter: roi '%s' refused (%s); keeping '%s'", text ? text : "",
                          r ? misfit.c_str()
                            : "give x,y,w,h in pixels with w and h above 0, regions separated "
                              "by ';', e.g. 100,80,320,240",
                          s.roi.c_str());
                break;
            }
            s.roi = text ? text : "";
            s.rois = *r;
            break;
        }
        case PROP_METRIC:
            s.metric = static_cast<FocusOperator>(g_value_get_enum(value));
            break;
        case PROP_BLUR:
            s.blur = g_value_get_boolean(value);
            break;
        case PROP_BLUR_SEARCH:
            s.blurSearch = g_value_get_int(value);
            break;
        case PROP_TRANSFER:
            s.transfer = static_cast<TransferFunction>(g_value_get_enum(value));
            break;
        case PROP_FOCAL_LENGTH:
        case PROP_F_NUMBER:
        case PROP_PIXEL_PITCH:
        case PROP_FOCUS_DISTANCE: {
            double& field = id == PROP_FOCAL_LENGTH  ? s.focalLengthMm
                            : id == PROP_F_NUMBER    ? s.fNumber
                            : id == PROP_PIXEL_PITCH ? s.pixelPitchUm
                                                     : s.focusDistanceM;
            const double v = g_value_get_double(value);
            // GLib's range check lets NaN through (every comparison with it is false).
            if (std::isnan(v)) {
                g_warning("focusmeter: %s nan refused; give a number in its range, keeping %g",
                          g_param_spec_get_name(pspec), field);
                break;
            }
            field = v;
            break;
        }
        case PROP_INTERVAL:
            s.interval = g_value_get_uint64(value);
            break;
        case PROP_POST_MESSAGES:
            s.postMessages = g_value_get_boolean(value);
            break;
        case PROP_ATTACH_META:
            s.attachMeta = g_value_get_boolean(value);
            attach = s.attachMeta;
            passthroughChanged = true;
            break;
        case PROP_SKIP_FRAMES:
            s.skipFrames = g_value_get_boolean(value);
            break;
        default:
            G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
            break;
    }
    rebuildSettings(s);
    GST_OBJECT_UNLOCK(self);
    // Adding metas needs a writable buffer (its memory stays shared): no passthrough then.
    if (passthroughChanged) gst_base_transform_set_passthrough(GST_BASE_TRANSFORM(self), !attach);
}

void getProperty(GObject* object, guint id, GValue* value, GParamSpec* pspec) {
    GstFocusMeter* self = GST_FOCUS_METER(object);
    const State& s = *self->s;
    GST_OBJECT_LOCK(self);
    switch (id) {
        case PROP_GRID:
            g_value_set_string(value, s.grid.c_str());
            break;
        case PROP_ROI:
            g_value_set_string(value, s.roi.c_str());
            break;
        case PROP_METRIC:
            g_value_set_enum(value, static_cast<int>(s.metric));
            break;
        case PROP_BLUR:
            g_value_set_boolean(value, s.blur);
            break;
        case PROP_BLUR_SEARCH:
            g_value_set_int(value, s.blurSearch);
            break;
        case PROP_TRANSFER:
            g_value_set_enum(value, static_cast<int>(s.transfer));
            break;
        case PROP_FOCAL_LENGTH:
            g_value_set_double(value, s.focalLengthMm);
            break;
        case PROP_F_NUMBER:
            g_value_set_double(value, s.fNumber);
            break;
        case PROP_PIXEL_PITCH:
            g_value_set_double(value, s.pixelPitchUm);
            break;
        case PROP_FOCUS_DISTANCE:
            g_value_set_double(value, s.focusDistanceM);
            break;
        case PROP_INTERVAL:
            g_value_set_uint64(value, s.interval);
            break;
        case PROP_POST_MESSAGES:
            g_value_set_boolean(value, s.postMessages);
            break;
        case PROP_ATTACH_META:
            g_value_set_boolean(value, s.attachMeta);
            break;
        case PROP_SKIP_FRAMES:
            g_value_set_boolean(value, s.skipFrames);
            break;
        default:
            G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
            break;
    }
    GST_OBJECT_UNLOCK(self);
}

void finalize(GObject* object) {
    GstFocusMeter* self = GST_FOCUS_METER(object);
    delete self->s;
    self->s = nullptr;
    G_OBJECT_CLASS(gst_focus_meter_parent_class)->finalize(object);
}

gboolean start(GstBaseTransform* trans) {
    GstFocusMeter* self = GST_FOCUS_METER(trans);
    State& s = *self->s;
    s.frames = 0;
    s.lastOffered = GST_CLOCK_TIME_NONE;
    s.warnedBuffer = false;
    s.warnedCaps = false;
    s.warnedAnalysis = false;
    {
        std::lock_guard lock(s.readingMutex);
        s.newest.reset();
    }
    s.worker =
        std::make_unique<FocusWorker>([self](const FocusReading& r) { publish(self, r); },
                                      [self](const infocus::Error& e) { analysisFailed(self, e); });
    return TRUE;
}

gboolean stop(GstBaseTransform* trans) {
    State& s = *GST_FOCUS_METER(trans)->s;
    s.worker.reset();  // joins the thread after the frame it is analysing
    s.haveInfo = false;
    return TRUE;
}

// Names what the caps carry, for a message about caps the element cannot read.
std::string capsFormatName(GstCaps* caps) {
    if (!caps || gst_caps_get_size(caps) == 0) return "empty caps";
    const GstStructure* st = gst_caps_get_structure(caps, 0);
    const char* media = gst_structure_get_name(st);
    const char* format = gst_structure_get_string(st, "format");
    if (g_strcmp0(media, "video/x-raw") == 0 && format) return std::string("video/x-raw ") + format;
    return media ? media : "unknown caps";
}

gboolean setCaps(GstBaseTransform* trans, GstCaps* incaps, GstCaps*) {
    GstFocusMeter* self = GST_FOCUS_METER(trans);
    State& s = *self->s;
    GstVideoInfo info;
    if (!gst_video_info_from_caps(&info, incaps)) {
        gchar* text = gst_caps_to_string(incaps);
        GST_ELEMENT_ERROR(self, CORE, NEGOTIATION, ("focusmeter cannot read the caps %s", text),
                          ("give it video/x-raw with a size and one of: %s", kFormatList));
        g_free(text);
        return FALSE;
    }
    const auto layout = lumaLayout(GST_VIDEO_INFO_FORMAT(&info), GST_VIDEO_INFO_WIDTH(&info));
    if (!layout) {
        GST_ELEMENT_ERROR(self, CORE, NEGOTIATION,
                          ("focusmeter cannot read %s video",
                           gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(&info))),
                          ("it reads %s; put videoconvert before it", kFormatList));
        return FALSE;
    }
    GST_OBJECT_LOCK(self);
    const std::string misfit = regionsMisfit(s.cols, s.rows, s.rois, GST_VIDEO_INFO_WIDTH(&info),
                                             GST_VIDEO_INFO_HEIGHT(&info));
    GST_OBJECT_UNLOCK(self);
    if (!misfit.empty()) {
        GST_ELEMENT_ERROR(self, CORE, NEGOTIATION, ("focusmeter cannot measure this video"),
                          ("%s", misfit.c_str()));
        return FALSE;
    }
    GST_OBJECT_LOCK(self);
    s.info = info;
    s.haveInfo = true;
    s.layout = layout;
    GST_OBJECT_UNLOCK(self);
    return TRUE;
}

// What to put before the element for caps it cannot read.
const char* capsAdvice(GstCaps* caps) {
    const GstStructure* st =
        caps && gst_caps_get_size(caps) ? gst_caps_get_structure(caps, 0) : nullptr;
    return st && gst_structure_has_name(st, "video/x-raw")
               ? "put videoconvert before it"
               : "decode it to video/x-raw first (jpegdec for image/jpeg, a decoder for others)";
}

// Whether @p caps are fixed caps outside what the element reads.
bool unreadable(GstCaps* caps) {
    if (!caps || !gst_caps_is_fixed(caps)) return false;
    GstCaps* templ = gst_static_pad_template_get_caps(&sinkTemplate);
    const bool readable = gst_caps_can_intersect(caps, templ);
    gst_caps_unref(templ);
    return !readable;
}

// Caps outside the template are refused by the pad's accept-caps check before any event
// reaches the element, and the source then fails with a bare not-negotiated: say here what the
// element cannot read. A warning, not an error: upstream may only be asking.
gboolean query(GstBaseTransform* trans, GstPadDirection direction, GstQuery* q) {
    GstFocusMeter* self = GST_FOCUS_METER(trans);
    GstCaps* caps = nullptr;
    if (direction == GST_PAD_SINK && GST_QUERY_TYPE(q) == GST_QUERY_ACCEPT_CAPS)
        gst_query_parse_accept_caps(q, &caps);
    if (unreadable(caps) && !self->s->warnedCaps) {
        self->s->warnedCaps = true;
        const std::string name = capsFormatName(caps);
        GST_ELEMENT_WARNING(self, CORE, NEGOTIATION, ("focusmeter cannot read %s", name.c_str()),
                            ("it reads video/x-raw in %s; %s", kFormatList, capsAdvice(caps)));
    }
    return GST_BASE_TRANSFORM_CLASS(gst_focus_meter_parent_class)->query(trans, direction, q);
}

gboolean sinkEvent(GstBaseTransform* trans, GstEvent* event) {
    GstFocusMeter* self = GST_FOCUS_METER(trans);
    State& s = *self->s;
    switch (GST_EVENT_TYPE(event)) {
        case GST_EVENT_EOS:
            // Every frame offered is measured and posted before the EOS reaches the sink.
            if (s.worker) s.worker->drain();
            break;
        case GST_EVENT_FLUSH_STOP:
        case GST_EVENT_STREAM_START:
            if (s.worker) s.worker->reset();
            s.lastOffered = GST_CLOCK_TIME_NONE;
            break;
        default:
            break;
    }
    return GST_BASE_TRANSFORM_CLASS(gst_focus_meter_parent_class)->sink_event(trans, event);
}

int64_t ns(GstClockTime t) {
    return GST_CLOCK_TIME_IS_VALID(t) ? static_cast<int64_t>(t) : -1;
}

GstFlowReturn transformIp(GstBaseTransform* trans, GstBuffer* buf) {
    GstFocusMeter* self = GST_FOCUS_METER(trans);
    State& s = *self->s;
    const uint64_t frame = s.frames++;

    GST_OBJECT_LOCK(self);
    const bool wanted = s.postMessages || s.attachMeta;
    const guint64 interval = s.interval;
    const bool skipFrames = s.skipFrames;
    const bool meta = s.attachMeta;
    auto settings = s.settings;
    GST_OBJECT_UNLOCK(self);
    if (!wanted || !s.haveInfo || !s.layout || !s.worker) return GST_FLOW_OK;

    const GstClockTime pts = GST_BUFFER_PTS(buf);
    bool offer = true;
    if (interval > 0 && GST_CLOCK_TIME_IS_VALID(pts) && GST_CLOCK_TIME_IS_VALID(s.lastOffered) &&
        pts >= s.lastOffered && pts - s.lastOffered < interval)
        offer = false;

    if (offer) {
        GstVideoFrame vf;
        if (!gst_video_frame_map(&vf, &s.info, buf, GST_MAP_READ)) {
            if (!s.warnedBuffer)
                GST_ELEMENT_WARNING(self, STREAM, FORMAT,
                                    ("focusmeter skipped a buffer it cannot read"),
                                    ("buffer of %" G_GSIZE_FORMAT
                                     " bytes does not hold a %dx%d %s frame (%" G_GSIZE_FORMAT
                                     " bytes); it passes on unmeasured",
                                     gst_buffer_get_size(buf), GST_VIDEO_INFO_WIDTH(&s.info),
                                     GST_VIDEO_INFO_HEIGHT(&s.info),
                                     gst_video_format_to_string(GST_VIDEO_INFO_FORMAT(&s.info)),
                                     GST_VIDEO_INFO_SIZE(&s.info)));
            s.warnedBuffer = true;
            return GST_FLOW_OK;
        }
        LumaSource src;
        src.format = s.layout->first;
        src.size = {GST_VIDEO_INFO_WIDTH(&s.info), GST_VIDEO_INFO_HEIGHT(&s.info)};
        src.data = static_cast<const uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&vf, 0));
        const gint stride = GST_VIDEO_FRAME_PLANE_STRIDE(&vf, 0);
        src.lineBytes = s.layout->second;
        // A video meta may describe any stride: the first plane's lines must fit its memory.
        const auto* mapEnd = vf.map[0].data + vf.map[0].size;
        const size_t h = static_cast<size_t>(src.size.height);
        const bool fits = stride > 0 && static_cast<size_t>(stride) >= src.lineBytes &&
                          src.data >= vf.map[0].data &&
                          static_cast<size_t>(mapEnd - src.data) >=
                              static_cast<size_t>(stride) * (h - 1) + src.lineBytes;
        if (!fits) {
            if (!s.warnedBuffer)
                GST_ELEMENT_WARNING(self, STREAM, FORMAT,
                                    ("focusmeter skipped a buffer it cannot read"),
                                    ("its first plane has stride %d for lines of %" G_GSIZE_FORMAT
                                     " bytes, or ends before its last line; it passes on "
                                     "unmeasured",
                                     stride, src.lineBytes));
            s.warnedBuffer = true;
            gst_video_frame_unmap(&vf);
            return GST_FLOW_OK;
        }
        src.stride = static_cast<size_t>(stride);
        infocus::gst::FrameTimes times;
        times.timestampNs = ns(pts);
        times.durationNs = ns(GST_BUFFER_DURATION(buf));
        if (GST_CLOCK_TIME_IS_VALID(pts) && trans->segment.format == GST_FORMAT_TIME) {
            times.runningTimeNs =
                ns(gst_segment_to_running_time(&trans->segment, GST_FORMAT_TIME, pts));
            times.streamTimeNs =
                ns(gst_segment_to_stream_time(&trans->segment, GST_FORMAT_TIME, pts));
        }
        s.worker->offer(src, frame, times, std::move(settings), !skipFrames);
        gst_video_frame_unmap(&vf);
        s.lastOffered = pts;
        // Waiting for every frame anyway: the metas then describe this very frame.
        if (meta && !skipFrames) s.worker->drain();
    }
    if (meta && gst_buffer_is_writable(buf)) attachMeta(self, buf);
    return GST_FLOW_OK;
}

}  // namespace

static void gst_focus_meter_class_init(GstFocusMeterClass* klass) {
    GObjectClass* gobject = G_OBJECT_CLASS(klass);
    GstElementClass* element = GST_ELEMENT_CLASS(klass);
    GstBaseTransformClass* trans = GST_BASE_TRANSFORM_CLASS(klass);

    gobject->set_property = setProperty;
    gobject->get_property = getProperty;
    gobject->finalize = finalize;

    const auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                                GST_PARAM_MUTABLE_PLAYING);
    g_object_class_install_property(
        gobject, PROP_GRID,
        g_param_spec_string("grid", "Grid",
                            "Regions as columns x rows, 1x1 to 256x256 (at most the frame's "
                            "pixels); ignored while roi is set",
                            kDefaultGrid, flags));
    g_object_class_install_property(
        gobject, PROP_ROI,
        g_param_spec_string("roi", "Regions of interest",
                            "Regions x,y,w,h in pixels separated by ';' instead of the grid "
                            "(within the frame); empty: the grid",
                            "", flags));
    g_object_class_install_property(
        gobject, PROP_METRIC,
        g_param_spec_enum("metric", "Metric", "Focus operator of the sharpness scores",
                          metricEnumType(), static_cast<int>(infocus::kDefaultOperator), flags));
    g_object_class_install_property(
        gobject, PROP_BLUR,
        g_param_spec_boolean("blur", "Blur", "Also measure each region's blur width", TRUE, flags));
    g_object_class_install_property(
        gobject, PROP_BLUR_SEARCH,
        g_param_spec_int("blur-search", "Blur search",
                         "Regions whose edges are searched afresh each frame (the others "
                         "measured again where found, within 1.5 ms); 0: every region every "
                         "frame, as infocus analyze on files",
                         0, kMaxBlurSearch, kDefaultBlurSearch, flags));
    g_object_class_install_property(
        gobject, PROP_TRANSFER,
        g_param_spec_enum("transfer", "Transfer function",
                          "How grey levels encode light, for the blur width", transferEnumType(),
                          static_cast<int>(TransferFunction::Linear), flags));
    g_object_class_install_property(
        gobject, PROP_FOCAL_LENGTH,
        g_param_spec_double("focal-length", "Focal length",
                            "Focal length of the lens in mm (0: unknown)", 0.0, kMaxFocalLengthMm,
                            0.0, flags));
    g_object_class_install_property(
        gobject, PROP_F_NUMBER,
        g_param_spec_double("f-number", "f-number", "f-number of the lens (0: unknown)", 0.0,
                            kMaxFNumber, 0.0, flags));
    g_object_class_install_property(
        gobject, PROP_PIXEL_PITCH,
        g_param_spec_double("pixel-pitch", "Pixel pitch",
                            "Sensor pixel pitch of the frames in micrometres (0: unknown)", 0.0,
                            kMaxPixelPitchUm, 0.0, flags));
    g_object_class_install_property(
        gobject, PROP_FOCUS_DISTANCE,
        g_param_spec_double("focus-distance", "Focus distance",
                            "Distance in focus in metres, inf for infinity (0: unknown)", 0.0,
                            INFINITY, 0.0, flags));
    g_object_class_install_property(
        gobject, PROP_INTERVAL,
        g_param_spec_uint64("interval", "Interval",
                            "Least time between analysed frames in ns, by their timestamps (0: "
                            "every frame)",
                            0, G_MAXUINT64, kDefaultIntervalNs, flags));
    g_object_class_install_property(
        gobject, PROP_POST_MESSAGES,
        g_param_spec_boolean("post-messages", "Post messages",
                             "Post an infocus element message per analysed frame", TRUE, flags));
    g_object_class_install_property(
        gobject, PROP_ATTACH_META,
        g_param_spec_boolean("attach-meta", "Attach meta",
                             "Attach a GstVideoRegionOfInterestMeta per region of the newest "
                             "analysis to each buffer",
                             FALSE, flags));
    g_object_class_install_property(
        gobject, PROP_SKIP_FRAMES,
        g_param_spec_boolean("skip-frames", "Skip frames",
                             "Skip frames while the analysis is busy, never holding up the "
                             "stream; false: wait so that every frame is analysed",
                             TRUE, flags));

    gst_element_class_set_static_metadata(
        element, "Focus meter", "Filter/Analyzer/Video",
        "Measures per-region sharpness and blur width and posts them as element messages",
        "infocus");
    gst_element_class_add_static_pad_template(element, &sinkTemplate);
    gst_element_class_add_static_pad_template(element, &srcTemplate);

    trans->start = start;
    trans->stop = stop;
    trans->set_caps = setCaps;
    trans->sink_event = sinkEvent;
    trans->query = query;
    trans->transform_ip = transformIp;
    // Passthrough is the element's own choice (off only to attach metas), not the caps'.
    trans->passthrough_on_same_caps = FALSE;
    trans->transform_ip_on_passthrough = TRUE;

    GST_DEBUG_CATEGORY_INIT(gst_focus_meter_debug, "focusmeter", 0, "infocus focus meter");
    gst_type_mark_as_plugin_api(metricEnumType(), static_cast<GstPluginAPIFlags>(0));
    gst_type_mark_as_plugin_api(transferEnumType(), static_cast<GstPluginAPIFlags>(0));
}

static void gst_focus_meter_init(GstFocusMeter* self) {
    self->s = new State();
    rebuildSettings(*self->s);
    gst_base_transform_set_passthrough(GST_BASE_TRANSFORM(self), TRUE);
}

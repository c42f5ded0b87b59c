// SPDX-License-Identifier: MIT
#include "src/live/web/web_control.h"

#include <array>
#include <nlohmann/json.hpp>
#include <optional>

#include "src/live/web/web_encode.h"

namespace infocus::web {

namespace {

using Json = nlohmann::json;

ControlReply ok(std::string status) {
    return {200, Json{{"ok", true}, {"status", std::move(status)}}.dump()};
}

ControlReply bad(std::string_view field, std::string_view what) {
    return {400, errorJson(std::string(field) + ": " + std::string(what))};
}

// The reply for a control's outcome: a refused value is the caller's (400), a source that cannot
// do it a conflict (409), a closing view 503.
ControlReply fromStatus(const Status& st, std::string_view field, std::string done) {
    if (st) return ok(std::move(done));
    switch (st.error().kind) {
        case ErrorKind::Usage:
            return bad(field, st.error().message);
        case ErrorKind::Unsupported:
        case ErrorKind::NotFound:
            return {409, errorJson(st.error().message)};
        default:
            return {503, errorJson(st.error().message)};
    }
}

bool isInt(const Json& v) {
    return v.is_number_integer() && v.get<int64_t>() >= -(1 << 30) && v.get<int64_t>() <= 1 << 30;
}

// An array of exactly @p n integers.
template <size_t N>
std::optional<std::array<int, N>> ints(const Json& v) {
    if (!v.is_array() || v.size() != N) return std::nullopt;
    std::array<int, N> out{};
    for (size_t i = 0; i < N; ++i) {
        if (!isInt(v[i])) return std::nullopt;
        out[i] = v[i].get<int>();
    }
    return out;
}

ControlReply noLens(std::string_view field) {
    return {409,
            errorJson(std::string(field) +
                      ": this source has no lens motor; focus it by hand and watch the meter")};
}

}  // namespace

bool sameSecret(std::string_view given, std::string_view expected) {
    const auto a = sha256(given);
    const auto b = sha256(expected);
    // Every byte is looked at; the volatile keeps the compiler from ending the loop early.
    volatile uint8_t diff = 0;
    for (size_t i = 0; i < a.size(); ++i)
        diff = static_cast<uint8_t>(diff | (a[i] ^ b[i]));
    return diff == 0;
}

std::string errorJson(std::string_view message) {
    return Json{{"error", message}}.dump(-1, ' ', false, Json::error_handler_t::replace);
}

ControlReply runControl(std::string_view body, LiveControls& controls, bool hasFocusControl) {
    const Json j = Json::parse(body, nullptr, false);
    if (j.is_discarded()) return {400, errorJson("the body is not JSON; send one command object")};
    if (!j.is_object() || j.size() != 1)
        return {400, errorJson("send one command as an object, e.g. {\"focus_step\": 1}")};
    const std::string field = j.begin().key();
    const Json& v = j.begin().value();

    if (field == "focus_step") {
        if (!isInt(v)) return bad(field, "give a whole number of steps, e.g. 1 or -10");
        if (!hasFocusControl) return noLens(field);
        const int n = v.get<int>();
        return fromStatus(controls.focusStep(n), field,
                          "focus moved " + std::to_string(n) + " steps");
    }
    if (field == "focus") {
        if (!v.is_number()) return bad(field, "give the lens position in its native unit");
        if (!hasFocusControl) return noLens(field);
        return fromStatus(controls.focusTo(v.get<double>()), field, "focus moved");
    }
    if (field == "autofocus") {
        // true (or "once") starts one autofocus; "continuous" and "off" switch continuous focus.
        std::optional<LiveAutofocusMode> parsed;
        if (v == true) parsed = LiveAutofocusMode::Once;
        if (v.is_string())
            if (auto m = parseLiveAutofocusMode(v.get<std::string>())) parsed = *m;
        if (!parsed)
            return bad(field, "send {\"autofocus\": true}, or \"once\", \"continuous\" or \"off\"");
        if (!hasFocusControl) return noLens(field);
        if (*parsed == LiveAutofocusMode::Once)
            return fromStatus(controls.autofocus(), field, "autofocus started");
        const bool on = *parsed == LiveAutofocusMode::Continuous;
        return fromStatus(controls.setContinuousAutofocus(on), field,
                          on ? "continuous autofocus on" : "continuous autofocus off");
    }
    if (field == "reset_peak") {
        if (v != true) return bad(field, "send {\"reset_peak\": true}");
        controls.resetPeak();
        return ok("peak reset");
    }
    if (field == "roi") {
        if (v.is_null())
            return fromStatus(controls.setScoreRoi(std::nullopt), field, "ROI cleared");
        const auto r = ints<4>(v);
        if (!r) return bad(field, "give [x, y, w, h] in frame pixels, or null");
        return fromStatus(controls.setScoreRoi(Rect{(*r)[0], (*r)[1], (*r)[2], (*r)[3]}), field,
                          "ROI set");
    }
    if (field == "magnifier") {
        if (v.is_null())
            return fromStatus(controls.setMagnifier(std::nullopt), field, "magnifier hidden");
        const auto m = ints<3>(v);
        if (!m) return bad(field, "give [x, y, zoom] in frame pixels with zoom 1 or 2, or null");
        return fromStatus(controls.setMagnifier(*m), field, "magnifier placed");
    }
    if (field == "grid") {
        const auto g = ints<2>(v);
        if (!g) return bad(field, "give [cols, rows], e.g. [16, 9]");
        return fromStatus(controls.setGrid((*g)[0], (*g)[1]), field, "grid changed");
    }
    if (field == "peaking") {
        if (!v.is_string()) return bad(field, "give \"off\", \"coc\" or \"percentile\"");
        auto mode = parsePeakingMode(v.get<std::string>());
        if (!mode) return bad(field, mode.error().message);
        return fromStatus(controls.setPeaking(*mode), field,
                          "peaking " + std::string(peakingModeName(*mode)));
    }
    return bad(field,
               "no such command; use focus_step, focus, autofocus, reset_peak, roi, "
               "magnifier, grid or peaking");
}

}  // namespace infocus::web

// SPDX-License-Identifier: MIT
// A V4L2 format's colour space and transfer function name the curve that encoded its grey levels:
// the kernel's V4L2_MAP_XFER_FUNC_DEFAULT table for the default, the explicit value otherwise
// (Documentation/userspace-api/media/v4l/colorspaces-defs.rst).
#include <catch2/catch.hpp>

#include "drivers/v4l2/v4l2_device.h"

using infocus::TransferFunction;
using infocus::v4l2::transferFromV4l2;

TEST_CASE("the default transfer function is the colour space's own") {
    const struct {
        uint32_t colorspace;
        TransferFunction curve;
    } cases[] = {
        {V4L2_COLORSPACE_SRGB, TransferFunction::Srgb},         // webcams (uvcvideo's default)
        {V4L2_COLORSPACE_JPEG, TransferFunction::Srgb},         // MJPEG
        {V4L2_COLORSPACE_REC709, TransferFunction::Rec709},     // HD video
        {V4L2_COLORSPACE_SMPTE170M, TransferFunction::Rec709},  // SD video: BT.601 uses BT.709's
        {V4L2_COLORSPACE_BT2020, TransferFunction::Rec709},     // BT.2020's SDR curve is BT.709's
        {V4L2_COLORSPACE_RAW, TransferFunction::Linear},        // a sensor's raw data
    };
    for (const auto& c : cases) {
        INFO("colorspace " << c.colorspace);
        const auto t = transferFromV4l2(c.colorspace, V4L2_XFER_FUNC_DEFAULT);
        REQUIRE(t.curve.has_value());
        CHECK(*t.curve == c.curve);
        CHECK_THAT(t.origin, Catch::Contains("colour space"));
    }
}

TEST_CASE("an explicit transfer function overrides the colour space's") {
    const auto rec709 = transferFromV4l2(V4L2_COLORSPACE_SRGB, V4L2_XFER_FUNC_709);
    CHECK(rec709.curve == TransferFunction::Rec709);
    CHECK_THAT(rec709.origin, Catch::Contains("transfer function"));
    CHECK(transferFromV4l2(V4L2_COLORSPACE_REC709, V4L2_XFER_FUNC_SRGB).curve ==
          TransferFunction::Srgb);
    CHECK(transferFromV4l2(V4L2_COLORSPACE_SRGB, V4L2_XFER_FUNC_NONE).curve ==
          TransferFunction::Linear);
}

TEST_CASE("curves infocus does not decode are named, not guessed") {
    const struct {
        uint32_t colorspace, xfer;
        const char* name;
    } cases[] = {
        {V4L2_COLORSPACE_OPRGB, V4L2_XFER_FUNC_DEFAULT, "opRGB"},
        {V4L2_COLORSPACE_SMPTE240M, V4L2_XFER_FUNC_DEFAULT, "SMPTE 240M"},
        {V4L2_COLORSPACE_DCI_P3, V4L2_XFER_FUNC_DEFAULT, "DCI-P3"},
        {V4L2_COLORSPACE_BT2020, V4L2_XFER_FUNC_SMPTE2084, "SMPTE 2084"},
        {V4L2_COLORSPACE_SRGB, 99, "99, unknown"},
    };
    for (const auto& c : cases) {
        const auto t = transferFromV4l2(c.colorspace, c.xfer);
        INFO(t.origin);
        CHECK(!t.curve);
        CHECK_THAT(t.origin, Catch::Contains(c.name));
    }
    // A driver that fills in neither field says nothing (the kernel's map would read BT.709).
    const auto none = transferFromV4l2(V4L2_COLORSPACE_DEFAULT, V4L2_XFER_FUNC_DEFAULT);
    CHECK(!none.curve);
    CHECK_THAT(none.origin, Catch::Contains("no colour space"));
}

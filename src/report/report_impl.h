// SPDX-License-Identifier: MIT
// Internal: what the report keeps of each frame (ReportWriter::Impl), shared by the document
// (page.cpp) and its figures (charts.cpp).
#pragma once

#include <turbojpeg.h>

#include <optional>
#include <string>
#include <vector>

#include "infocus/dof.h"
#include "infocus/report.h"

namespace infocus {

// A report being built: its options and, for every frame added, what its sections are drawn from.
struct ReportWriter::Impl {
    struct Entry {
        FrameAnalysis a;
        std::string jpeg;  // base64, empty without an image
        DepthMap map;
        std::optional<optics::CameraGeometry> camera;
        std::string focusSource;
        std::optional<optics::DofResult> dof;
    };
    ReportOptions o;
    std::vector<Entry> entries;
    tjhandle tj = nullptr;

    ~Impl() {
        if (tj) tjDestroy(tj);
    }

    // The frame @p luma reduced to the thumbnail width and encoded as a base64 JPEG; empty
    // without an image.
    Result<std::string> thumbnail(const Luma8& luma);
    // The camera that saw frame @p a: the report's lens and pitch, focused at the given distance
    // or at the frame's lens position (@p source says which); empty without them.
    std::optional<optics::CameraGeometry> cameraFor(const FrameAnalysis& a, std::string& source);

    // Each appends its part of frame @p e's section (the @p index-th) to @p h. The document
    // (page.cpp): the section with its summary, and the table of regions.
    void frameSection(std::string& h, const Entry& e, size_t index) const;
    void regionTable(std::string& h, const Entry& e) const;
    // The figures (charts.cpp): the frame tinted by blur, the blur and sharpness maps, and the
    // blur against the distance from the in-focus line.
    void overlay(std::string& h, const Entry& e) const;
    void maps(std::string& h, const Entry& e) const;
    void vPlot(std::string& h, const Entry& e) const;
};

}  // namespace infocus

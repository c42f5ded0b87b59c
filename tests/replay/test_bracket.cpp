// SPDX-License-Identifier: MIT
// Focus brackets as a lens: the Raspberry Pi camera's focus sweep (../shared/data/focus-sweep-pi,
// machine Z in mm from the names zNNN_Z±ZZZ.jpg) served as a source whose lens moves along Z.
// Setting a position serves the frame captured nearest it, after the delay frames; the source
// never ends. A recording whose frames carry lens positions brackets with bracket=recorded. Bad
// positions files (missing, malformed, out of order, short) are refused naming the file and line.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "infocus/recording.h"
#include "infocus/source.h"
#include "replay/replay_sources.h"
#include "tests/common/scratch_dir.h"
#include "tests/common/test_data.h"

using namespace infocus;
namespace fs = std::filesystem;

namespace {

// Machine Z (mm) of each frame of the sweep, by frame number, from the file names.
std::map<int, int> sweepZ(const fs::path& dir) {
    std::map<int, int> z;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name.size() == 14 && name[0] == 'z' && name.substr(4, 2) == "_Z")
            z[std::stoi(name.substr(1, 3))] = std::stoi(name.substr(6, 4));
    }
    return z;
}

// The positions file `stack --positions` reads, built from the names.
std::string writeCsv(const test::ScratchDir& tmp, const std::map<int, int>& z) {
    const std::string path = tmp.file("pi.csv");
    std::ofstream out(path);
    out << "frame,position,unit\n";
    for (const auto& [frame, mm] : z)
        out << frame << "," << mm << ",mm\n";
    return path;
}

Result<std::unique_ptr<FrameSource>> open(const std::string& text) {
    auto spec = parseSourceSpec(text);
    REQUIRE(spec.ok());
    return replay::openPathSource(*spec);
}

std::string fileName(const Frame& f) {
    return fs::path(f.origin).filename().string();
}

}  // namespace

TEST_CASE("bracket: the Pi sweep as a lens serves the frame nearest the position") {
    const fs::path dir = test::requireData("focus-sweep-pi");
    const auto z = sweepZ(dir);
    if (z.size() != 131) test::skipExecutable("focus-sweep-pi does not hold its 131 frames");
    test::ScratchDir tmp("infocus-bracket-");
    const std::string csv = writeCsv(tmp, z);
    auto src = open(dir.string() + ",bracket=" + csv + ",pace=fast");
    REQUIRE(src.ok());
    const SourceInfo info = (*src)->info();
    CHECK(info.driver == "bracket");
    CHECK_FALSE(info.frameCount.has_value());  // live: it never ends
    CHECK(info.device.find("131 frames") != std::string::npos);
    FocusControl* focus = (*src)->focusControl();
    REQUIRE(focus);
    const FocusRange range = focus->range();
    CHECK(range.min == -110);
    CHECK(range.max == 20);
    CHECK(range.step == 1);
    CHECK(range.unit == "mm");
    CHECK(range.defaultValue == 20);  // the first frame's

    REQUIRE((*src)->start().ok());
    auto first = (*src)->next();
    REQUIRE(first.ok());
    CHECK(fileName(*first) == "z000_Z+020.jpg");
    CHECK(first->lens->value == 20);

    // Position asked for → the frame at the nearest Z (ties go to the lower Z).
    const std::pair<double, const char*> cases[] = {
        {-50, "z070_Z-050.jpg"},    {-49.6, "z070_Z-050.jpg"}, {-49.4, "z069_Z-049.jpg"},
        {-109.9, "z130_Z-110.jpg"}, {-500, "z130_Z-110.jpg"},  {7.5, "z013_Z+007.jpg"},
        {19.2, "z001_Z+019.jpg"},   {1e9, "z000_Z+020.jpg"},
    };
    double at = 20;
    for (const auto& [value, expected] : cases) {
        INFO("set " << value << " mm");
        Frame before = *(*src)->next();
        REQUIRE(focus->set(value).ok());
        const double to = std::clamp(value, -110.0, 20.0);
        const int discard = focus->framesToSettle(at, to);
        CHECK(discard >= 2);
        for (int i = 0; i < discard; ++i) {
            auto f = (*src)->next();
            REQUIRE(f.ok());
            if (i < 2) CHECK(fileName(*f) == fileName(before));  // in flight: the old frame
        }
        for (int i = 0; i < 3; ++i) {
            auto f = (*src)->next();
            REQUIRE(f.ok());
            CHECK(fileName(*f) == expected);
            CHECK(f->lens->value == z.at(std::stoi(std::string(expected).substr(1, 3))));
        }
        at = to;
    }
    // Served for as long as it is asked, with rising sequence numbers and timestamps.
    uint64_t last = 0;
    for (int i = 0; i < 300; ++i) {
        auto f = (*src)->next();
        REQUIRE(f.ok());
        CHECK(f->sequence > last);
        last = f->sequence;
    }
}

TEST_CASE("bracket: a starting position, and options refused") {
    const fs::path dir = test::requireData("focus-sweep-pi");
    const auto z = sweepZ(dir);
    if (z.size() != 131) test::skipExecutable("focus-sweep-pi does not hold its 131 frames");
    test::ScratchDir tmp("infocus-bracket-");
    const std::string csv = writeCsv(tmp, z);
    auto src = open((dir / "z*.jpg").string() + ",bracket=" + csv + ",pace=fast,focus=-100");
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    CHECK(fileName(*(*src)->next()) == "z120_Z-100.jpg");
    for (const char* bad : {",focus=30", ",delay=-1", ",travel=fast", ",pace=slow", ",loop=1"}) {
        INFO(bad);
        auto s = open(dir.string() + ",bracket=" + csv + bad);
        REQUIRE_FALSE(s.ok());
        CHECK(s.error().kind == ErrorKind::Usage);
    }
}

TEST_CASE("bracket: bad positions files name the file and the line") {
    const fs::path dir = test::requireData("focus-sweep-pi");
    const auto z = sweepZ(dir);
    if (z.size() != 131) test::skipExecutable("focus-sweep-pi does not hold its 131 frames");
    test::ScratchDir tmp("infocus-bracket-");
    // Every row's text, so that a case can replace one.
    std::vector<std::string> rows;
    for (const auto& [frame, mm] : z)
        rows.push_back(std::to_string(frame) + "," + std::to_string(mm) + ",mm");
    const auto write = [&](const std::string& name, const std::vector<std::string>& lines) {
        std::ofstream out(tmp.file(name));
        out << "frame,position,unit\n";
        for (const auto& l : lines)
            out << l << "\n";
        return tmp.file(name);
    };
    struct Case {
        const char* what;
        std::string file;
        ErrorKind kind;
        const char* says;
    };
    std::vector<std::string> malformed = rows, swapped = rows, backwards = rows, shortRows = rows;
    malformed[40] = "40;-20;mm";
    swapped[50] = "50,-29,mm";  // Z -30 expected: -29 repeats frame 49's and turns back
    backwards[90] = "90,-60,mm";
    shortRows.pop_back();
    const Case cases[] = {
        {"missing", tmp.file("none.csv"), ErrorKind::NotFound, "none.csv"},
        {"malformed", write("malformed.csv", malformed), ErrorKind::Usage, "line 42"},
        {"out of order", write("swapped.csv", swapped), ErrorKind::Usage, "line 52"},
        {"backwards", write("backwards.csv", backwards), ErrorKind::Usage, "line 92"},
        {"a frame short", write("short.csv", shortRows), ErrorKind::Usage, "131"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        auto s = open(dir.string() + ",bracket=" + c.file);
        REQUIRE_FALSE(s.ok());
        CHECK(s.error().kind == c.kind);
        CHECK(s.error().message.find(fs::path(c.file).filename().string()) != std::string::npos);
        CHECK(s.error().message.find(c.says) != std::string::npos);
    }
    // Images carry no lens positions of their own.
    auto s = open(dir.string() + ",bracket=recorded");
    REQUIRE_FALSE(s.ok());
    CHECK(s.error().message.find("no lens position") != std::string::npos);
}

TEST_CASE("bracket: a recording whose frames carry lens positions") {
    // Record the sim's lens at 0.5, 1, ... 5 dpt (at rest each time), then serve it as a lens.
    test::ScratchDir tmp("infocus-bracket-rec-");
    const std::string rec = tmp.file("rec");
    {
        auto spec = parseSourceSpec("sim:size=64x48,pace=fast,focus=0.5dpt");
        auto sim = replay::openSimSource(*spec);
        REQUIRE(sim.ok());
        FocusControl* lens = (*sim)->focusControl();
        auto writer = RecordingWriter::create(rec, makeRecordingHeader((*sim)->info(), lens));
        REQUIRE(writer.ok());
        REQUIRE((*sim)->start().ok());
        for (int i = 1; i <= 10; ++i) {
            REQUIRE(lens->set(0.5 * i).ok());
            for (int k = 0; k < lens->settleFrames(); ++k)
                REQUIRE((*sim)->next().ok());
            auto f = (*sim)->next();
            REQUIRE(f.ok());
            REQUIRE(f->lens->value == 0.5 * i);
            REQUIRE((*writer)->append(*f).ok());
        }
        REQUIRE((*writer)->close().ok());
    }
    auto src = open(rec + ",bracket=recorded,pace=fast,delay=0,travel=0ms,settle=0ms");
    REQUIRE(src.ok());
    FocusControl* focus = (*src)->focusControl();
    CHECK(focus->range().min == 0.5);
    CHECK(focus->range().max == 5.0);
    CHECK(focus->range().unit == "dioptre");
    REQUIRE(focus->set(3.0).ok());
    CHECK(focus->get()->dioptres == 3.0);
    CHECK(focus->framesToSettle(0.5, 5.0) == 0);  // an ideal lens delivered at once
    REQUIRE((*src)->start().ok());
    for (double v : {2.6, 1.2, 4.9}) {
        REQUIRE(focus->set(v).ok());
        auto f = (*src)->next();
        REQUIRE(f.ok());
        CHECK(f->lens->value == std::round(v * 2) / 2);
        CHECK(f->lens->dioptres.has_value());
    }
}

// SPDX-License-Identifier: MIT
// Recordings round-trip bit-exact with their metadata for every pixel format (MJPEG with a real
// JPEG), and damaged recordings replay their intact frames and report the damage.
#include <sys/resource.h>
#include <sys/stat.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "infocus/recording.h"
#include "infocus/source.h"
#include "replay/recording_format.h"
#include "replay/replay_sources.h"
#include "tests/common/scratch_dir.h"

using namespace infocus;

namespace {

// A path for a new recording directory named @p name, in one scratch directory for the whole
// run (removed at exit): some recordings outlive the function that wrote them.
std::string tempDir(const std::string& name) {
    static const test::ScratchDir scratch("infocus-test-rec-");
    static int made = 0;
    return scratch.file(name + std::to_string(++made));
}

uint8_t pattern(size_t i, unsigned plane, uint64_t seq) {
    return static_cast<uint8_t>((i * 31 + plane * 97 + seq * 13 + (i >> 7)) & 255);
}

// A frame of @p format filled with a pattern that differs per plane, byte and frame.
Frame patterned(PixelFormat format, Size size, size_t stride, uint64_t seq) {
    auto f = allocateFrame(format, size, stride);
    REQUIRE(f.ok());
    for (unsigned p = 0; p < f->numPlanes; ++p)
        for (size_t i = 0; i < f->planes[p].size; ++i)
            mutablePlane(*f, p)[i] = pattern(i, p, seq);
    return *f;
}

// A real JPEG of a gradient, encoded by libturbojpeg.
std::vector<uint8_t> encodeJpeg(int w, int h, int seed) {
    std::vector<uint8_t> rgb(static_cast<size_t>(w) * h * 3);
    for (size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = static_cast<uint8_t>((i * 7 + seed * 11) & 255);
    tjhandle tj = tjInitCompress();
    unsigned char* out = nullptr;
    unsigned long size = 0;
    REQUIRE(tjCompress2(tj, rgb.data(), w, 0, h, TJPF_RGB, &out, &size, TJSAMP_422, 85, 0) == 0);
    std::vector<uint8_t> bytes(out, out + size);
    tjFree(out);
    tjDestroy(tj);
    return bytes;
}

void requireSameFrame(const Frame& a, const Frame& b) {
    REQUIRE(a.format == b.format);
    REQUIRE(a.size == b.size);
    REQUIRE(a.numPlanes == b.numPlanes);
    for (unsigned p = 0; p < a.numPlanes; ++p) {
        REQUIRE(a.planes[p].stride == b.planes[p].stride);
        REQUIRE(a.planes[p].size == b.planes[p].size);
        REQUIRE(std::memcmp(a.planes[p].data, b.planes[p].data, a.planes[p].size) == 0);
    }
    REQUIRE(a.sequence == b.sequence);
    REQUIRE(a.timestampNs == b.timestampNs);
    REQUIRE(a.lens == b.lens);
    REQUIRE(a.exposureS == b.exposureS);
}

RecordingHeader header(PixelFormat format, Size size) {
    SourceInfo info;
    info.sourceString = "v4l2:/dev/video0,format=" + pixelFormatName(format);
    info.device = "/dev/video0";
    info.driver = "uvcvideo";
    info.format = format;
    info.size = size;
    info.fps = 30;
    return makeRecordingHeader(info, nullptr);
}

// Opens a path source through the replay module (what openSource() does for kind "path").
Result<std::unique_ptr<FrameSource>> openPath(const std::string& text) {
    auto spec = parseSourceSpec(text);
    if (!spec) return spec.error();
    return replay::openPathSource(*spec);
}

uint64_t fileSize(const std::string& path) {
    struct stat st;
    REQUIRE(::stat(path.c_str(), &st) == 0);
    return static_cast<uint64_t>(st.st_size);
}

}  // namespace

TEST_CASE("CRC-32 matches the standard check value") {
    // The CRC-32 check value of "123456789" is 0xCBF43926 (IEEE 802.3, as zlib and PNG).
    REQUIRE(replay::crc32("123456789", 9) == 0xCBF43926u);
    // Chaining over pieces gives the same as one call.
    REQUIRE(replay::crc32("6789", 4, replay::crc32("12345", 5)) == 0xCBF43926u);
    // Every length and alignment about the folded blocks' edges (64-byte blocks, 16-byte
    // tails) agrees with a plain bit-at-a-time CRC.
    std::vector<uint8_t> bytes(700);
    uint32_t state = 12345;
    for (uint8_t& b : bytes)
        b = static_cast<uint8_t>((state = state * 1103515245u + 12345u) >> 24);
    const auto bitwise = [](const uint8_t* p, size_t n, uint32_t crc) {
        crc = ~crc;
        while (n--) {
            crc ^= *p++;
            for (int k = 0; k < 8; ++k)
                crc = (crc & 1) ? 0xEDB88320u ^ (crc >> 1) : crc >> 1;
        }
        return ~crc;
    };
    int wrong = 0;
    for (size_t offset : {0, 1, 5, 8})
        for (size_t n = 0; n + offset <= bytes.size(); n += n < 200 ? 1 : 37)
            wrong +=
                replay::crc32(bytes.data() + offset, n, 7) != bitwise(bytes.data() + offset, n, 7);
    CHECK(wrong == 0);
}

TEST_CASE("every pixel format round-trips bit-exact with metadata") {
    struct Case {
        PixelFormat format;
        Size size;
        size_t stride;
    };
    const Case cases[] = {
        {PixelFormat::YUYV, {64, 30}, 0},  {PixelFormat::UYVY, {32, 16}, 96},
        {PixelFormat::NV12, {64, 48}, 80}, {PixelFormat::NV21, {32, 16}, 0},
        {PixelFormat::YU12, {64, 32}, 96}, {PixelFormat::GREY, {33, 17}, 40},
        {PixelFormat::Y10, {20, 10}, 0},   {PixelFormat::Y16, {21, 11}, 48},
        {PixelFormat::RGB24, {15, 9}, 48}, {PixelFormat::BGR24, {16, 8}, 0},
        {PixelFormat::SRGGB8, {16, 8}, 0}, {PixelFormat::SGRBG8, {16, 8}, 0},
        {PixelFormat::SGBRG8, {16, 8}, 0}, {PixelFormat::SBGGR8, {16, 8}, 0},
    };
    for (const Case& c : cases) {
        INFO("format " << pixelFormatName(c.format));
        const std::string dir = tempDir("rec");
        std::vector<Frame> written;
        {
            auto w = RecordingWriter::create(dir, header(c.format, c.size));
            REQUIRE(w.ok());
            for (uint64_t seq = 0; seq < 4; ++seq) {
                Frame f = patterned(c.format, c.size, c.stride, seq);
                f.sequence = 100 + seq + (seq == 3 ? 2 : 0);  // a gap before the last frame
                f.timestampNs = 1'000'000'000'000 + static_cast<int64_t>(seq) * 33'333'333;
                if (seq % 2 == 0)
                    f.lens = LensPosition{250.0 + seq, "v4l2", std::nullopt};
                else
                    f.lens = LensPosition{1.25 + seq, "dioptre", 1.25 + seq};
                if (seq != 2) f.exposureS = 0.01 * (seq + 1);
                REQUIRE((*w)->append(f).ok());
                written.push_back(f);
            }
            REQUIRE((*w)->droppedFlags() == 1);
            REQUIRE((*w)->close().ok());
        }
        auto r = RecordingReader::open(dir);
        REQUIRE(r.ok());
        REQUIRE((*r)->frameCount() == written.size());
        REQUIRE(!(*r)->damage());
        REQUIRE((*r)->header().format == c.format);
        REQUIRE((*r)->header().size == c.size);
        REQUIRE((*r)->header().driver == "uvcvideo");
        REQUIRE((*r)->header().formatVersion == replay::kRecordingFormatVersion);
        for (size_t i = 0; i < written.size(); ++i) {
            auto f = (*r)->read(i);
            REQUIRE(f.ok());
            requireSameFrame(*f, written[i]);
            REQUIRE((*r)->frameInfo(i).droppedBefore == (i == 3));
        }
    }
}

TEST_CASE("MJPEG frames of different sizes round-trip and replay through openSource") {
    const std::string dir = tempDir("mjpeg");
    std::vector<std::vector<uint8_t>> jpegs;
    {
        SourceInfo info;
        info.sourceString = "libcamera:0";
        info.format = PixelFormat::MJPEG;
        info.size = {64, 48};
        FocusRange range{0.0, 15.0, 0.0, 1.0, "dioptre"};
        struct Fake : FocusControl {
            FocusRange r;
            FocusRange range() const override { return r; }
            Result<LensPosition> get() override { return LensPosition{}; }
            Status set(double) override { return {}; }
            int settleFrames() const override { return 2; }
        } focus;
        focus.r = range;
        auto w = RecordingWriter::create(dir, makeRecordingHeader(info, &focus));
        REQUIRE(w.ok());
        for (int i = 0; i < 3; ++i) {
            jpegs.push_back(encodeJpeg(64, 48, i * 40));
            Frame f = makeCompressedFrame(PixelFormat::MJPEG, {64, 48}, jpegs.back().data(),
                                          jpegs.back().size());
            f.sequence = static_cast<uint64_t>(i);
            f.timestampNs = i * 10'000'000;
            f.lens = LensPosition{0.5 * i, "dioptre", 0.5 * i};
            REQUIRE((*w)->append(f).ok());
        }
    }
    // JPEG sizes differ, so records are of variable length.
    REQUIRE(jpegs[0].size() != jpegs[2].size());
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    REQUIRE((*r)->header().focus.has_value());
    REQUIRE((*r)->header().focus->max == 15.0);
    REQUIRE((*r)->header().focus->unit == "dioptre");

    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->info().format == PixelFormat::MJPEG);
    REQUIRE((*src)->start().ok());
    for (int i = 0; i < 3; ++i) {
        auto f = (*src)->next();
        REQUIRE(f.ok());
        REQUIRE(f->planes[0].size == jpegs[i].size());
        REQUIRE(std::memcmp(f->planes[0].data, jpegs[i].data(), jpegs[i].size()) == 0);
        REQUIRE(f->lens->dioptres == Approx(0.5 * i).margin(0));  // stored as the exact double
    }
    auto end = (*src)->next();
    REQUIRE(!end.ok());
    REQUIRE(end.error().kind == ErrorKind::EndOfStream);
}

namespace {

// Writes @p n GREY frames of 16x8 to a new recording and returns its directory.
std::string writeGrey(int n) {
    const std::string dir = tempDir("grey");
    auto w = RecordingWriter::create(dir, header(PixelFormat::GREY, {16, 8}));
    REQUIRE(w.ok());
    for (int i = 0; i < n; ++i) {
        Frame f = patterned(PixelFormat::GREY, {16, 8}, 0, static_cast<uint64_t>(i));
        f.sequence = static_cast<uint64_t>(i);
        f.timestampNs = i * 40'000'000LL;  // 25 fps
        REQUIRE((*w)->append(f).ok());
    }
    return dir;
}

constexpr uint64_t kGreyRecord = sizeof(replay::RecordHeader) + 16 * 8;

}  // namespace

TEST_CASE("a recording keeps the transfer function its source named, and where it came from") {
    for (const auto curve :
         {std::optional<TransferFunction>{}, std::optional{TransferFunction::Linear},
          std::optional{TransferFunction::Srgb}, std::optional{TransferFunction::Rec709}}) {
        SourceInfo info;
        info.sourceString = "v4l2:/dev/video0";
        info.format = PixelFormat::GREY;
        info.size = {16, 8};
        info.transfer = {curve, "the V4L2 format's colour space"};
        const std::string dir = tempDir("transfer");
        {
            auto w = RecordingWriter::create(dir, makeRecordingHeader(info, nullptr));
            REQUIRE(w.ok());
            REQUIRE((*w)->append(patterned(PixelFormat::GREY, {16, 8}, 0, 0)).ok());
        }
        auto r = RecordingReader::open(dir);
        REQUIRE(r.ok());
        CHECK((*r)->header().transfer.curve == curve);
        CHECK((*r)->header().transfer.origin == "the V4L2 format's colour space");
        auto s = openPath(dir);
        REQUIRE(s.ok());
        CHECK((*s)->info().transfer.curve == curve);
        CHECK((*s)->info().transfer.origin ==
              "the recording's header: the V4L2 format's colour space");
    }
    // Recordings made before the header named it replay as unknown, and say so.
    const std::string dir = writeGrey(1);
    std::ifstream in(dir + "/header.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const std::string key : {"\"transfer\": null,\n", "\"transfer_origin\": \"\",\n"}) {
        const size_t pos = text.find(key);
        REQUIRE(pos != std::string::npos);
        text.erase(pos, key.size());
    }
    std::ofstream(dir + "/header.json") << text;
    auto s = openPath(dir);
    REQUIRE(s.ok());
    CHECK(!(*s)->info().transfer.curve);
    CHECK((*s)->info().transfer.origin == "the recording's header names no transfer function");
}

TEST_CASE("a truncated recording replays its complete frames and reports the torn one") {
    const std::string dir = writeGrey(5);
    const std::string frames = dir + "/frames.bin";
    REQUIRE(fileSize(frames) == 5 * kGreyRecord);
    // Cut inside frame 3's payload, as a kill during its write would.
    REQUIRE(::truncate(frames.c_str(), 3 * kGreyRecord + 150) == 0);
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    REQUIRE((*r)->frameCount() == 3);
    REQUIRE((*r)->damage().has_value());
    REQUIRE_THAT(*(*r)->damage(), Catch::Contains("frame 3") && Catch::Contains("incomplete") &&
                                      Catch::Contains(frames));

    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    for (uint64_t i = 0; i < 3; ++i) {
        auto f = (*src)->next();
        REQUIRE(f.ok());
        REQUIRE(f->sequence == i);
        REQUIRE(f->planes[0].data[5] == pattern(5, 0, i));
    }
    auto torn = (*src)->next();
    REQUIRE(!torn.ok());
    REQUIRE(torn.error().kind == ErrorKind::Corrupt);
    REQUIRE((*src)->stats().errors == 1);
    auto end = (*src)->next();
    REQUIRE(end.error().kind == ErrorKind::EndOfStream);
    REQUIRE((*src)->stats().delivered == 3);

    // A cut inside a record header is detected too.
    REQUIRE(::truncate(frames.c_str(), 2 * kGreyRecord + 10) == 0);
    auto r2 = RecordingReader::open(dir);
    REQUIRE(r2.ok());
    REQUIRE((*r2)->frameCount() == 2);
    REQUIRE_THAT(*(*r2)->damage(), Catch::Contains("frame 2"));
}

TEST_CASE("a disk that fills up mid-frame keeps the frames before it and says what to do") {
    // The file size limit stands in for a full disk: past it a write fails (EFBIG) as it would
    // with ENOSPC, part-way through the fourth frame's record.
    const std::string dir = tempDir("full");
    auto w = RecordingWriter::create(dir, header(PixelFormat::GREY, {16, 8}));
    REQUIRE(w.ok());
    rlimit saved{};
    REQUIRE(::getrlimit(RLIMIT_FSIZE, &saved) == 0);
    const auto previous = std::signal(SIGXFSZ, SIG_IGN);
    rlimit small = saved;
    small.rlim_cur = 3 * kGreyRecord + 50;
    REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
    std::optional<Error> failure;
    int appended = 0;
    for (int i = 0; i < 6 && !failure; ++i) {
        Frame f = patterned(PixelFormat::GREY, {16, 8}, 0, static_cast<uint64_t>(i));
        f.sequence = static_cast<uint64_t>(i);
        f.timestampNs = i * 40'000'000LL;
        auto r = (*w)->append(f);
        if (r.ok())
            ++appended;
        else
            failure = r.error();
    }
    ::setrlimit(RLIMIT_FSIZE, &saved);
    std::signal(SIGXFSZ, previous);
    w->reset();
    REQUIRE(appended == 3);
    REQUIRE(failure.has_value());
    CHECK(failure->kind == ErrorKind::Io);
    CHECK_THAT(failure->message, Catch::Contains("cannot write frame 3 to " + dir) &&
                                     Catch::Contains("the 3 frames before it are kept") &&
                                     Catch::Contains("free disk space"));
    // And they are: three frames replay, the torn fourth was cut off again.
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    CHECK((*r)->frameCount() == 3);
    CHECK(!(*r)->damage().has_value());
}

TEST_CASE("a corrupt frame is reported and skipped, the others replay") {
    const std::string dir = writeGrey(4);
    {
        std::fstream f(dir + "/frames.bin", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(kGreyRecord + sizeof(replay::RecordHeader) + 7));
        f.put('\x5a' ^ static_cast<char>(pattern(7, 0, 1)));
    }
    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    std::vector<uint64_t> seen;
    int corrupt = 0;
    while (true) {
        auto f = (*src)->next();
        if (!f && f.error().kind == ErrorKind::EndOfStream) break;
        if (!f) {
            REQUIRE(f.error().kind == ErrorKind::Corrupt);
            REQUIRE_THAT(f.error().message, Catch::Contains("frame 1") && Catch::Contains("CRC"));
            ++corrupt;
            continue;
        }
        seen.push_back(f->sequence);
    }
    REQUIRE(corrupt == 1);
    REQUIRE(seen == std::vector<uint64_t>{0, 2, 3});
    REQUIRE((*src)->stats().errors == 1);

    // A damaged record header ends the index there (frames after it cannot be located).
    {
        std::fstream f(dir + "/frames.bin", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(2 * kGreyRecord + 20));
        f.put('\x7f');
    }
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    REQUIRE((*r)->frameCount() == 2);
    REQUIRE_THAT(*(*r)->damage(), Catch::Contains("damaged record header"));
}

TEST_CASE("bad recordings fail with errors that name the file and the problem") {
    SECTION("missing directory") {
        auto r = RecordingReader::open("/nonexistent/rec");
        REQUIRE(!r.ok());
        REQUIRE(r.error().kind == ErrorKind::NotFound);
        REQUIRE_THAT(r.error().message, Catch::Contains("/nonexistent/rec"));
        auto s = openPath("/nonexistent/rec");
        REQUIRE(!s.ok());
        REQUIRE(s.error().kind == ErrorKind::NotFound);
    }
    SECTION("newer format version") {
        const std::string dir = writeGrey(1);
        std::ifstream in(dir + "/header.json");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const size_t pos = text.find("\"format_version\": 1");
        REQUIRE(pos != std::string::npos);
        text.replace(pos, 19, "\"format_version\": 7");
        std::ofstream(dir + "/header.json") << text;
        auto r = RecordingReader::open(dir);
        REQUIRE(!r.ok());
        REQUIRE(r.error().kind == ErrorKind::Unsupported);
        REQUIRE_THAT(r.error().message,
                     Catch::Contains("version 7") && Catch::Contains("newer infocus"));
    }
    SECTION("header that is not JSON") {
        const std::string dir = writeGrey(1);
        std::ofstream(dir + "/header.json") << "{ truncated";
        auto r = RecordingReader::open(dir);
        REQUIRE(!r.ok());
        REQUIRE(r.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(r.error().message, Catch::Contains("header.json"));
    }
    SECTION("header fields of the wrong type are named, not thrown") {
        // Each edit keeps the header valid JSON (one field a line); the field then holds a value
        // of another type, or an integer past int.
        const std::pair<std::string, std::string> edits[] = {
            {"format", "99999999"},       {"infocus_version", "[]"},
            {"infocus_version", "1e308"}, {"format_version", "-4294967295"},
            {"format_version", "1.5"},    {"width_px", "\"16\""},
            {"height_px", "1e308"},       {"width_px", "4294967312"},
            {"created_unix_s", "1e308"},  {"width_px", "40000000"},
            {"transfer", "\"gamma\""},    {"transfer", "2.2"},
        };
        for (const auto& [key, value] : edits) {
            INFO(key << ": " << value);
            const std::string dir = writeGrey(1);
            std::ifstream in(dir + "/header.json");
            std::string text((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
            const size_t pos = text.find("\"" + key + "\": ");
            REQUIRE(pos != std::string::npos);
            const size_t from = pos + key.size() + 4;
            const size_t to = text.find_first_of(",\n", from);
            text.replace(from, to - from, value);
            std::ofstream(dir + "/header.json") << text;
            auto r = RecordingReader::open(dir);
            REQUIRE(!r.ok());
            CHECK(r.error().kind == ErrorKind::Corrupt);
            CHECK(r.error().message.find("header.json") != std::string::npos);
            CHECK(r.error().message.find(key) != std::string::npos);
        }
    }
    SECTION("an empty frame file has nothing to play") {
        const std::string dir = tempDir("empty");
        {
            auto w = RecordingWriter::create(dir, header(PixelFormat::GREY, {16, 8}));
            REQUIRE(w.ok());
        }
        auto s = openPath(dir);
        REQUIRE(!s.ok());
        REQUIRE(s.error().kind == ErrorKind::NotFound);
    }
    SECTION("the writer names a file given as the output directory") {
        // It said "check that the parent directory exists and is writable", which it was.
        const std::string file = tempDir("file");
        std::ofstream(file) << "not a directory";
        auto w = RecordingWriter::create(file, header(PixelFormat::GREY, {16, 8}));
        REQUIRE(!w.ok());
        CHECK(w.error().kind == ErrorKind::Usage);
        CHECK_THAT(w.error().message, Catch::Contains(file + " exists and is not a directory"));
    }
    SECTION("the writer refuses a directory that holds files") {
        const std::string dir = writeGrey(1);
        auto w = RecordingWriter::create(dir, header(PixelFormat::GREY, {16, 8}));
        REQUIRE(!w.ok());
        REQUIRE(w.error().kind == ErrorKind::Usage);
        REQUIRE_THAT(w.error().message, Catch::Contains("not empty"));
    }
}

TEST_CASE("playback options: seek, loop with monotonic timestamps, pacing") {
    const std::string dir = writeGrey(5);  // timestamps 0, 40, ..., 160 ms
    SECTION("start by frame and by time") {
        auto s = openPath(dir + ",start=3");
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        REQUIRE((*s)->next()->sequence == 3);
        auto t = openPath(dir + ",start=0.1s");  // first frame at ≥ 100 ms is 120 ms
        REQUIRE(t.ok());
        REQUIRE((*t)->start().ok());
        REQUIRE((*t)->next()->timestampNs == 120'000'000);
        auto beyond = openPath(dir + ",start=5");
        REQUIRE(!beyond.ok());
        REQUIRE(beyond.error().kind == ErrorKind::Usage);
        // Past what a frame index or a count of nanoseconds can hold: refused or beyond, never
        // wrapped round to the first frame.
        for (const char* far : {",start=1e30", ",start=1e30s", ",start=1e300s"}) {
            INFO(far);
            auto f = openPath(dir + far);
            REQUIRE(!f.ok());
            CHECK(f.error().kind == ErrorKind::Usage);
        }
        auto late = openPath(dir + ",start=1e30s");
        REQUIRE(!late.ok());
        CHECK_THAT(late.error().message, Catch::Contains("start=1e+30s is beyond its last frame"));
    }
    SECTION("loop keeps timestamps and sequence numbers increasing") {
        auto s = openPath(dir + ",loop=1,start=1");
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        int64_t lastTs = -1;
        uint64_t lastSeq = 0;
        for (int i = 0; i < 13; ++i) {
            auto f = (*s)->next();
            REQUIRE(f.ok());
            if (i > 0) {
                // Each step is exactly one 40 ms frame interval, also across the loop.
                REQUIRE(f->timestampNs - lastTs == 40'000'000);
                REQUIRE(f->sequence == lastSeq + 1);
            }
            lastTs = f->timestampNs;
            lastSeq = f->sequence;
        }
        REQUIRE((*s)->stats().dropped == 0);
    }
    SECTION("fixed fps and original pacing take the expected wall time") {
        using clock = std::chrono::steady_clock;
        auto s = openPath(dir + ",fps=50");  // 5 frames: 4 intervals of 20 ms
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        auto t0 = clock::now();
        while ((*s)->next().ok()) {
        }
        const double fpsMs = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
        REQUIRE(fpsMs >= 79.0);                     // ≥ 4 × 20 ms minus 1 ms of timer slack
        auto o = openPath(dir + ",pace=original");  // 4 intervals of 40 ms
        REQUIRE(o.ok());
        REQUIRE((*o)->start().ok());
        t0 = clock::now();
        while ((*o)->next().ok()) {
        }
        const double origMs = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
        REQUIRE(origMs >= 159.0);  // a lower bound only: a loaded machine may take longer
    }
    SECTION("bad options are usage errors") {
        // fps past a million, or below one frame in 11.6 days, would overflow the timestamps.
        for (const char* opt : {",pace=slow", ",loop=2", ",start=abc", ",fps=0", ",speed=2",
                                ",fps=1e-300", ",fps=1e9"}) {
            auto s = openPath(dir + opt);
            REQUIRE(!s.ok());
            REQUIRE(s.error().kind == ErrorKind::Usage);
        }
    }
}

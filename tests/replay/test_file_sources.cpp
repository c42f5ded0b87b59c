// SPDX-License-Identifier: MIT
// File sources: Y4M in every colour space (luma delivered), images (JPEG as the file's bytes in an
// MJPEG frame, 8- and 16-bit PNG as GREY/Y16), directories and globs in name order, video files
// through OpenCV (the decoder module, loaded on demand), and clear errors for unreadable or missing
// files and a missing module.
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

#include "infocus/source.h"
#include "replay/decoders/decoders.h"
#include "replay/replay_sources.h"
#include "src/core/module_loader.h"
#include "tests/common/scratch_dir.h"
#include "tests/common/test_data.h"

using namespace infocus;

namespace {

Result<std::unique_ptr<FrameSource>> openPath(const std::string& text) {
    auto spec = parseSourceSpec(text);
    if (!spec) return spec.error();
    return replay::openPathSource(*spec);
}

uint8_t luma(int x, int y, int frame) {
    return static_cast<uint8_t>(x * 5 + y * 3 + frame * 17);
}

// Writes a Y4M file of @p frames frames; chroma bytes are 0xC5 so a reader that took them for
// luma would fail the pattern check.
void writeY4m(const std::string& path, const std::string& colour, int w, int h, int frames,
              size_t chromaBytes, int bytesPerSample = 1) {
    std::ofstream out(path, std::ios::binary);
    out << "YUV4MPEG2 W" << w << " H" << h << " F25:1 Ip A1:1";
    if (!colour.empty()) out << " C" << colour;
    out << " XCOMMENT=test\n";
    for (int f = 0; f < frames; ++f) {
        out << (f == 1 ? "FRAME Ixyz\n" : "FRAME\n");  // frame parameters must be skipped
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (bytesPerSample == 2) {
                    const uint16_t v = static_cast<uint16_t>(luma(x, y, f) * 4 + 1);  // 10-bit
                    out.put(static_cast<char>(v & 0xff)).put(static_cast<char>(v >> 8));
                } else {
                    out.put(static_cast<char>(luma(x, y, f)));
                }
            }
        for (size_t i = 0; i < chromaBytes * bytesPerSample; ++i)
            out.put('\xC5');
    }
}

std::vector<Frame> readAll(FrameSource& src, int* errors = nullptr) {
    REQUIRE(src.start().ok());
    std::vector<Frame> frames;
    while (true) {
        auto f = src.next();
        if (!f && f.error().kind == ErrorKind::EndOfStream) break;
        if (!f) {
            if (errors) ++*errors;
            continue;
        }
        frames.push_back(std::move(*f));
    }
    return frames;
}

}  // namespace

TEST_CASE("Y4M: 420, 422, 444 and mono deliver the luma plane") {
    const test::ScratchDir scratch("infocus-test-files-");
    const std::string dir = scratch.path();
    const int w = 9, h = 6;  // odd width: chroma planes round up
    struct Case {
        std::string colour;
        size_t chroma;
    };
    const Case cases[] = {
        {"", 2 * 5 * 3},  // default 420jpeg
        {"420paldv", 2 * 5 * 3},
        {"420mpeg2", 2 * 5 * 3},
        {"422", 2 * 5 * 6},
        {"444", 2 * 9 * 6},
        {"mono", 0},
    };
    for (const Case& c : cases) {
        INFO("colour space '" << c.colour << "'");
        const std::string path = dir + "/v" + c.colour + ".y4m";
        writeY4m(path, c.colour, w, h, 3, c.chroma);
        auto src = openPath(path);
        REQUIRE(src.ok());
        REQUIRE((*src)->info().fps == Approx(25.0).epsilon(1e-12));
        REQUIRE((*src)->info().frameCount == 3);
        const auto frames = readAll(**src);
        REQUIRE(frames.size() == 3);
        for (int f = 0; f < 3; ++f) {
            REQUIRE(frames[f].format == PixelFormat::GREY);
            REQUIRE(frames[f].timestampNs == f * 40'000'000LL);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    REQUIRE(frames[f].planes[0].data[y * frames[f].planes[0].stride + x] ==
                            luma(x, y, f));
        }
    }
    SECTION("10-bit 4:2:0 becomes Y10") {
        const std::string path = dir + "/p10.y4m";
        writeY4m(path, "420p10", w, h, 2, 2 * 5 * 3, 2);
        auto src = openPath(path);
        REQUIRE(src.ok());
        const auto frames = readAll(**src);
        REQUIRE(frames.size() == 2);
        REQUIRE(frames[1].format == PixelFormat::Y10);
        const uint8_t* p = frames[1].planes[0].data + 2 * (2 * w + 3);
        REQUIRE((p[0] | (p[1] << 8)) == luma(3, 2, 1) * 4 + 1);
    }
    SECTION("a truncated last frame is reported after the intact ones") {
        const std::string path = dir + "/cut.y4m";
        writeY4m(path, "mono", w, h, 3, 0);
        std::ifstream in(path, std::ios::binary | std::ios::ate);
        const auto size = static_cast<off_t>(in.tellg());
        REQUIRE(::truncate(path.c_str(), size - 10) == 0);
        auto src = openPath(path);
        REQUIRE(src.ok());
        REQUIRE((*src)->start().ok());
        REQUIRE((*src)->next().ok());
        REQUIRE((*src)->next().ok());
        auto bad = (*src)->next();
        REQUIRE(!bad.ok());
        REQUIRE(bad.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(bad.error().message, Catch::Contains("cut.y4m") &&
                                              Catch::Contains("frame 2") &&
                                              Catch::Contains("incomplete"));
        REQUIRE((*src)->stats().errors == 1);
    }
    SECTION("unsupported colour space") {
        const std::string path = dir + "/c411.y4m";
        writeY4m(path, "411", w, h, 1, 0);
        auto src = openPath(path);
        REQUIRE(!src.ok());
        REQUIRE(src.error().kind == ErrorKind::Unsupported);
        REQUIRE_THAT(src.error().message, Catch::Contains("411"));
    }
    SECTION("a header without a size says what to do") {
        const std::string path = dir + "/nosize.y4m";
        std::ofstream(path, std::ios::binary) << "YUV4MPEG2 H48 F25:1\nFRAME\n";
        auto src = openPath(path);
        REQUIRE(!src.ok());
        REQUIRE(src.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(src.error().message, Catch::Contains("nosize.y4m") &&
                                              Catch::Contains("no positive width") &&
                                              Catch::Contains("yuv4mpegpipe"));
    }
}

TEST_CASE("Y4M: a width or height that is not a whole number of pixels is named") {
    const test::ScratchDir scratch("infocus-test-y4m-size-");
    // atoi read "W1e9" as 1 and "H4294967297" as 1, and played a 1-pixel frame.
    for (const std::string size :
         {"W1e9 H48", "W64 H4294967297", "W0 H48", "W64 H", "W70000 H48", "W20000 H20000"}) {
        INFO(size);
        const std::string path = scratch.file("bad.y4m");
        {
            std::ofstream out(path, std::ios::binary);
            out << "YUV4MPEG2 " << size << " F25:1 Cmono\nFRAME\n" << std::string(64 * 48, 'x');
        }
        auto src = openPath(path);
        REQUIRE(!src.ok());
        CHECK(src.error().kind == ErrorKind::Corrupt);
        CHECK_THAT(src.error().message, Catch::Contains("bad.y4m") && Catch::Contains("pixels"));
    }
    // A frame rate it cannot read, or one so slow that the timestamps would overflow int64 by
    // the third frame (F1:2147483647 is 4.7e-10 fps), only loses the pace: the frames still
    // play, 30 frames a second apart.
    for (const std::string rate : {"F25:0", "F1:2147483647", "F1e3:1"}) {
        INFO(rate);
        const std::string path = scratch.file("rate.y4m");
        {
            std::ofstream out(path, std::ios::binary);
            out << "YUV4MPEG2 W64 H48 " << rate << " Cmono\n";
            for (int f = 0; f < 5; ++f)
                out << "FRAME\n" << std::string(64 * 48, 'x');
        }
        auto src = openPath(path);
        REQUIRE(src.ok());
        CHECK((*src)->info().size.width == 64);
        const auto frames = readAll(**src);
        REQUIRE(frames.size() == 5);
        CHECK(frames[4].timestampNs == 4 * 33'333'333);
    }
}

TEST_CASE("an image whose header claims more pixels than a frame may hold is refused at once") {
    const test::ScratchDir scratch("infocus-test-huge-");
    std::vector<uint8_t> jpeg;
    REQUIRE(cv::imencode(".jpg", cv::Mat(48, 64, CV_8UC1, cv::Scalar(90)), jpeg));
    // The SOF0 frame size patched to 60000 x 60000: 3.6 G pixels for a file of a few hundred
    // bytes, which the decoder would have allocated and filled.
    size_t sof = 2;
    while (sof + 9 < jpeg.size() && !(jpeg[sof] == 0xFF && jpeg[sof + 1] == 0xC0))
        ++sof;
    REQUIRE(sof + 9 < jpeg.size());
    for (const size_t at : {sof + 5, sof + 7})
        jpeg[at] = 60000 >> 8, jpeg[at + 1] = 60000 & 0xFF;
    const std::string path = scratch.file("huge.jpg");
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(jpeg.data()),
               static_cast<std::streamsize>(jpeg.size()));
    auto src = openPath(path);
    REQUIRE(!src.ok());
    CHECK(src.error().kind == ErrorKind::Corrupt);
    CHECK_THAT(src.error().message, Catch::Contains("huge.jpg") && Catch::Contains("60000x60000"));
}

TEST_CASE("images: JPEG as MJPEG bytes, PNG as GREY or Y16, directories and globs in order") {
    const test::ScratchDir scratch("infocus-test-files-");
    const std::string dir = scratch.path();
    cv::Mat grey(12, 20, CV_8UC1), wide(12, 20, CV_16UC1), colour(12, 20, CV_8UC3);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 20; ++x) {
            grey.at<uint8_t>(y, x) = luma(x, y, 0);
            wide.at<uint16_t>(y, x) = static_cast<uint16_t>(luma(x, y, 1) * 251);
            colour.at<cv::Vec3b>(y, x) = {luma(x, y, 2), luma(x, y, 3), luma(x, y, 4)};
        }
    REQUIRE(cv::imwrite(dir + "/b_grey.png", grey));
    REQUIRE(cv::imwrite(dir + "/c_wide.png", wide));
    REQUIRE(cv::imwrite(dir + "/a_photo.JPG", colour));
    std::ofstream(dir + "/notes.txt") << "not an image";  // ignored: not an image extension

    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->info().frameCount == 3);
    const auto frames = readAll(**src);
    REQUIRE(frames.size() == 3);
    // Name order: a_photo.JPG, b_grey.png, c_wide.png.
    REQUIRE(frames[0].format == PixelFormat::MJPEG);
    REQUIRE(frames[0].size == Size{20, 12});
    std::ifstream jpg(dir + "/a_photo.JPG", std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(jpg)),
                                  std::istreambuf_iterator<char>());
    REQUIRE(frames[0].planes[0].size == bytes.size());
    REQUIRE(std::memcmp(frames[0].planes[0].data, bytes.data(), bytes.size()) == 0);
    REQUIRE(frames[1].format == PixelFormat::GREY);
    REQUIRE(frames[1].planes[0].data[3 * frames[1].planes[0].stride + 7] == luma(7, 3, 0));
    REQUIRE(frames[2].format == PixelFormat::Y16);
    const uint8_t* p = frames[2].planes[0].data + 3 * frames[2].planes[0].stride + 2 * 7;
    REQUIRE((p[0] | (p[1] << 8)) == luma(7, 3, 1) * 251);
    REQUIRE(frames[2].sequence == 2);

    SECTION("a glob selects and orders files") {
        auto g = openPath(dir + "/*.png");
        REQUIRE(g.ok());
        const auto gf = readAll(**g);
        REQUIRE(gf.size() == 2);
        REQUIRE(gf[0].format == PixelFormat::GREY);
        REQUIRE(gf[1].format == PixelFormat::Y16);
        auto none = openPath(dir + "/*.tiff");
        REQUIRE(!none.ok());
        REQUIRE(none.error().kind == ErrorKind::NotFound);
    }
    SECTION("a single image with loop=1 repeats with increasing timestamps") {
        auto one = openPath(dir + "/b_grey.png,loop=1,fps=100");
        REQUIRE(one.ok());
        REQUIRE((*one)->start().ok());
        auto f0 = (*one)->next(), f1 = (*one)->next(), f2 = (*one)->next();
        REQUIRE(f1->timestampNs - f0->timestampNs == 10'000'000);
        REQUIRE(f2->timestampNs - f1->timestampNs == 10'000'000);
    }
    SECTION("an unreadable image in a sequence is reported, the others play") {
        std::ofstream(dir + "/bb_broken.png") << "garbage, not a PNG";
        int errors = 0;
        auto s = openPath(dir);
        REQUIRE(s.ok());
        const auto all = readAll(**s, &errors);
        REQUIRE(all.size() == 3);
        REQUIRE(errors == 1);
        REQUIRE((*s)->stats().errors == 1);
        auto alone = openPath(dir + "/bb_broken.png");
        REQUIRE(!alone.ok());
        REQUIRE(alone.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(alone.error().message, Catch::Contains("bb_broken.png"));
    }
    SECTION("an empty file and a JPEG cut inside its header say so") {
        std::ofstream(dir + "/empty.png").close();
        auto empty = openPath(dir + "/empty.png");
        REQUIRE(!empty.ok());
        REQUIRE(empty.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(empty.error().message, Catch::Contains("empty.png is empty (0 bytes)"));
        // The JPEG's first 20 bytes: its start marker and part of the APP0 segment, no frame
        // header.
        std::ofstream(dir + "/cut.jpg", std::ios::binary).write(bytes.data(), 20);
        auto cut = openPath(dir + "/cut.jpg");
        REQUIRE(!cut.ok());
        REQUIRE(cut.error().kind == ErrorKind::Corrupt);
        REQUIRE_THAT(cut.error().message, Catch::Contains("cut.jpg"));
        REQUIRE_THAT(cut.error().message, !Catch::Contains("OpenCV("));
    }
}

TEST_CASE("the real focus stack plays as MJPEG frames in name order") {
    const std::string dir = infocus::test::requireData("focus-stack/depthmap").string();
    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->info().frameCount == 10);
    REQUIRE((*src)->info().format == PixelFormat::MJPEG);
    REQUIRE((*src)->info().size == Size{2048, 1536});
}

TEST_CASE("video files play through OpenCV as GREY frames") {
    const test::ScratchDir scratch("infocus-test-files-");
    const std::string path = scratch.file("clip.avi");
    {
        cv::VideoWriter vw(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 20.0, {64, 48});
        REQUIRE(vw.isOpened());
        for (int f = 0; f < 6; ++f) {
            // Uniform grey levels survive the JPEG compression within a few levels.
            cv::Mat m(48, 64, CV_8UC3, cv::Scalar::all(40 + 30 * f));
            vw.write(m);
        }
    }
    auto src = openPath(path);
    REQUIRE(src.ok());
    REQUIRE((*src)->info().fps == Approx(20.0).epsilon(1e-6));
    const auto frames = readAll(**src);
    REQUIRE(frames.size() == 6);
    for (int f = 0; f < 6; ++f) {
        REQUIRE(frames[f].format == PixelFormat::GREY);
        REQUIRE(frames[f].timestampNs == f * 50'000'000LL);
        // JPEG round trip of a flat colour: within 3 grey levels.
        REQUIRE(std::abs(frames[f].planes[0].data[10 * 64 + 10] - (40 + 30 * f)) <= 3);
    }
    auto seek = openPath(path + ",start=4");
    REQUIRE(seek.ok());
    const auto tail = readAll(**seek);
    REQUIRE(tail.size() == 2);
    REQUIRE(std::abs(tail[0].planes[0].data[0] - (40 + 30 * 4)) <= 3);

    std::ofstream(path + ".bin") << "neither a video nor an image";
    auto bad = openPath(path + ".bin");
    REQUIRE(!bad.ok());
    REQUIRE_THAT(bad.error().message, Catch::Contains("clip.avi.bin"));
}

TEST_CASE("a truncated video reports the frames its container lists but that did not decode") {
    const test::ScratchDir scratch("infocus-test-files-");
    const std::string path = scratch.file("cut.avi");
    {
        cv::VideoWriter vw(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10.0, {64, 48});
        REQUIRE(vw.isOpened());
        for (int f = 0; f < 10; ++f)
            vw.write(cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(20 * f)));
    }
    // Cut the file just after its first frame's chunk ("00dc" in the "movi" list): the header
    // still lists 10.
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const size_t first = bytes.find("00dc", bytes.find("movi"));
    REQUIRE(first != std::string::npos);
    const size_t second = bytes.find("00dc", first + 4);
    REQUIRE(second != std::string::npos);
    std::filesystem::resize_file(path, second);
    auto src = openPath(path);
    REQUIRE(src.ok());
    REQUIRE((*src)->info().frameCount == 10);
    int errors = 0;
    std::vector<std::string> messages;
    REQUIRE((*src)->start().ok());
    size_t frames = 0;
    while (true) {
        auto f = (*src)->next();
        if (!f && f.error().kind == ErrorKind::EndOfStream) break;
        if (f) {
            ++frames;
            continue;
        }
        ++errors;
        messages.push_back(f.error().message);
        REQUIRE(f.error().kind == ErrorKind::Corrupt);
    }
    // The frame before the cut decodes; the nine after it are reported once, by file name.
    REQUIRE(frames == 1);
    REQUIRE(errors == 1);
    REQUIRE_THAT(messages[0], Catch::Contains("cut.avi") && Catch::Contains("lists 10 frames") &&
                                  Catch::Contains("9 of them"));
}

TEST_CASE("a video file is offered to OpenCV's file backends only, FFmpeg first") {
    const std::vector<int> apis = replay::videoFileBackends();
    REQUIRE(!apis.empty());
    CHECK(apis.front() == cv::CAP_FFMPEG);
    // A camera backend takes the path for a device: V4L2 opens it read-write, gphoto2 scans the
    // USB bus. Nor may the list defer to OpenCV's own choice, which tries them all.
    for (const int api : apis) {
        CHECK(api != cv::CAP_ANY);
        CHECK(api != cv::CAP_V4L2);
        CHECK(api != cv::CAP_GPHOTO2);
        CHECK(api != cv::CAP_FIREWIRE);
        CHECK(api != cv::CAP_UEYE);
    }
}

TEST_CASE("a missing module is named, with where it was looked for and what to do") {
    const test::ScratchDir scratch("infocus-test-modules-");
    const std::string dir = scratch.file("modules");
    auto entry = loadModuleEntry(replay::kDecodersModule, replay::kDecodersEntry,
                                 "reading video files", {dir, "/nonexistent"});
    REQUIRE(!entry.ok());
    CHECK(entry.error().kind == ErrorKind::Unsupported);
    const std::string& m = entry.error().message;
    CHECK_THAT(m, Catch::StartsWith("reading video files needs the module infocus-decoders.so"));
    CHECK_THAT(m, Catch::Contains(dir + ", /nonexistent"));
    CHECK_THAT(m, Catch::Contains("reinstall infocus, or set INFOCUS_MODULE_DIR"));

    // A file of that name that is no shared object: the loader's reason is given.
    std::ofstream(scratch.file(replay::kDecodersModule)) << "not a shared object";
    auto bad = loadModuleEntry(replay::kDecodersModule, replay::kDecodersEntry,
                               "reading video files", {scratch.path()});
    REQUIRE(!bad.ok());
    CHECK_THAT(bad.error().message, Catch::Contains("cannot be loaded"));
}

TEST_CASE("the build tree's decoder module is found and is of this version") {
    auto decoders = replay::loadDecoders("reading video files");
    REQUIRE(decoders.ok());
    CHECK((*decoders)->abi == replay::kDecodersAbi);
}

TEST_CASE("a FIFO or a device as a file source is refused, not waited on or read without end") {
    const test::ScratchDir scratch("infocus-test-files-");
    const std::string fifo = scratch.file("pipe.y4m");
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    // Before the check, opening the FIFO blocked until a writer came (never, here).
    auto src = openPath(fifo);
    REQUIRE(!src.ok());
    REQUIRE(src.error().kind != ErrorKind::Usage);
    REQUIRE_THAT(src.error().message, Catch::Contains("pipe.y4m") && Catch::Contains("FIFO"));
    auto dev = openPath("/dev/zero");
    REQUIRE(!dev.ok());
    REQUIRE_THAT(dev.error().message,
                 Catch::Contains("/dev/zero") && Catch::Contains("character device"));
}

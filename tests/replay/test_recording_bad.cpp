// SPDX-License-Identifier: MIT
// Recordings and playback under hostile input: crafted record lengths, extreme timestamps,
// frames without pixels, concurrent writers and a disk that fills up. Each ends in an error that
// names what is at fault, never in a crash, a hang or a recording that lies about its source.
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <barrier>
#include <catch2/catch.hpp>
#include <climits>
#include <csignal>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <thread>

#include "infocus/recording.h"
#include "infocus/source.h"
#include "replay/recording_format.h"
#include "replay/replay_sources.h"
#include "tests/common/scratch_dir.h"

using namespace infocus;

namespace {

// A path for a new recording directory named @p name, in one scratch directory for the run.
std::string tempDir(const std::string& name) {
    static const test::ScratchDir scratch("infocus-test-recbad-");
    static int made = 0;
    return scratch.file(name + std::to_string(++made));
}

RecordingHeader greyHeader(const std::string& sourceString) {
    SourceInfo info;
    info.sourceString = sourceString;
    info.format = PixelFormat::GREY;
    info.size = {16, 8};
    info.fps = 25;
    return makeRecordingHeader(info, nullptr);
}

Frame greyFrame(uint64_t seq, int64_t timestampNs) {
    auto f = allocateFrame(PixelFormat::GREY, {16, 8}, 0);
    REQUIRE(f.ok());
    for (size_t i = 0; i < f->planes[0].size; ++i)
        mutablePlane(*f, 0)[i] = static_cast<uint8_t>(i * 7 + seq);
    f->sequence = seq;
    f->timestampNs = timestampNs;
    return *f;
}

// A GREY 16x8 recording with one frame per timestamp in @p timestampsNs.
std::string writeGrey(const std::vector<int64_t>& timestampsNs) {
    const std::string dir = tempDir("grey");
    auto w = RecordingWriter::create(dir, greyHeader("sim:"));
    REQUIRE(w.ok());
    for (size_t i = 0; i < timestampsNs.size(); ++i)
        REQUIRE((*w)->append(greyFrame(i, timestampsNs[i])).ok());
    return dir;
}

constexpr uint64_t kGreyRecord = sizeof(replay::RecordHeader) + 16 * 8;

// Rewrites the header of record @p index with @p edit applied and its CRC recomputed, as a
// crafted file would have it.
template <typename Edit>
void craftRecord(const std::string& dir, uint64_t index, Edit edit) {
    std::fstream f(dir + "/frames.bin", std::ios::in | std::ios::out | std::ios::binary);
    REQUIRE(f);
    replay::RecordHeader h;
    f.seekg(static_cast<std::streamoff>(index * kGreyRecord));
    f.read(reinterpret_cast<char*>(&h), sizeof h);
    edit(h);
    h.headerCrc = replay::crc32(&h, offsetof(replay::RecordHeader, headerCrc));
    f.seekp(static_cast<std::streamoff>(index * kGreyRecord));
    f.write(reinterpret_cast<const char*>(&h), sizeof h);
}

Result<std::unique_ptr<FrameSource>> openPath(const std::string& text) {
    auto spec = parseSourceSpec(text);
    if (!spec) return spec.error();
    return replay::openPathSource(*spec);
}

// Runs @p body in a child process bounded by @p seconds of wall time: a reader that loops or
// allocates without end fails the test instead of taking the machine down. Returns the child's
// exit status as waitpid() gives it.
template <typename Body>
int inChild(unsigned seconds, Body body) {
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::alarm(seconds);
        rlimit mem{1ull << 30, 1ull << 30};
        ::setrlimit(RLIMIT_AS, &mem);
        int code = 3;
        try {
            code = body() ? 0 : 1;
        } catch (...) {
            code = 2;
        }
        ::_exit(code);
    }
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    return status;
}

}  // namespace

TEST_CASE("record lengths near 2^64 are refused before any addition or allocation") {
    // Each length makes offset + header + payload wrap: back onto the record itself (indexing
    // forever), onto the next record (a bogus index entry whose read allocates ~2^64 bytes), or
    // anywhere in between.
    const std::pair<uint32_t, uint64_t> lengths[] = {
        {128, UINT64_MAX - 127},  // end == offset
        {512, UINT64_MAX - 255},  // end == the next record
        {128, UINT64_MAX},
        {4096, UINT64_MAX - 5},
    };
    for (const auto& [headerBytes, payloadBytes] : lengths) {
        INFO("headerBytes " << headerBytes << ", payloadBytes " << payloadBytes);
        const std::string dir = writeGrey({0, 40'000'000, 80'000'000});
        craftRecord(dir, 1, [&](replay::RecordHeader& h) {
            h.headerBytes = headerBytes;
            h.payloadBytes = payloadBytes;
        });
        const int status = inChild(20, [&] {
            auto r = RecordingReader::open(dir);
            if (!r.ok() || (*r)->frameCount() != 1 || !(*r)->damage()) return false;
            const std::string& d = *(*r)->damage();
            if (d.find(dir + "/frames.bin: frame 1 at byte " + std::to_string(kGreyRecord)) ==
                std::string::npos)
                return false;
            auto src = openPath(dir);
            if (!src.ok() || !(*src)->start().ok()) return false;
            if (!(*src)->next().ok()) return false;
            auto torn = (*src)->next();
            return !torn.ok() && torn.error().message.find("frame 1") != std::string::npos;
        });
        CHECK(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 0);
    }
    SECTION("a header length past the file is refused too") {
        const std::string dir = writeGrey({0, 40'000'000});
        craftRecord(dir, 1, [](replay::RecordHeader& h) { h.headerBytes = UINT32_MAX; });
        auto r = RecordingReader::open(dir);
        REQUIRE(r.ok());
        CHECK((*r)->frameCount() == 1);
        REQUIRE((*r)->damage());
        CHECK_THAT(*(*r)->damage(),
                   Catch::Contains("frame 1 at byte " + std::to_string(kGreyRecord)));
    }
}

TEST_CASE("a record whose length changes after indexing is refused by read, not allocated") {
    const std::string dir = writeGrey({0, 40'000'000});
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    REQUIRE((*r)->frameCount() == 2);
    craftRecord(dir, 1, [](replay::RecordHeader& h) { h.payloadBytes = UINT64_MAX - 127; });
    const int status = inChild(20, [&] {
        auto f = (*r)->read(1);
        return !f.ok() && f.error().kind == ErrorKind::Corrupt &&
               f.error().message.find("frame 1 at byte " + std::to_string(kGreyRecord)) !=
                   std::string::npos;
    });
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
}

TEST_CASE("extreme timestamps never overflow: saturated or refused naming the option") {
    SECTION("start= seconds across the whole int64 range") {
        const std::string dir =
            writeGrey({INT64_MIN, INT64_MIN + 1'000'000'000'000'000'000, INT64_MAX});
        // Frame 2 lies 2^64 - 1 ns after frame 0, past int64: it is the first at ≥ 5e9 s.
        auto s = openPath(dir + ",start=5e9s");
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        auto f = (*s)->next();
        REQUIRE(f.ok());
        CHECK(f->sequence == 2);
        auto beyond = openPath(dir + ",start=1e300s");
        REQUIRE(!beyond.ok());
        CHECK(beyond.error().kind == ErrorKind::Usage);
    }
    SECTION("loop=1 that would carry timestamps past int64 ends with a message") {
        for (const std::vector<int64_t>& ts :
             {std::vector<int64_t>{0, INT64_MAX}, std::vector<int64_t>{INT64_MIN, INT64_MAX},
              std::vector<int64_t>{INT64_MAX - 10}}) {
            INFO("first timestamp " << ts.front());
            const std::string dir = writeGrey(ts);
            auto s = openPath(dir + ",loop=1");
            REQUIRE(s.ok());
            REQUIRE((*s)->start().ok());
            std::optional<int64_t> last;
            std::optional<Error> failure;
            for (int i = 0; i < 8 && !failure; ++i) {
                auto f = (*s)->next();
                if (!f) {
                    failure = f.error();
                    break;
                }
                if (last) CHECK(f->timestampNs > *last);
                last = f->timestampNs;
            }
            REQUIRE(failure);
            CHECK(failure->kind != ErrorKind::EndOfStream);
            CHECK_THAT(failure->message, Catch::Contains("loop=1") && Catch::Contains(dir));
        }
    }
    SECTION("pace=original refuses a frame further from the first than int64 nanoseconds") {
        const std::string dir = writeGrey({INT64_MIN, INT64_MAX});
        auto s = openPath(dir + ",pace=original");
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        REQUIRE((*s)->next().ok());
        auto f = (*s)->next();
        REQUIRE(!f.ok());
        CHECK(f.error().kind != ErrorKind::EndOfStream);
        CHECK_THAT(f.error().message,
                   Catch::Contains("pace=original") && Catch::Contains("frame 1"));
    }
    SECTION("pace=original with timestamps that run backwards does not wait") {
        const std::string dir = writeGrey({INT64_MAX, INT64_MIN, 0});
        auto s = openPath(dir + ",pace=original");
        REQUIRE(s.ok());
        REQUIRE((*s)->start().ok());
        for (int i = 0; i < 3; ++i)
            REQUIRE((*s)->next().ok());
    }
}

TEST_CASE("copyFrame refuses a frame whose plane has no pixels") {
    Frame f = greyFrame(7, 0);
    f.planes[0].data = nullptr;
    auto c = copyFrame(f);
    REQUIRE(!c.ok());
    CHECK_THAT(c.error().message, Catch::Contains("frame 7") && Catch::Contains("plane 0"));
    Frame m = makeCompressedFrame(PixelFormat::MJPEG, {16, 8}, nullptr, 0);
    m.planes[0] = Plane{nullptr, 0, 100};
    auto cm = copyFrame(m);
    REQUIRE(!cm.ok());
    CHECK_THAT(cm.error().message, Catch::Contains("plane 0"));
    // A whole frame still copies.
    auto ok = copyFrame(greyFrame(1, 0));
    REQUIRE(ok.ok());
}

TEST_CASE("two writers on one new directory: one wins, the other says why") {
    for (int trial = 0; trial < 200; ++trial) {
        const std::string dir = tempDir("race");
        std::barrier sync(2);
        std::optional<std::string> failure[2];
        bool won[2] = {false, false};
        auto run = [&](int who) {
            auto w = RecordingWriter::create(dir, greyHeader("sim:writer=" + std::to_string(who)));
            // Both have tried before either closes, as two recorders running side by side.
            sync.arrive_and_wait();
            if (!w) {
                failure[who] = w.error().message;
                return;
            }
            won[who] = (*w)->append(greyFrame(static_cast<uint64_t>(who), 0)).ok();
        };
        std::thread a(run, 0), b(run, 1);
        a.join();
        b.join();
        INFO("trial " << trial);
        REQUIRE(won[0] != won[1]);
        const int winner = won[0] ? 0 : 1;
        REQUIRE(failure[1 - winner]);
        CHECK_THAT(
            *failure[1 - winner],
            Catch::Contains("another recording is being written there") && Catch::Contains(dir));
        auto r = RecordingReader::open(dir);
        REQUIRE(r.ok());
        REQUIRE((*r)->header().sourceString == "sim:writer=" + std::to_string(winner));
        REQUIRE((*r)->frameCount() == 1);
        auto f = (*r)->read(0);
        REQUIRE(f.ok());
        REQUIRE(f->sequence == static_cast<uint64_t>(winner));
    }
}

TEST_CASE("a write cut by a full disk is truncated back to the last whole frame") {
    // The file size limit stands in for a full disk (EFBIG, as ENOSPC), part-way through the
    // fourth record; the child process keeps the limit away from the rest of the test.
    const std::string dir = tempDir("full");
    const int status = inChild(20, [&] {
        auto w = RecordingWriter::create(dir, greyHeader("sim:"));
        if (!w) return false;
        std::signal(SIGXFSZ, SIG_IGN);
        rlimit small{3 * kGreyRecord + 50, RLIM_INFINITY};
        if (::setrlimit(RLIMIT_FSIZE, &small) != 0) return false;
        int appended = 0;
        for (int i = 0; i < 6; ++i)
            if ((*w)->append(greyFrame(static_cast<uint64_t>(i), i * 40'000'000LL)).ok())
                ++appended;
        return appended == 3 && (*w)->frames() == 3 && (*w)->close().ok();
    });
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    struct stat st;
    REQUIRE(::stat((dir + "/frames.bin").c_str(), &st) == 0);
    CHECK(static_cast<uint64_t>(st.st_size) == 3 * kGreyRecord);
    auto r = RecordingReader::open(dir);
    REQUIRE(r.ok());
    CHECK((*r)->frameCount() == 3);
    CHECK(!(*r)->damage());
    auto src = openPath(dir);
    REQUIRE(src.ok());
    REQUIRE((*src)->start().ok());
    for (int i = 0; i < 3; ++i)
        REQUIRE((*src)->next().ok());
    CHECK((*src)->next().error().kind == ErrorKind::EndOfStream);
}

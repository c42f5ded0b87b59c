// SPDX-License-Identifier: MIT
// Recording writer and reader (format in recording_format.h).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <dirent.h>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <fstream>
#include <optional>
#include <sstream>

#include "infocus/recording.h"
#include "infocus_config.h"
#include "replay/recording_format.h"
#include "src/core/read_number.h"

namespace infocus {

using replay::RecordHeader;

namespace {

std::string errnoText(int e) {
    return std::strerror(e);
}

bool isDirectory(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool directoryIsEmpty(const std::string& path) {
    DIR* d = ::opendir(path.c_str());
    if (!d) return false;
    bool empty = true;
    while (dirent* e = ::readdir(d)) {
        if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) {
            empty = false;
            break;
        }
    }
    ::closedir(d);
    return empty;
}

// Whether a writer holds the lock on the frame file in @p dir: a recording is being written.
bool beingWritten(const std::string& dir) {
    const std::string path = dir + "/" + replay::kFramesFileName;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool locked = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
    ::close(fd);
    return locked;
}

// Creates @p path exclusively, locked (flock) before it appears, so that a second writer that
// sees the file also sees it locked. Returns the descriptor, or -errno (-EEXIST when another
// writer made it first).
int claimFramesFile(const std::string& dir, const std::string& path) {
    // An unnamed file, locked, then linked into place: linkat() fails if the name exists.
    const int tmp = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (tmp >= 0) {
        ::flock(tmp, LOCK_EX);
        const std::string self = "/proc/self/fd/" + std::to_string(tmp);
        if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, path.c_str(), AT_SYMLINK_FOLLOW) == 0 &&
            ::fcntl(tmp, F_SETFL, O_APPEND) == 0)
            return tmp;
        const int e = errno;
        ::close(tmp);
        if (e == EEXIST) return -e;
    }
    // No O_TMPFILE here (or no /proc): O_EXCL still decides the winner, with a moment before
    // the lock in which the file is visible unlocked.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0666);
    if (fd < 0) return -errno;
    ::flock(fd, LOCK_EX);
    return fd;
}

// Writes all of @p size bytes, retrying after signals and short writes.
bool writeAll(int fd, const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return false;
        }
        p += n;
        size -= static_cast<size_t>(n);
    }
    return true;
}

// Reads up to @p size bytes at @p offset; returns the count read (short at end of file) or -1.
ssize_t readAt(int fd, void* data, size_t size, uint64_t offset) {
    auto* p = static_cast<uint8_t*>(data);
    size_t done = 0;
    while (done < size) {
        const ssize_t n = ::pread(fd, p + done, size - done, static_cast<off_t>(offset + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        if (n == 0) break;
        done += static_cast<size_t>(n);
    }
    return static_cast<ssize_t>(done);
}

uint32_t headerCrc(const RecordHeader& h) {
    return replay::crc32(&h, offsetof(RecordHeader, headerCrc));
}

// The most pixel data one record can hold: three planes of up to 4 GiB each.
constexpr uint64_t kMaxPayloadBytes = 3ull * UINT32_MAX;

// Whether the record with header @p h fits in the @p left bytes from its start to the end of
// the file; no addition, so lengths near 2^64 cannot wrap.
bool recordFits(const RecordHeader& h, uint64_t left) {
    return h.headerBytes <= left && h.payloadBytes <= left - h.headerBytes;
}

nlohmann::ordered_json headerToJson(const RecordingHeader& h) {
    nlohmann::ordered_json j;
    j["format"] = "infocus-recording";
    j["format_version"] = replay::kRecordingFormatVersion;
    j["infocus_version"] = INFOCUS_VERSION;
    j["source"] = h.sourceString;
    j["device"] = h.device;
    j["driver"] = h.driver;
    j["pixel_format"] = pixelFormatName(h.format);
    j["width_px"] = h.size.width;
    j["height_px"] = h.size.height;
    j["fps"] = h.fps;
    j["created_unix_s"] = h.createdUnixS;
    if (h.focus) {
        j["focus_control"] = {{"min", h.focus->min},
                              {"max", h.focus->max},
                              {"step", h.focus->step},
                              {"default", h.focus->defaultValue},
                              {"unit", h.focus->unit}};
    } else {
        j["focus_control"] = nullptr;
    }
    if (h.transfer.curve)
        j["transfer"] = transferFunctionName(*h.transfer.curve);
    else
        j["transfer"] = nullptr;
    j["transfer_origin"] = h.transfer.origin;
    j["frames_file"] = replay::kFramesFileName;
    return j;
}

Result<RecordingHeader> headerFromJson(const std::string& path, const std::string& text) {
    const auto bad = [&](const std::string& why) -> Error {
        return makeError(ErrorKind::Corrupt,
                         "recording header " + path + ": " + why +
                             "; the recording is damaged or not an infocus recording");
    };
    nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return bad("not valid JSON");
    // The field being read: nlohmann's type errors do not name it, and the user needs to know
    // which one is damaged.
    std::string field;
    // An integer field within [lo, hi] (jsonInteger), the field noted first.
    const auto integer = [&](const nlohmann::json& o, const char* key, int64_t lo,
                             int64_t hi) -> std::optional<int64_t> {
        field = key;
        return jsonInteger(o.at(key), lo, hi);
    };
    RecordingHeader h;
    try {
        field = "format";
        if (j.value("format", std::string()) != "infocus-recording")
            return bad("missing \"format\": \"infocus-recording\"");
        field = "infocus_version";
        h.infocusVersion = j.value("infocus_version", std::string("unknown"));
        field = "format_version";
        if (!j.contains("format_version")) return bad("missing integer \"format_version\"");
        const auto version = integer(j, "format_version", 1, INT64_MAX);
        if (!version) return bad("\"format_version\" must be a whole number from 1 up");
        if (*version > replay::kRecordingFormatVersion)
            return makeError(ErrorKind::Unsupported,
                             "recording " + path + " uses format version " +
                                 std::to_string(*version) + " (written by infocus " +
                                 h.infocusVersion +
                                 "); this infocus (" INFOCUS_VERSION ") reads up to version " +
                                 std::to_string(replay::kRecordingFormatVersion) +
                                 ": use a newer infocus to replay it");
        h.formatVersion = static_cast<int>(*version);
        field = "source";
        h.sourceString = j.value("source", std::string());
        field = "device";
        h.device = j.value("device", std::string());
        field = "driver";
        h.driver = j.value("driver", std::string());
        field = "pixel_format";
        auto fmt = parsePixelFormat(j.at("pixel_format").get<std::string>());
        if (!fmt) return bad("unknown pixel_format");
        h.format = *fmt;
        const auto w = integer(j, "width_px", 1, INT32_MAX);
        const auto ht = w ? integer(j, "height_px", 1, INT32_MAX) : std::nullopt;
        if (!w || !ht) return bad("\"" + field + "\" must be a whole number from 1 up");
        if (!withinFrameLimit(*w, *ht))
            return bad("\"width_px\" x \"height_px\", " + std::to_string(*w) + "x" +
                       std::to_string(*ht) + ", is more than the " + maxFrameSizeText() +
                       " pixels a frame may hold");
        h.size = {static_cast<int>(*w), static_cast<int>(*ht)};
        field = "fps";
        h.fps = j.value("fps", 0.0);
        if (j.contains("created_unix_s")) {
            const auto created = integer(j, "created_unix_s", INT64_MIN, INT64_MAX);
            if (!created) return bad("\"created_unix_s\" must be a whole number of seconds");
            h.createdUnixS = *created;
        }
        field = "focus_control";
        if (j.contains("focus_control") && j["focus_control"].is_object()) {
            const auto& f = j["focus_control"];
            FocusRange r;
            r.min = f.at("min").get<double>();
            r.max = f.at("max").get<double>();
            r.step = f.at("step").get<double>();
            r.defaultValue = f.at("default").get<double>();
            r.unit = f.at("unit").get<std::string>();
            h.focus = r;
        }
        // Absent from recordings made before infocus read transfer functions: unknown.
        field = "transfer";
        if (j.contains("transfer") && !j["transfer"].is_null()) {
            const std::string name = j["transfer"].get<std::string>();
            h.transfer.curve = transferFunctionFromName(name);
            if (!h.transfer.curve)
                return bad("\"transfer\" is '" + name +
                           "'; it must be linear, srgb, rec709 or null");
        }
        field = "transfer_origin";
        h.transfer.origin = j.value("transfer_origin", std::string());
    } catch (const nlohmann::json::exception& e) {
        return bad("\"" + field + "\" missing or of the wrong type (" + e.what() + ")");
    }
    return h;
}

}  // namespace

RecordingHeader makeRecordingHeader(const SourceInfo& info, const FocusControl* focus) {
    RecordingHeader h;
    h.formatVersion = replay::kRecordingFormatVersion;
    h.infocusVersion = INFOCUS_VERSION;
    h.sourceString = info.sourceString;
    h.device = info.device;
    h.driver = info.driver;
    h.format = info.format;
    h.size = info.size;
    h.fps = info.fps;
    if (focus) h.focus = focus->range();
    h.transfer = info.transfer;
    h.createdUnixS = static_cast<int64_t>(std::time(nullptr));
    return h;
}

// ---------------------------------------------------------------------------------------------
// Writer

Result<std::unique_ptr<RecordingWriter>> RecordingWriter::create(const std::string& dir,
                                                                 const RecordingHeader& header) {
    const auto another = [&](int e) {
        return makeError(ErrorKind::Io,
                         "output directory " + dir +
                             ": another recording is being written there; wait for it to end "
                             "or choose another directory",
                         e);
    };
    // mkdir() first, not a stat() before it: two recorders that both saw no directory would
    // otherwise both go on. The frame file below is the claim that decides between them.
    if (::mkdir(dir.c_str(), 0777) != 0) {
        const int e = errno;
        if (e != EEXIST)
            return makeError(ErrorKind::Io,
                             "cannot create recording directory " + dir + ": " + errnoText(e) +
                                 "; check that the parent directory exists and is writable",
                             e);
        // A file of that name (often a mistyped -o): say so, rather than blame the parent.
        if (!isDirectory(dir))
            return makeError(ErrorKind::Usage, "output " + dir +
                                                   " exists and is not a directory; give a new "
                                                   "or empty directory for the recording");
        if (!directoryIsEmpty(dir)) {
            if (beingWritten(dir)) return another(EBUSY);
            return makeError(ErrorKind::Usage, "output directory " + dir +
                                                   " is not empty; choose a new directory or "
                                                   "remove the old recording first");
        }
    }
    // The frame file is claimed before the header is written, so only the winner writes one.
    const std::string framesPath = dir + "/" + replay::kFramesFileName;
    const int fd = claimFramesFile(dir, framesPath);
    if (fd == -EEXIST) return another(EEXIST);
    if (fd < 0)
        return makeError(ErrorKind::Io, "cannot create " + framesPath + ": " + errnoText(-fd), -fd);
    // The header goes through a temporary file and rename() so it is never half written.
    const std::string headerPath = dir + "/" + replay::kHeaderFileName;
    const std::string tmpPath = headerPath + ".tmp";
    {
        const std::string text = headerToJson(header).dump(2) + "\n";
        const int fd = ::open(tmpPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        const int hfd = ::open(tmpPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        if (hfd < 0 || !writeAll(hfd, text.data(), text.size()) || ::fsync(hfd) != 0) {
            const int e = errno;
            if (hfd >= 0) ::close(hfd);
            ::close(fd);
            return makeError(ErrorKind::Io, "cannot write " + tmpPath + ": " + errnoText(e), e);
        }
        ::close(hfd);
        if (::rename(tmpPath.c_str(), headerPath.c_str()) != 0) {
            const int e = errno;
            ::close(fd);
            return makeError(ErrorKind::Io, "cannot rename " + tmpPath + ": " + errnoText(e), e);
        }
    }
    return std::unique_ptr<RecordingWriter>(new RecordingWriter(framesPath, fd));
}

RecordingWriter::~RecordingWriter() {
    (void)close();
}

Status RecordingWriter::append(const Frame& frame) {
    if (fd_ < 0)
        return makeError(ErrorKind::Usage, "recording " + path_ + " is closed; cannot append");
    if (frame.numPlanes < 1 || frame.numPlanes > 3)
        return makeError(ErrorKind::Usage, "frame " + std::to_string(frame.sequence) + " has " +
                                               std::to_string(frame.numPlanes) +
                                               " planes; a recorded frame needs 1 to 3");
    RecordHeader h{};
    h.magic = replay::kRecordMagic;
    h.headerBytes = sizeof(RecordHeader);
    h.sequence = frame.sequence;
    h.timestampNs = frame.timestampNs;
    h.pixelFormat = static_cast<uint32_t>(frame.format);
    h.width = frame.size.width;
    h.height = frame.size.height;
    h.numPlanes = frame.numPlanes;
    uint32_t crc = 0;
    iovec iov[4];
    iov[0] = {&h, sizeof h};
    for (unsigned i = 0; i < frame.numPlanes; ++i) {
        const Plane& p = frame.planes[i];
        if (p.size > UINT32_MAX)
            return makeError(ErrorKind::Usage, "frame plane of " + std::to_string(p.size) +
                                                   " bytes is too large to record (max 4 GiB)");
        h.stride[i] = static_cast<uint32_t>(p.stride);
        h.planeBytes[i] = static_cast<uint32_t>(p.size);
        h.payloadBytes += p.size;
        crc = replay::crc32(p.data, p.size, crc);
        iov[i + 1] = {const_cast<uint8_t*>(p.data), p.size};
    }
    h.payloadCrc = crc;
    if (lastSequence_ && frame.sequence != *lastSequence_ + 1)
        h.flags |= replay::kFlagDroppedBefore;
    if (frame.lens) {
        h.flags |= replay::kFlagHasLens;
        h.lensValue = frame.lens->value;
        std::strncpy(h.lensUnit, frame.lens->unit.c_str(), sizeof h.lensUnit - 1);
        if (frame.lens->dioptres) {
            h.flags |= replay::kFlagHasLensDioptres;
            h.lensDioptres = *frame.lens->dioptres;
        }
    }
    if (frame.exposureS) {
        h.flags |= replay::kFlagHasExposure;
        h.exposureS = *frame.exposureS;
    }
    h.headerCrc = headerCrc(h);

    // One writev() for the whole record: a kill leaves either the record or a torn tail that the
    // reader detects by length and CRC. Short writes (rare, e.g. a signal) are finished by hand.
    size_t total = sizeof h + h.payloadBytes;
    ssize_t n;
    do {
        n = ::writev(fd_, iov, static_cast<int>(frame.numPlanes + 1));
    } while (n < 0 && errno == EINTR);
    // Said alike whether the first write or a later part of it fails (a disk that fills up
    // part-way through a frame): what is kept, and what to do.
    // The torn part of the record is cut off again, so that the file ends with its last whole
    // frame and replays cleanly rather than reporting damage every time.
    const auto failed = [&](int e) {
        std::string kept = "; the " + std::to_string(frames_) + " frames before it are kept";
        if (::ftruncate(fd_, static_cast<off_t>(bytes_)) == 0)
            kept += " and replay";
        else
            kept += " (its torn part could not be removed: " + errnoText(errno) +
                    "; replay reports it)";
        return makeError(ErrorKind::Io,
                         "cannot write frame " + std::to_string(frames_) + " to " + path_ + ": " +
                             errnoText(e) + kept + "; free disk space or record to another disk",
                         e);
    };
    if (n < 0) return failed(errno);
    size_t written = static_cast<size_t>(n);
    for (unsigned i = 0; i < frame.numPlanes + 1 && written < total; ++i) {
        size_t skip = written;
        size_t before = 0;
        for (unsigned k = 0; k < i; ++k)
            before += iov[k].iov_len;
        if (skip >= before + iov[i].iov_len) continue;
        skip -= before;
        if (!writeAll(fd_, static_cast<uint8_t*>(iov[i].iov_base) + skip, iov[i].iov_len - skip))
            return failed(errno);
        written += iov[i].iov_len - skip;
    }
    if (h.flags & replay::kFlagDroppedBefore) ++dropped_;
    lastSequence_ = frame.sequence;
    ++frames_;
    bytes_ += total;
    return {};
}

Status RecordingWriter::flush() {
    if (fd_ >= 0 && ::fdatasync(fd_) != 0) {
        const int e = errno;
        return makeError(ErrorKind::Io, "cannot flush " + path_ + ": " + errnoText(e), e);
    }
    return {};
}

Status RecordingWriter::close() {
    if (fd_ < 0) return {};
    Status s = flush();
    ::close(fd_);
    fd_ = -1;
    return s;
}

// ---------------------------------------------------------------------------------------------
// Reader

RecordingReader::~RecordingReader() {
    if (fd_ >= 0) ::close(fd_);
}

Result<std::unique_ptr<RecordingReader>> RecordingReader::open(const std::string& dir) {
    if (!isDirectory(dir))
        return makeError(ErrorKind::NotFound, "recording " + dir +
                                                  " does not exist or is not a directory; give the "
                                                  "directory written by 'infocus record'");
    const std::string headerPath = dir + "/" + replay::kHeaderFileName;
    std::ifstream in(headerPath);
    if (!in)
        return makeError(ErrorKind::NotFound, "recording " + dir + " has no " +
                                                  replay::kHeaderFileName +
                                                  "; it is not an infocus recording or its "
                                                  "recording never started");
    std::stringstream ss;
    ss << in.rdbuf();
    auto header = headerFromJson(headerPath, ss.str());
    if (!header) return header.error();

    std::unique_ptr<RecordingReader> r(new RecordingReader);
    r->header_ = std::move(*header);
    r->path_ = dir + "/" + replay::kFramesFileName;
    r->fd_ = ::open(r->path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (r->fd_ < 0) {
        const int e = errno;
        return makeError(e == ENOENT ? ErrorKind::NotFound : ErrorKind::Io,
                         "cannot open " + r->path_ + ": " + errnoText(e), e);
    }
    struct stat st;
    if (::fstat(r->fd_, &st) != 0) {
        const int e = errno;
        return makeError(ErrorKind::Io, "cannot stat " + r->path_ + ": " + errnoText(e), e);
    }
    const auto fileSize = static_cast<uint64_t>(st.st_size);
    r->fileSize_ = fileSize;

    // Walk the record headers; payloads are checked when read, so opening stays fast.
    uint64_t offset = 0;
    while (offset < fileSize) {
        const std::string where = r->path_ + ": frame " + std::to_string(r->index_.size()) +
                                  " at byte " + std::to_string(offset);
        RecordHeader h;
        const ssize_t n = readAt(r->fd_, &h, sizeof h, offset);
        if (n < 0) {
            const int e = errno;
            return makeError(ErrorKind::Io, "cannot read " + where + ": " + errnoText(e), e);
        }
        if (static_cast<size_t>(n) < sizeof h) {
            r->damage_ = where + " is incomplete (" + std::to_string(n) + " of " +
                         std::to_string(sizeof h) +
                         " header bytes; the recording was interrupted); the frames before it "
                         "are intact";
            break;
        }
        if (h.magic != replay::kRecordMagic || h.headerBytes < sizeof h ||
            headerCrc(h) != h.headerCrc) {
            r->damage_ = where +
                         " has a damaged record header (bad magic or CRC); the frames after it "
                         "cannot be located, the frames before it are intact";
            break;
        }
        // Lengths are compared with what is left of the file before they are added: a crafted
        // length near 2^64 would wrap the sum back into the file.
        if (!recordFits(h, fileSize - offset)) {
            if (h.payloadBytes > kMaxPayloadBytes)
                r->damage_ = where + " claims " + std::to_string(h.payloadBytes) +
                             " bytes of pixel data, more than a record holds (3 planes of at "
                             "most 4 GiB); its header is damaged, the frames before it are intact";
            else
                r->damage_ = where + " is incomplete (" + std::to_string(fileSize - offset) +
                             " of " + std::to_string(h.headerBytes + h.payloadBytes) +
                             " bytes; the recording was interrupted); the frames before it are "
                             "intact";
            break;
        }
        const uint64_t end = offset + h.headerBytes + h.payloadBytes;
        RecordedFrameInfo info;
        info.sequence = h.sequence;
        info.timestampNs = h.timestampNs;
        info.droppedBefore = (h.flags & replay::kFlagDroppedBefore) != 0;
        info.offset = offset;
        info.payloadBytes = h.payloadBytes;
        r->index_.push_back(info);
        offset = end;
    }
    return r;
}

Result<Frame> RecordingReader::read(size_t i) const {
    if (i >= index_.size())
        return makeError(ErrorKind::Usage, "frame " + std::to_string(i) + " is beyond the " +
                                               std::to_string(index_.size()) + " frames of " +
                                               path_);
    const RecordedFrameInfo& info = index_[i];
    const std::string where =
        path_ + ": frame " + std::to_string(i) + " at byte " + std::to_string(info.offset);
    RecordHeader h;
    if (readAt(fd_, &h, sizeof h, info.offset) != static_cast<ssize_t>(sizeof h)) {
        const int e = errno;
        return makeError(ErrorKind::Io, "cannot read " + where + ": " + errnoText(e), e);
    }
    // The file may have changed since it was indexed: its lengths are checked again before they
    // size an allocation.
    if (h.magic != replay::kRecordMagic || headerCrc(h) != h.headerCrc ||
        h.headerBytes < sizeof h || h.payloadBytes != info.payloadBytes ||
        info.offset > fileSize_ || !recordFits(h, fileSize_ - info.offset))
        return makeError(ErrorKind::Corrupt,
                         where +
                             " has a record header that no longer matches the file (changed "
                             "since it was opened, or damaged); it is skipped");
    // The buffer is left uninitialised: every byte is overwritten by the read.
    std::shared_ptr<uint8_t[]> buffer(new uint8_t[h.payloadBytes > 0 ? h.payloadBytes : 1]);
    if (readAt(fd_, buffer.get(), h.payloadBytes, info.offset + h.headerBytes) !=
        static_cast<ssize_t>(h.payloadBytes)) {
        const int e = errno;
        return makeError(ErrorKind::Io, "cannot read " + where + ": " + errnoText(e), e);
    }
    if (replay::crc32(buffer.get(), h.payloadBytes) != h.payloadCrc)
        return makeError(ErrorKind::Corrupt,
                         where + " is corrupt (pixel data fails its CRC); it is skipped");
    uint64_t sum = 0;
    for (unsigned p = 0; p < h.numPlanes && p < 3; ++p)
        sum += h.planeBytes[p];
    if (h.numPlanes < 1 || h.numPlanes > 3 || sum != h.payloadBytes)
        return makeError(ErrorKind::Corrupt,
                         where + " has an inconsistent plane layout; it is skipped");

    Frame f;
    f.format = static_cast<PixelFormat>(h.pixelFormat);
    f.size = {h.width, h.height};
    f.numPlanes = h.numPlanes;
    size_t offset = 0;
    for (unsigned p = 0; p < h.numPlanes; ++p) {
        f.planes[p] = Plane{buffer.get() + offset, h.stride[p], h.planeBytes[p]};
        offset += h.planeBytes[p];
    }
    f.timestampNs = h.timestampNs;
    f.sequence = h.sequence;
    if (h.flags & replay::kFlagHasLens) {
        LensPosition lens;
        lens.value = h.lensValue;
        lens.unit.assign(h.lensUnit, strnlen(h.lensUnit, sizeof h.lensUnit));
        if (h.flags & replay::kFlagHasLensDioptres) lens.dioptres = h.lensDioptres;
        f.lens = lens;
    }
    if (h.flags & replay::kFlagHasExposure) f.exposureS = h.exposureS;
    f.storage = std::move(buffer);
    return f;
}

}  // namespace infocus

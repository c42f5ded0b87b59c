// SPDX-License-Identifier: MIT
// The path source: which reader a path is for (a recording directory, a Y4M file, image files,
// a directory or glob of them, or a video file), and recordings as a reader.
#include <fcntl.h>
#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "infocus/recording.h"
#include "replay/bracket.h"
#include "replay/decoders/decoders.h"
#include "replay/file_readers.h"
#include "replay/recording_format.h"
#include "replay/replay_sources.h"

namespace infocus::replay {

namespace {

class RecordingFrameReader final : public FrameReader {
public:
    RecordingFrameReader(std::unique_ptr<RecordingReader> r, std::string text)
        : r_(std::move(r)), text_(std::move(text)) {}

    SourceInfo info() const override {
        const RecordingHeader& h = r_->header();
        SourceInfo i;
        i.sourceString = text_;
        i.device = h.device.empty() ? h.sourceString : h.device;
        i.driver = "replay";
        i.format = h.format;
        i.size = h.size;
        i.fps = h.fps;
        i.frameCount = static_cast<int64_t>(r_->frameCount());
        i.transfer.curve = h.transfer.curve;
        i.transfer.origin = h.transfer.origin.empty()
                                ? "the recording's header names no transfer function"
                                : "the recording's header: " + h.transfer.origin;
        return i;
    }
    size_t count() const override { return r_->frameCount(); }
    int64_t timestampNs(size_t i) const override { return r_->frameInfo(i).timestampNs; }
    Result<Frame> read(size_t i) override { return r_->read(i); }
    std::optional<Error> trailingError() const override {
        if (!r_->damage()) return std::nullopt;
        return makeError(ErrorKind::Corrupt, *r_->damage());
    }

private:
    std::unique_ptr<RecordingReader> r_;
    std::string text_;
};

bool isDirectory(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool exists(const std::string& path) {
    struct stat st;
    return ::stat(path.c_str(), &st) == 0;
}

// Why @p file is there but cannot be read (no permission, a link to a missing file), or
// nothing when it reads or is not there at all: a recording's header that cannot be read is
// not a recording without one.
std::optional<Error> unreadable(const std::string& file) {
    const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
        ::close(fd);
        return std::nullopt;
    }
    const int e = errno;
    struct stat st;
    if (e == ENOENT && ::lstat(file.c_str(), &st) == 0)
        return makeError(ErrorKind::Io, "cannot read " + file +
                                            ": it is a link to a missing file; restore the file "
                                            "it points to");
    if (e == ENOENT) return std::nullopt;
    return makeError(ErrorKind::Io,
                     "cannot read " + file + ": " + std::strerror(e) + "; check its permissions");
}

// The frames of a bracket: a recording, a directory of images or a glob of them.
Result<std::unique_ptr<FrameSource>> openBracketPath(const SourceSpec& spec,
                                                     const std::string& path) {
    std::unique_ptr<FrameReader> reader;
    if (isDirectory(path)) {
        if (auto e = unreadable(path + "/" + kHeaderFileName)) return *e;
        if (exists(path + "/" + kHeaderFileName)) {
            auto r = RecordingReader::open(path);
            if (!r) return r.error();
            reader = std::make_unique<RecordingFrameReader>(std::move(*r), spec.text);
        } else {
            auto files = imagesInDirectory(path);
            if (files.empty())
                return makeError(ErrorKind::NotFound,
                                 "source '" + spec.text + "': directory " + path +
                                     " holds neither a recording nor images to bracket");
            auto r = openImageReader(spec, std::move(files), 30.0);
            if (!r) return r.error();
            reader = std::move(*r);
        }
    } else if (!exists(path) && path.find_first_of("*?[") != std::string::npos) {
        glob_t g{};
        std::vector<std::string> files;
        if (::glob(path.c_str(), 0, nullptr, &g) == 0)
            for (size_t i = 0; i < g.gl_pathc; ++i)
                if (!isDirectory(g.gl_pathv[i])) files.emplace_back(g.gl_pathv[i]);
        ::globfree(&g);
        if (files.empty())
            return makeError(ErrorKind::NotFound,
                             "no file matches the pattern '" + path + "'; check the path");
        std::sort(files.begin(), files.end());
        auto r = openImageReader(spec, std::move(files), 30.0);
        if (!r) return r.error();
        reader = std::move(*r);
    } else {
        return makeError(exists(path) ? ErrorKind::Usage : ErrorKind::NotFound,
                         "source '" + spec.text + "': " + path +
                             (exists(path) ? " is a single file" : " does not exist") +
                             "; a bracket is a directory or glob of images, or a recording");
    }
    return openBracket(spec, std::move(reader));
}

}  // namespace

Result<std::unique_ptr<FrameSource>> openPathSource(const SourceSpec& spec) {
    std::string path = spec.target;
    while (path.size() > 1 && path.back() == '/')
        path.pop_back();
    if (spec.options.count("bracket")) return openBracketPath(spec, path);

    if (isDirectory(path)) {
        if (::access(path.c_str(), R_OK | X_OK) != 0)
            return makeError(ErrorKind::Io, "cannot read directory " + path + ": " +
                                                std::strerror(errno) + "; check its permissions");
        if (auto e = unreadable(path + "/" + kHeaderFileName)) return *e;
        if (exists(path + "/" + kHeaderFileName)) {
            auto options = parsePlaybackOptions(spec);
            if (!options) return options.error();
            auto reader = RecordingReader::open(path);
            if (!reader) return reader.error();
            return makePlayback(
                std::make_unique<RecordingFrameReader>(std::move(*reader), spec.text), *options);
        }
        auto files = imagesInDirectory(path);
        if (files.empty()) {
            if (exists(path + "/" + kFramesFileName))
                return makeError(ErrorKind::Corrupt,
                                 "recording " + path + " has " + kFramesFileName + " but no " +
                                     kHeaderFileName + "; the recording is damaged");
            return makeError(ErrorKind::NotFound,
                             "directory " + path +
                                 " holds neither a recording (header.json) nor images (.jpg, "
                                 ".png, .tif, .bmp, .pgm, ...)");
        }
        return openImages(spec, std::move(files));
    }
    if (!exists(path)) {
        if (path.find_first_of("*?[") != std::string::npos) {
            glob_t g{};
            std::vector<std::string> files;
            if (::glob(path.c_str(), 0, nullptr, &g) == 0)
                for (size_t i = 0; i < g.gl_pathc; ++i)
                    if (!isDirectory(g.gl_pathv[i])) files.emplace_back(g.gl_pathv[i]);
            ::globfree(&g);
            if (files.empty())
                return makeError(ErrorKind::NotFound,
                                 "no file matches the pattern '" + path + "'; check the path");
            std::sort(files.begin(), files.end());
            return openImages(spec, std::move(files));
        }
        return makeError(ErrorKind::NotFound,
                         "source '" + spec.text + "': " + path +
                             " does not exist; give an existing recording, video, image, "
                             "directory or glob, or a camera (v4l2:, libcamera:, sim:)");
    }
    // A FIFO would block open() until a writer comes, a device would be read without end:
    // every file source reads a file it can measure and seek.
    if (struct stat st; ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
        return makeError(ErrorKind::Unsupported,
                         "cannot read " + path + ": it is " +
                             (S_ISFIFO(st.st_mode)   ? "a FIFO (named pipe)"
                              : S_ISCHR(st.st_mode)  ? "a character device"
                              : S_ISBLK(st.st_mode)  ? "a block device"
                              : S_ISSOCK(st.st_mode) ? "a socket"
                                                     : "not a regular file") +
                             "; give a recording, Y4M, image or video file");
    const std::string ext = extension(path);
    if (ext == "y4m") {
        auto options = parsePlaybackOptions(spec);
        if (!options) return options.error();
        auto reader = openY4mReader(path, spec.text);
        if (!reader) return reader.error();
        return makePlayback(std::move(*reader), *options);
    }
    if (isImageExtension(ext)) return openImages(spec, {path});
    auto options = parsePlaybackOptions(spec);
    if (!options) return options.error();
    auto decoders = loadDecoders("cannot open " + path + ": reading video files");
    if (!decoders) return decoders.error();
    auto reader = (*decoders)->openVideo(path, spec.text);
    if (!reader) return reader.error();
    return makePlayback(std::move(*reader), *options);
}

}  // namespace infocus::replay

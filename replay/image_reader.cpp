// SPDX-License-Identifier: MIT
// Image files, alone or in sequence (a directory or a glob): JPEG files are delivered as MJPEG
// frames holding the file's bytes (so the luma path decodes luma only); other formats through
// the decoder module (OpenCV's imgcodecs) as GREY or, for 16-bit files, Y16.
#include <turbojpeg.h>

#include <dirent.h>
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>

#include "replay/decoders/decoders.h"
#include "replay/file_readers.h"

namespace infocus::replay {

namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

Result<std::vector<uint8_t>> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in)
        return makeError(ErrorKind::NotFound,
                         "cannot open image " + path + ": " + std::strerror(errno));
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
    return bytes;
}

Result<Frame> loadImage(const std::string& path) {
    // A file that cannot be decoded: @p what is wrong with it, and what to do.
    const auto damaged = [&](const std::string& what) {
        return makeError(ErrorKind::Corrupt,
                         "image " + path + " " + what + "; copy or export it again");
    };
    auto bytes = readFile(path);
    if (!bytes) return bytes.error();
    if (bytes->empty()) return damaged("is empty (0 bytes)");
    const bool jpeg = bytes->size() > 3 && (*bytes)[0] == 0xFF && (*bytes)[1] == 0xD8;
    if (jpeg) {
        tjhandle tj = tjInitDecompress();
        int w = 0, h = 0, subsamp = 0, colorspace = 0;
        const int rc =
            tjDecompressHeader3(tj, bytes->data(), bytes->size(), &w, &h, &subsamp, &colorspace);
        const std::string why = rc != 0 ? tjGetErrorStr2(tj) : "";
        tjDestroy(tj);
        if (rc != 0) return damaged("is not a readable JPEG (" + why + ")");
        // A file cut inside its header may still parse without a frame size.
        if (w <= 0 || h <= 0) return damaged("is a JPEG cut short before its frame size");
        if (!withinFrameLimit(w, h))
            return damaged("claims " + std::to_string(w) + "x" + std::to_string(h) +
                           " pixels, more than the " + maxFrameSizeText() + " a frame may hold");
        Frame f = makeCompressedFrame(PixelFormat::MJPEG, {w, h}, bytes->data(), bytes->size());
        f.origin = path;
        return f;
    }
    auto decoders = loadDecoders("cannot open image " + path + ": decoding images other than JPEG");
    if (!decoders) return decoders.error();
    return (*decoders)->decodeImage(*bytes, path);
}

class ImageListReader final : public FrameReader {
public:
    ImageListReader(std::vector<std::string> files, std::string text, std::string device,
                    double fps, Frame first)
        : files_(std::move(files)),
          text_(std::move(text)),
          device_(std::move(device)),
          fps_(fps),
          first_(std::move(first)) {}

    SourceInfo info() const override {
        SourceInfo i;
        i.sourceString = text_;
        i.device = device_;
        i.driver = "images";
        i.format = first_.format;
        i.size = first_.size;
        i.fps = fps_;
        i.frameCount = static_cast<int64_t>(files_.size());
        // Viewers take an image without a colour profile as sRGB, and cameras write them so;
        // 16-bit files come from raw converters as often linear as encoded.
        if (first_.format == PixelFormat::Y16) {
            i.transfer.origin =
                "a 16-bit image file may hold linear or encoded levels, and "
                "infocus reads no colour profile";
        } else {
            i.transfer.curve = TransferFunction::Srgb;
            i.transfer.origin =
                "image files are sRGB unless a colour profile says otherwise, "
                "and infocus reads none";
        }
        return i;
    }
    size_t count() const override { return files_.size(); }
    int64_t timestampNs(size_t i) const override { return frameTimeNs(i, fps_); }
    Result<Frame> read(size_t i) override {
        auto f = i == 0 && first_.numPlanes ? Result<Frame>(first_) : loadImage(files_[i]);
        if (!f) return f.error();
        f->sequence = i;
        f->timestampNs = timestampNs(i);
        return f;
    }

private:
    std::vector<std::string> files_;
    std::string text_, device_;
    double fps_;
    Frame first_;
};

}  // namespace

std::string extension(const std::string& path) {
    const size_t slash = path.rfind('/');
    const size_t dot = path.rfind('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    return lower(path.substr(dot + 1));
}

bool isImageExtension(const std::string& ext) {
    static const std::set<std::string> kExts = {"jpg", "jpeg", "png", "tif", "tiff", "bmp",
                                                "pgm", "ppm",  "pnm", "pbm", "webp"};
    return kExts.count(ext) > 0;
}

std::vector<std::string> imagesInDirectory(const std::string& dir) {
    std::vector<std::string> out;
    DIR* d = ::opendir(dir.c_str());
    if (!d) return out;
    while (dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        if (name[0] != '.' && isImageExtension(extension(name))) out.push_back(dir + "/" + name);
    }
    ::closedir(d);
    std::sort(out.begin(), out.end());
    return out;
}

Result<std::unique_ptr<FrameReader>> openImageReader(const SourceSpec& spec,
                                                     std::vector<std::string> files, double fps) {
    auto first = loadImage(files[0]);
    if (!first) return first.error();
    return std::unique_ptr<FrameReader>(std::make_unique<ImageListReader>(
        std::move(files), spec.text, spec.target, fps, std::move(*first)));
}

Result<std::unique_ptr<FrameSource>> openImages(const SourceSpec& spec,
                                                std::vector<std::string> files) {
    auto options = parsePlaybackOptions(spec);
    if (!options) return options.error();
    auto first = loadImage(files[0]);
    if (!first) return first.error();
    const double fps = options->fps > 0 ? options->fps : 30.0;
    return makePlayback(std::make_unique<ImageListReader>(std::move(files), spec.text, spec.target,
                                                          fps, std::move(*first)),
                        *options);
}

}  // namespace infocus::replay

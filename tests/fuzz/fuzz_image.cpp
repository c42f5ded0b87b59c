// SPDX-License-Identifier: MIT
// MJPEG and image decoding. The first byte chooses the path: 0 an MJPEG frame through the luma
// converter (libturbojpeg), its claimed size in the next four bytes; 1 a .jpg file through the
// image source; 2 the decoder module's OpenCV decoding of any image format.
#include <turbojpeg.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "infocus/luma.h"
#include "infocus/source.h"
#include "replay/decoders/decoders.h"
#include "tests/fuzz/fuzz.h"

namespace infocus::fuzz {

namespace {

std::vector<uint8_t> jpeg(int w, int h, int pixelFormat, int subsamp) {
    std::vector<uint8_t> pixels(static_cast<size_t>(w * h * tjPixelSize[pixelFormat]));
    for (size_t i = 0; i < pixels.size(); ++i)
        pixels[i] = static_cast<uint8_t>(i * 13);
    tjhandle tj = tjInitCompress();
    unsigned char* buf = nullptr;
    unsigned long n = 0;
    std::vector<uint8_t> out;
    if (tjCompress2(tj, pixels.data(), w, 0, h, pixelFormat, &buf, &n, subsamp, 90, 0) == 0)
        out.assign(buf, buf + n);
    tjFree(buf);
    tjDestroy(tj);
    return out;
}

std::vector<uint8_t> encoded(const std::string& ext, int type) {
    cv::Mat m(6, 10, type);
    cv::randu(m, 0, 255);
    std::vector<uint8_t> out;
    cv::imencode(ext, m, out);
    return out;
}

std::vector<uint8_t> tagged(uint8_t mode, const std::vector<uint8_t>& bytes, int w = 0, int h = 0) {
    const ptrdiff_t head = mode == 0 ? 5 : 1;
    std::vector<uint8_t> out(static_cast<size_t>(head) + bytes.size(), 0);
    out[0] = mode;
    if (mode == 0) {
        out[1] = static_cast<uint8_t>(w);
        out[3] = static_cast<uint8_t>(h);
    }
    std::copy(bytes.begin(), bytes.end(), out.begin() + head);
    return out;
}

}  // namespace

std::vector<std::vector<uint8_t>> seeds() {
    const auto grey = jpeg(16, 8, TJPF_GRAY, TJSAMP_GRAY);
    const auto colour = jpeg(17, 9, TJPF_RGB, TJSAMP_420);
    return {tagged(0, grey, 16, 8),
            tagged(0, colour, 17, 9),
            tagged(1, grey),
            tagged(1, colour),
            tagged(2, encoded(".png", CV_8UC1)),
            tagged(2, encoded(".png", CV_16UC3)),
            tagged(2, encoded(".bmp", CV_8UC3)),
            tagged(2, encoded(".tiff", CV_16UC1)),
            tagged(2, colour)};
}

}  // namespace infocus::fuzz

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace infocus;
    fuzz::Bytes in(data, size);
    switch (in.u8() % 3) {
        case 0: {
            const Size claimed{in.u16(), in.u16()};
            const Frame f = makeCompressedFrame(PixelFormat::MJPEG, claimed, in.data(), in.size());
            (void)toLuma8(f);
            (void)toLuma16(f);
            break;
        }
        case 1: {
            static const std::string path = fuzz::scratchDir() + "/input.jpg";
            fuzz::writeFile(path, in.data(), in.size());
            auto source = openSource(path);
            if (!source || !(*source)->start()) break;
            if (auto frame = (*source)->next()) (void)toLuma8(*frame);
            break;
        }
        default: {
            const std::vector<uint8_t> bytes(in.data(), in.data() + in.size());
            if (auto frame = replay::decodeImage(bytes, "input")) (void)toLuma8(*frame);
        }
    }
    return 0;
}

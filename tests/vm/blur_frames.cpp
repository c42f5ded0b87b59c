// SPDX-License-Identifier: MIT
// Writes frames of known blur as raw YUYV, for the VM tier's V4L2 loopback: the frames go into
// vivid's output node and must come back out of its capture node with their blur intact.
// Usage: infocus_vm_blur_frames [--y4m] OUT_PREFIX NAME...
//   NAME is "sharp", "g<σ>" (Gaussian of σ px) or "d<d>" (uniform disc of diameter d px);
//   writes OUT_PREFIX<NAME>.yuyv (720x480 YUYV), and with --y4m the same luma as
//   OUT_PREFIX<NAME>.y4m (one grey frame), for the host's reading of the very same pixels.
//   "probe" writes a pixel pattern instead (impulses, one-pixel checker, ramp) to compare the
//   captured frame with byte by byte.
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "infocus/synth.h"

namespace {

using infocus::synth::Psf;

// vivid's S-Video loopback runs at NTSC size.
constexpr int kWidth = 720;
constexpr int kHeight = 480;
// One dark square on a light ground per region of the 3x2 grid the VM analyses: four straight
// edges a region, each 140 px long, at least 50 px from the region's border and 40 px from the
// next edge, so that a 4.5 σ + 3.5 px ESF patch of σ 4 px sees one edge and two plateaus.
constexpr int kCell = 240;
constexpr double kSidePx = 140.0;
// Slants between 4° and 14°: slanted enough for the ESF's sub-pixel sampling, none aligned.
constexpr double kAngleDeg[6] = {5.0, 8.0, 11.0, 4.0, 14.0, 7.0};
// Levels well inside video range (16–235), so the frames need no clipping on either side.
constexpr float kDark = 40.0f;
constexpr float kBright = 215.0f;
constexpr int kSupersample = 8;

// The frame for @p psf: each cell's square rendered exactly (synth::renderSquare: the blurred
// square's area average over each pixel, no resampling), then pasted.
std::vector<uint8_t> renderFrame(const Psf& psf) {
    std::vector<uint8_t> luma(size_t(kWidth) * kHeight);
    const infocus::synth::Imaging imaging{psf, kSupersample, 0.0, 1};
    for (int cy = 0; cy < kHeight / kCell; ++cy)
        for (int cx = 0; cx < kWidth / kCell; ++cx) {
            const infocus::synth::Square square{
                kCell / 2.0, kCell / 2.0, kSidePx, kAngleDeg[cy * 3 + cx], kDark, kBright};
            const auto img = infocus::synth::toLuma8(
                infocus::synth::renderSquare(kCell, kCell, square, imaging).pixels);
            for (int y = 0; y < kCell; ++y)
                for (int x = 0; x < kCell; ++x)
                    luma[size_t(cy * kCell + y) * kWidth + cx * kCell + x] = img.at(x, y);
        }
    return luma;
}

// A pattern whose every pixel is known, to compare the looped frame with: impulses of 235 on 16
// (top third), a one-pixel checker 16/235 (middle third), a horizontal ramp 0..255 repeated
// (bottom third). Chroma varies too (column index), so a chroma filter would show.
std::vector<uint8_t> probeFrame() {
    std::vector<uint8_t> luma(size_t(kWidth) * kHeight);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            uint8_t v;
            if (y < kHeight / 3)
                v = (x % 7 == 3 && y % 7 == 3) ? 235 : 16;
            else if (y < 2 * kHeight / 3)
                v = ((x + y) % 2) ? 235 : 16;
            else
                v = uint8_t(x % 256);
            luma[size_t(y) * kWidth + x] = v;
        }
    return luma;
}

bool write(const std::string& path, const std::vector<uint8_t>& bytes, const std::string& head) {
    std::ofstream out(path, std::ios::binary);
    out << head;
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return bool(out);
}

}  // namespace

int main(int argc, char** argv) {
    int first = 1;
    const bool y4m = argc > 1 && std::string(argv[1]) == "--y4m";
    if (y4m) ++first;
    if (argc < first + 2) {
        std::fprintf(stderr, "usage: %s [--y4m] OUT_PREFIX sharp|g<sigma>|d<diameter>|probe...\n",
                     argv[0]);
        return 2;
    }
    const std::string prefix = argv[first];
    for (int i = first + 1; i < argc; ++i) {
        const std::string name = argv[i];
        std::vector<uint8_t> luma;
        const bool probe = name == "probe";
        if (probe)
            luma = probeFrame();
        else if (name == "sharp")
            luma = renderFrame(Psf::gaussian(0.0));
        else if (name.size() > 1 && (name[0] == 'g' || name[0] == 'd')) {
            const double size = std::atof(name.c_str() + 1);
            luma = renderFrame(name[0] == 'g' ? Psf::gaussian(size) : Psf::disc(size));
        } else {
            std::fprintf(stderr, "unknown frame %s (sharp, g<sigma>, d<diameter>, probe)\n",
                         name.c_str());
            return 2;
        }
        std::vector<uint8_t> yuyv(luma.size() * 2);
        for (size_t p = 0; p < luma.size(); ++p) {
            yuyv[p * 2] = luma[p];
            // Neutral chroma for the blur frames; the probe's chroma follows the column.
            yuyv[p * 2 + 1] = probe ? uint8_t(16 + (p % kWidth) % 224) : 128;
        }
        if (!write(prefix + name + ".yuyv", yuyv, "")) return 1;
        if (y4m && !write(prefix + name + ".y4m", luma,
                          "YUV4MPEG2 W" + std::to_string(kWidth) + " H" + std::to_string(kHeight) +
                              " F30:1 Ip A1:1 Cmono\nFRAME\n"))
            return 1;
    }
    return 0;
}

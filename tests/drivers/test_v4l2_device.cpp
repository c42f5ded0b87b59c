// SPDX-License-Identifier: MIT
// Streams from every V4L2 capture node present: capabilities, mode, frames, timestamps, sequence
// numbers and luma. Exits 77 (skipped) where the machine has no capture node; the VM tier
// (tests/vm/run.sh) runs it against vivid.
#include <cstdio>
#include <string>

#include "infocus/devices.h"
#include "infocus/luma.h"
#include "infocus/source.h"

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok" : "FAIL", what.c_str());
    if (!ok) ++failures;
}

}  // namespace

int main() {
    auto devices = infocus::listDevices();
    if (!devices) {
        std::printf("FAIL: listing devices: %s\n", devices.error().message.c_str());
        return 1;
    }
    int tested = 0;
    for (const auto& d : *devices) {
        // Media-controller nodes stream only through a configured pipeline (libcamera's job).
        if (d.backend != "v4l2" || d.mediaController) continue;
        ++tested;
        check(!d.driver.empty() && !d.card.empty(), d.device + " reports driver and card");
        check(!d.formats.empty(), d.device + " enumerates formats");
        auto source = infocus::openSource(d.sourceString);
        if (!source) {
            check(false, d.device + " opens: " + source.error().message);
            continue;
        }
        auto& s = **source;
        const auto info = s.info();
        check(infocus::isSupported(info.format) && info.size.width > 0,
              d.device + " mode " + infocus::pixelFormatName(info.format) + " " +
                  std::to_string(info.size.width) + "x" + std::to_string(info.size.height));
        if (auto st = s.start(); !st) {
            check(false, d.device + " starts: " + st.error().message);
            continue;
        }
        infocus::LumaConverter luma;
        int64_t lastTs = 0;
        uint64_t lastSeq = 0;
        bool ordered = true;
        int frames = 0;
        // Hold every frame for a while: more than the driver's buffers, so the copy path runs too.
        std::vector<infocus::Frame> held;
        for (int i = 0; i < 8; ++i) {
            auto f = s.next();
            if (!f) {
                check(false, d.device + " frame " + std::to_string(i) + ": " + f.error().message);
                break;
            }
            if (i > 0 && (f->timestampNs <= lastTs || f->sequence <= lastSeq)) ordered = false;
            lastTs = f->timestampNs;
            lastSeq = f->sequence;
            auto y = luma.toLuma8(*f);
            if (!y) check(false, d.device + " luma: " + y.error().message);
            held.push_back(*f);
            ++frames;
        }
        check(frames == 8, d.device + " delivers 8 frames");
        check(ordered, d.device + " timestamps and sequence numbers increase");
        check(s.stats().delivered == 8, d.device + " counts delivered frames");
        s.stop();
        s.stop();  // twice is allowed
    }
    if (tested == 0) {
        std::printf("no V4L2 capture node: skipped\n");
        return 77;
    }
    return failures ? 1 : 0;
}
